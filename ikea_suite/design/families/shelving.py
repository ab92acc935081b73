"""Shelving: shelves clamped between two metal ladders (round posts joined by rungs).

Posts and rungs are hollow steel tube; shelves are a sheet-steel tray, or a
board (`shelf`: solid pine, particleboard) where the variant says so."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms

GAP = 0.003


def post_shelving(name, variant, width=0.8, depth=0.4, height=1.5, shelves=4, post_radius=0.0125,
                  shelf_thickness=0.02, material="metal", shelf_material="metal",
                  shelf=cons.STEEL_SHEET):
  """Two identical side ladders (two round posts joined by a rung at the foot and the top)
  with identical shelves clamped between them; each ladder is one part."""
  furniture = bp.Blueprint(name, "shelving", "posts", variant,
                           f"{width:.2f} m post shelving, {shelves} shelves, {height:.2f} m high")
  r = post_radius
  py = depth / 2 - r
  rung = 0.03
  ladder = []
  for sy in (-1, 1):
    ladder += part_geoms.round_leg(furniture, r, height, material, cons.STEEL_TUBE,
                                   pos=(0, sy * py, 0))
  for sz in (-1, 1):
    ladder += part_geoms.box((2 * r, 2 * py, rung), material, cons.STEEL_TUBE,
                             pos=(0, 0, sz * (height / 2 - rung / 2)))
  side_x = width / 2 + r + GAP
  sides = [furniture.add_part(f"ladder{i}", (sx * side_x, 0, height / 2),
                              rot=bp.rot_z(0 if i == 0 else np.pi), geoms=ladder)
           for i, sx in enumerate((-1, 1))]
  levels = np.linspace(rung + 0.06, height - rung - 0.06, shelves)
  shelf_geoms = part_geoms.board(furniture, (width, depth, shelf_thickness), shelf_material, shelf)
  for k, z in enumerate(levels):
    shelf = furniture.add_part(f"shelf{k}", (0, 0, z), geoms=shelf_geoms)
    for side, sx in zip(sides, (-1, 1)):
      furniture.connect(shelf, side, (sx * width / 2, 0, z), up=(sx, 0, 0), forward=(0, 0, 1),
                        type_a="shelf_end", type_b="ladder_clamp", twists_deg=(0, 180))
  return furniture


def variants():
  posts = [("steel", dict(shelf_material="wood_light", shelf=cons.PINE)),
           ("steel_tall", dict(height=1.8, shelves=5)),
           ("steel_wide", dict(width=1.0, depth=0.5, shelves=4)),
           ("birch_shelves", dict(shelves=3, height=1.2, shelf_material="birch",
                                  shelf=cons.PARTICLEBOARD)),
           ("white_low", dict(width=0.6, depth=0.35, height=0.9, shelves=3,
                              shelf_material="white_laminate", shelf=cons.PARTICLEBOARD)),
           ("black_six", dict(height=1.9, shelves=6, shelf_material="black_laminate",
                              shelf=cons.PARTICLEBOARD))]
  out = [post_shelving(f"shelving_posts_{v}", v, **kw) for v, kw in posts]
  return out
