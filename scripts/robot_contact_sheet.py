"""Writes a contact sheet of each robot's cameras: one column per robot, one row per camera.

    MUJOCO_GL=egl python scripts/robot_contact_sheet.py --out docs/cameras_84px.png --zoom 3
    MUJOCO_GL=egl python scripts/robot_contact_sheet.py --robots sawyer panda jaco baxter \\
        --cameras front side --size 240 320 --out docs/robots_work_area.png

Each cell is the first observation of `ikea_suite.load(furniture, robot, seed=...,
cameras=..., image_size=...)` at the robot's work scale (load's default): the robot at
home with the furniture's parts laid out, as an agent sees them. By default each robot
shows the arena's front camera (framed on its work area, tasks/framing.py) and its own
cameras (an arm's wrist cameras; the Cursor, which has none, the top camera), at 84 px,
the size pixel policies are trained at. `--zoom` enlarges each pixel to a square of that
many, so the sheet shows exactly what the policy sees, only larger.
"""

import argparse
import os
import sys

os.environ.setdefault("MUJOCO_GL", "egl")   # headless by default; must precede dm_control

import numpy as np  # pylint: disable=g-import-not-at-top

import ikea_suite  # pylint: disable=g-import-not-at-top

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from randomized_contact_sheet import write_png  # pylint: disable=g-import-not-at-top,wrong-import-position

BORDER = 2   # px of white around each cell


def robot_cameras(robot, furniture):
  """The cameras a robot's column shows by default: front, then the robot's own (the
  top camera for a robot without any)."""
  env = ikea_suite.load(furniture, robot, seed=0)
  own = tuple(env.task.robot.cameras)
  env.close()
  return ("front",) + (own or ("top",))


def render_robot(robot, furniture, cameras, size, seed):
  """The robot's first observation from each of `cameras`: a list of (h, w, 3) images."""
  env = ikea_suite.load(furniture, robot, seed=seed, cameras=cameras, image_size=size)
  observation = env.reset().observation
  images = [observation[f"cameras/{c}_rgb"] for c in cameras]
  env.close()
  return images


def sheet(columns, size, zoom):
  """The contact sheet of `columns` (lists of images, top first), short ones padded."""
  rows = max(len(c) for c in columns)
  blank = np.full((*size, 3), 255, dtype=np.uint8)
  cells = []
  for images in columns:
    images = list(images) + [blank] * (rows - len(images))
    cells.append(np.concatenate(
        [np.pad(np.kron(image, np.ones((zoom, zoom, 1), dtype=np.uint8)),
                ((BORDER, BORDER), (BORDER, BORDER), (0, 0)), constant_values=255)
         for image in images], axis=0))
  return np.concatenate(cells, axis=1)


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--robots", nargs="+", default=ikea_suite.robot_names())
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--cameras", nargs="+", default=None,
                      help="the same cameras for every robot (default: front and its own)")
  parser.add_argument("--size", type=int, nargs=2, default=(84, 84), metavar=("H", "W"))
  parser.add_argument("--zoom", type=int, default=1, help="pixels per image pixel, per side")
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--out", default="docs/cameras_84px.png")
  args = parser.parse_args()
  size = tuple(args.size)
  columns, captions = [], []
  for robot in args.robots:
    cameras = tuple(args.cameras) if args.cameras else robot_cameras(robot, args.furniture)
    columns.append(render_robot(robot, args.furniture, cameras, size, args.seed))
    captions.append(f"{robot}: {', '.join(cameras)}")
  write_png(args.out, sheet(columns, size, args.zoom))
  print(f"wrote {args.out}: {size[0]}x{size[1]} px images, columns (cameras top to bottom): "
        f"{'; '.join(captions)}")


if __name__ == "__main__":
  main()
