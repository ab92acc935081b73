"""Writes a contact sheet of every arm at its work area: one cell per robot, two cameras.

    MUJOCO_GL=egl python scripts/robot_contact_sheet.py --out docs/robots_work_area.png

Each cell is the first observation of `ikea_suite.load(furniture, robot,
scale=<robot's WORK_SCALE>, cameras=...)`: the arm at home with the
furniture's parts laid out within its reach, as an agent would see it.
"""

import argparse
import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")   # headless by default; must precede dm_control

import numpy as np  # pylint: disable=g-import-not-at-top

import ikea_suite  # pylint: disable=g-import-not-at-top
from ikea_suite.robots import registry  # pylint: disable=g-import-not-at-top

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from randomized_contact_sheet import write_png  # pylint: disable=g-import-not-at-top,wrong-import-position


def render_robot(robot, furniture, cameras, size, seed):
  scale = registry.get(robot).factory.CONFIG.WORK_SCALE
  env = ikea_suite.load(furniture, robot, seed=seed, scale=scale, cameras=cameras, image_size=size)
  observation = env.reset().observation
  images = [observation[f"cameras/{c}_rgb"] for c in cameras]
  env.close()
  return np.concatenate(images, axis=0)


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--robots", nargs="+", default=registry.names(tag="arm"))
  parser.add_argument("--furniture", default="table_four_leg_lack")
  parser.add_argument("--cameras", nargs="+", default=["front", "side"])
  parser.add_argument("--size", type=int, nargs=2, default=(240, 320))
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--out", default="docs/robots_work_area.png")
  args = parser.parse_args()
  border = 2
  cells = [np.pad(render_robot(r, args.furniture, tuple(args.cameras), tuple(args.size), args.seed),
                  ((border, border), (border, border), (0, 0)), constant_values=255)
           for r in args.robots]
  write_png(args.out, np.concatenate(cells, axis=1))
  print(f"wrote {args.out}: {', '.join(args.robots)} (columns), cameras {', '.join(args.cameras)} (rows)")


if __name__ == "__main__":
  main()
