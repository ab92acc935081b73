"""Writes a contact sheet of randomized scenes: one column per scene preset, one row per seed.

    MUJOCO_GL=egl python scripts/randomized_contact_sheet.py --out contact_sheet.png

Each cell is the first observation of `ikea_suite.load(furniture, "cursor",
seed=seed, scene=preset, randomize=...)` seen by one camera, so the sheet
shows exactly what an agent would see. Pure numpy PNG output, no imaging library.
"""

import argparse
import os
import struct
import zlib

os.environ.setdefault("MUJOCO_GL", "egl")   # headless by default; must precede dm_control

import numpy as np  # pylint: disable=g-import-not-at-top

import ikea_suite  # pylint: disable=g-import-not-at-top
from ikea_suite.arenas import presets  # pylint: disable=g-import-not-at-top


def write_png(path, image):
  """Writes an (h, w, 3) uint8 array as an RGB PNG."""
  image = np.ascontiguousarray(image, dtype=np.uint8)
  height, width = image.shape[:2]
  rows = b"".join(b"\x00" + image[r].tobytes() for r in range(height))   # filter 0 per row

  def chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

  header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)   # 8-bit RGB
  with open(path, "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 6))
            + chunk(b"IEND", b""))


def render_cell(furniture, scene, seed, randomize, camera, size, preassembled):
  env = ikea_suite.load(furniture, "cursor", seed=seed, scene=scene, randomize=randomize,
                        cameras=(camera,), image_size=size, preassembled=preassembled)
  image = env.reset().observation[f"cameras/{camera}_rgb"]
  env.close()
  return image


def contact_sheet(furniture, scenes, seeds, randomize, camera, size, preassembled, border=2):
  rows = []
  for seed in seeds:
    cells = [np.pad(render_cell(furniture, scene, seed, randomize, camera, size, preassembled),
                    ((border, border), (border, border), (0, 0)), constant_values=255)
             for scene in scenes]
    rows.append(np.concatenate(cells, axis=1))
  return np.concatenate(rows, axis=0)


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--scenes", nargs="+", default=presets.names(),
                      help="scene presets (columns)")
  parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3], help="seeds (rows)")
  parser.add_argument("--randomize", nargs="*", default=["visual"],
                      help="randomization factors or groups (physics, visual, all); none for off")
  parser.add_argument("--camera", default="front")
  parser.add_argument("--size", type=int, default=160, help="cell size in pixels")
  parser.add_argument("--preassembled", type=int, nargs=2, default=(0, 2),
                      help="range of connections made before the episode starts")
  parser.add_argument("--out", default="contact_sheet.png")
  args = parser.parse_args()
  randomize = None if args.randomize in ([], ["none"]) else args.randomize
  sheet = contact_sheet(args.furniture, args.scenes, args.seeds, randomize, args.camera, args.size,
                        tuple(args.preassembled))
  write_png(args.out, sheet)
  print(f"wrote {args.out}: {len(args.scenes)} scenes x {len(args.seeds)} seeds, "
        f"{sheet.shape[1]}x{sheet.shape[0]} pixels")


if __name__ == "__main__":
  main()
