"""Renders every catalog model, assembled, into one contact-sheet PNG (docs/gallery.png).

    MUJOCO_GL=egl python scripts/render_gallery.py [--out docs/gallery.png] [--columns 10]

Tiles run in catalog (name) order, left to right, top to bottom; the README (Furniture catalog)
lists the same order. Plain MuJoCo renders each model file as written: the
furniture stands assembled on its floor, collision geoms hidden.
"""

import argparse
import os
import pathlib
import struct
import sys
import zlib

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from ikea_suite import physics_settings  # noqa: E402
from ikea_suite.props import catalog  # noqa: E402

_BACKGROUND = (246, 246, 244)


def write_png(path, image):
  """Writes an (h, w, 3) uint8 image as a PNG file with zlib (no imaging library needed)."""
  height, width, _ = image.shape
  raw = b"".join(b"\x00" + image[row].tobytes() for row in range(height))
  def chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data
            + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
  pathlib.Path(path).write_bytes(
      b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
      + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def furniture_bounds(model, data):
  """World bounding box of all part geoms (the floor excluded)."""
  mujoco.mj_forward(model, data)
  corners = []
  for g in range(model.ngeom):
    if model.geom_bodyid[g] == 0:
      continue
    centre = data.geom_xpos[g] + data.geom_xmat[g].reshape(3, 3) @ model.geom_aabb[g, :3]
    half = np.abs(data.geom_xmat[g].reshape(3, 3)) @ model.geom_aabb[g, 3:]
    corners += [centre - half, centre + half]
  corners = np.array(corners)
  return corners.min(0), corners.max(0)


def render_tile(path, width, height):
  model = mujoco.MjModel.from_xml_path(str(path))
  physics_settings.configure_model(model)
  data = mujoco.MjData(model)
  lo, hi = furniture_bounds(model, data)
  camera = mujoco.MjvCamera()
  camera.lookat[:] = (lo + hi) / 2
  camera.distance = 1.35 * np.linalg.norm(hi - lo) + 0.15
  camera.azimuth, camera.elevation = 60.0, -24.0   # from the front left (fronts face -y)
  with mujoco.Renderer(model, height, width) as renderer:
    renderer.update_scene(data, camera)
    image = renderer.render()
    renderer.enable_depth_rendering()
    renderer.update_scene(data, camera)
    depth = renderer.render()
  image[depth >= depth.max() - 1e-3] = _BACKGROUND   # empty sky behind the floor
  return image


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("--out", default="docs/gallery.png")
  parser.add_argument("--columns", type=int, default=10)
  parser.add_argument("--tile", type=int, nargs=2, default=(160, 128), metavar=("W", "H"))
  args = parser.parse_args(argv)
  names = catalog.names()
  width, height = args.tile
  rows = -(-len(names) // args.columns)
  sheet = np.full((rows * height, args.columns * width, 3), 255, np.uint8)
  for k, name in enumerate(names):
    r, c = divmod(k, args.columns)
    sheet[r * height:(r + 1) * height, c * width:(c + 1) * width] = render_tile(
        catalog.path_of(name), width, height)
  write_png(args.out, sheet)
  print(f"wrote {args.out}: {len(names)} models, {sheet.shape[1]} x {sheet.shape[0]} px")
  return 0


if __name__ == "__main__":
  sys.exit(main())
