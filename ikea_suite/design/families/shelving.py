"""Shelving: shelves clamped between two metal ladders (round posts joined by rungs), and
board uprights carrying shelves on L brackets."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes

GAP = 0.003


def post_shelving(name, variant, width=0.8, depth=0.4, height=1.5, shelves=4, post_radius=0.0125,
                  shelf_thickness=0.02, material="metal", shelf_material="metal"):
  """Two identical side ladders (two round posts joined by a rung at the foot and the top)
  with identical shelves clamped between them; each ladder is one part."""
  furniture = bp.Blueprint(name, "shelving", "posts", variant,
                           f"{width:.2f} m post shelving, {shelves} shelves, {height:.2f} m high")
  r = post_radius
  py = depth / 2 - r
  rung = 0.03
  ladder = []
  for sy in (-1, 1):
    ladder += part_geoms.round_leg(furniture, r, height, material, pos=(0, sy * py, 0))
  for sz in (-1, 1):
    ladder += part_geoms.box((2 * r, 2 * py, rung), material, pos=(0, 0, sz * (height / 2 - rung / 2)))
  side_x = width / 2 + r + GAP
  sides = [furniture.add_part(f"ladder{i}", (sx * side_x, 0, height / 2),
                              rot=bp.rot_z(0 if i == 0 else np.pi), geoms=ladder)
           for i, sx in enumerate((-1, 1))]
  levels = np.linspace(rung + 0.06, height - rung - 0.06, shelves)
  shelf_geoms = part_geoms.board(furniture, (width, depth, shelf_thickness),
                                 shelf_material)
  for k, z in enumerate(levels):
    shelf = furniture.add_part(f"shelf{k}", (0, 0, z), geoms=shelf_geoms)
    for side, sx in zip(sides, (-1, 1)):
      furniture.connect(shelf, side, (sx * width / 2, 0, z), up=(sx, 0, 0), forward=(0, 0, 1),
                        type_a="shelf_end", type_b="ladder_clamp", twists_deg=(0, 180))
  return furniture


def bracket_shelving(name, variant, width=0.6, depth=0.25, height=1.2, shelves=2, board=0.018,
                     material="wood_light", bracket_material="metal"):
  """Two upright boards; each shelf rests on two L brackets screwed to the uprights' inner faces.

  The uprights are one part turned half a turn, and every bracket is the same
  part: a bracket is concave, so it collides through its coacd pieces.
  """
  furniture = bp.Blueprint(name, "shelving", "brackets", variant,
                           f"{width:.2f} m bracket shelving, {shelves} shelves, {height:.2f} m high")
  inner = width - 2 * board
  uprights = [furniture.add_part(f"upright{i}", (sx * (width / 2 - board / 2), 0, height / 2),
                                 rot=bp.rot_z(0 if i == 0 else np.pi),
                                 geoms=part_geoms.board(furniture, (board, depth, height), material))
              for i, sx in enumerate((-1, 1))]
  leg, flange, thickness = 0.06, 0.05, 0.004
  mesh = shapes.l_bracket(leg, flange, depth - 0.05, thickness)   # leg along +x, flange along +z
  # Turned over so the leg is on top, under the shelf, and the flange hangs below it.
  bracket_geoms = part_geoms.concave(furniture, mesh, "l_bracket", bracket_material,
                                     rot=bp.rot_x(np.pi))
  shelf_width = inner - 2 * GAP
  shelf_geoms = part_geoms.board(furniture, (shelf_width, depth, board), material)
  for k, z in enumerate(np.linspace(0.25, height - 0.1, shelves)):
    shelf = furniture.add_part(f"shelf{k}", (0, 0, z + board / 2), geoms=shelf_geoms)
    for i, (upright, sx) in enumerate(zip(uprights, (-1, 1))):
      # The bracket's flange lies on the upright; its leg carries the shelf from below.
      x = sx * (inner / 2 - leg / 2)
      bracket = furniture.add_part(f"bracket{k}_{i}", (x, 0, z - flange / 2),
                                   rot=bp.rot_z(0 if i == 0 else np.pi), geoms=bracket_geoms)
      furniture.connect(bracket, upright, (sx * inner / 2, 0, z - flange / 2), up=(sx, 0, 0),
                        forward=(0, 0, 1), type_a="bracket_back", type_b="upright_bracket_slot",
                        twists_deg=(0,))
      furniture.connect(shelf, bracket, (x, 0, z), up=(0, 0, -1), forward=bracket.rot[:, 0],
                        type_a="shelf_bottom", type_b="bracket_top", twists_deg=(0, 180))
  return furniture


def variants():
  posts = [("steel", dict(shelf_material="wood_light")),
           ("steel_tall", dict(height=1.8, shelves=5)),
           ("steel_wide", dict(width=1.0, depth=0.5, shelves=4)),
           ("birch_shelves", dict(shelves=3, height=1.2, shelf_material="birch")),
           ("white_low", dict(width=0.6, depth=0.35, height=0.9, shelves=3,
                              shelf_material="white_laminate")),
           ("black_six", dict(height=1.9, shelves=6, shelf_material="black_laminate"))]
  out = [post_shelving(f"shelving_posts_{v}", v, **kw) for v, kw in posts]
  brackets = [("pine", {}), ("white_three", dict(shelves=3, height=1.3, material="white_laminate")),
              ("oak_wide", dict(width=0.8, material="wood_medium"))]
  out += [bracket_shelving(f"shelving_brackets_{v}", v, **kw) for v, kw in brackets]
  return out
