"""Tables: four-leg tables, round tables on a central post, coffee tables with a lower shelf,
and trestle tables on T-shaped legs. Dimensions follow flat-pack side, coffee and dining tables."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes

SQUARE_TWISTS = (0, 90, 180, 270)
GAP = 0.003


def leg_geoms(furniture, leg_side, length, material, round_legs, construction=None):
  """Geoms of a square (side `leg_side`) or round leg `length` m long; solid wood or steel tube
  by its finish (cons.leg) unless `construction` says otherwise."""
  construction = construction or cons.leg(material)
  if round_legs:
    return part_geoms.round_leg(furniture, leg_side / 2, length, material, construction)
  return part_geoms.board(furniture, (leg_side, leg_side, length), material, construction)


def four_leg_table(name, variant, width=0.55, depth=0.55, height=0.45, top_thickness=0.05,
                   leg_side=0.05, inset=0.0, material="wood_light", leg_material=None,
                   round_legs=False, top=cons.PARTICLEBOARD, legs=None):
  """A rectangular top on four legs screwed into its underside; any leg fits any corner.

  `top` and `legs` are constructions; legs default to solid wood or steel tube by
  their finish (cons.leg).
  """
  furniture = bp.Blueprint(name, "table", "four_leg", variant,
                           f"{width:.2f} x {depth:.2f} m table, {height:.2f} m high, four legs")
  leg_length = height - top_thickness
  top_part = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=part_geoms.board(
      furniture, (width, depth, top_thickness), material, top))
  dx = width / 2 - leg_side / 2 - inset
  dy = depth / 2 - leg_side / 2 - inset
  geoms = leg_geoms(furniture, leg_side, leg_length, leg_material or material, round_legs, legs)
  for i, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
    leg = furniture.add_part(f"leg{i}", (sx * dx, sy * dy, leg_length / 2), geoms=geoms)
    furniture.connect(leg, top_part, (sx * dx, sy * dy, leg_length), up=(0, 0, 1),
                      forward=(1, 0, 0), type_a="leg_top", type_b="top_leg_slot",
                      twists_deg=() if round_legs else SQUARE_TWISTS)
  return furniture


def round_post_table(name, variant, diameter=0.6, height=0.72, top_thickness=0.025,
                     post_radius=0.035, base_diameter=0.45, base_thickness=0.025,
                     material="white_laminate", post_material="metal"):
  """A disc top on a central post standing on a round foot; round joints fit at any twist.

  The top is particleboard; a metal post is a steel tube on a steel-plate foot.
  """
  furniture = bp.Blueprint(name, "table", "round_post", variant,
                           f"round table, {diameter:.2f} m across, {height:.2f} m high, central post")
  post_length = height - top_thickness - base_thickness
  metal = post_material == "metal"
  base = furniture.add_part("base", (0, 0, base_thickness / 2), geoms=part_geoms.cylinder(
      base_diameter / 2, base_thickness, post_material,
      cons.STEEL_PLATE if metal else cons.solid_wood(post_material)))
  post = furniture.add_part("post", (0, 0, base_thickness + post_length / 2),
                            geoms=part_geoms.round_leg(furniture, post_radius, post_length,
                                                       post_material, cons.leg(post_material)))
  top = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=part_geoms.cylinder(
      diameter / 2, top_thickness, material, cons.PARTICLEBOARD))
  furniture.connect(post, top, (0, 0, height - top_thickness), up=(0, 0, 1), forward=(1, 0, 0),
                    type_a="post_top", type_b="top_post_socket", twists_deg=())
  furniture.connect(base, post, (0, 0, base_thickness), up=(0, 0, 1), forward=(1, 0, 0),
                    type_a="base_post_socket", type_b="post_bottom", twists_deg=())
  return furniture


def coffee_shelf_table(name, variant, width=0.90, depth=0.55, height=0.45, top_thickness=0.05,
                       leg_side=0.05, shelf_height=0.10, shelf_thickness=0.018,
                       material="wood_light", shelf_material=None):
  """A four-leg coffee table with a lower shelf held between the legs at its corners.

  Built as the Lack coffee table: honeycomb top, hollow fibreboard legs, a
  particleboard shelf.

  The legs are identical: each is the first leg turned a quarter turn per
  corner, so its inner edge, which carries the shelf connector, faces the middle.
  """
  furniture = bp.Blueprint(name, "table", "coffee_shelf", variant,
                           f"{width:.2f} x {depth:.2f} m coffee table with a lower shelf, "
                           f"{height:.2f} m high")
  leg_length = height - top_thickness
  top = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=part_geoms.board(
      furniture, (width, depth, top_thickness), material, cons.HONEYCOMB_BOARD))
  dx, dy = width / 2 - leg_side, depth / 2 - leg_side
  z = shelf_height + shelf_thickness / 2
  shelf = furniture.add_part("shelf", (0, 0, z), geoms=part_geoms.board(
      furniture, (2 * dx - 2 * GAP, 2 * dy - 2 * GAP, shelf_thickness), shelf_material or material,
      cons.PARTICLEBOARD))
  legs = part_geoms.board(furniture, (leg_side, leg_side, leg_length), material,
                          cons.HOLLOW_FIBREBOARD_LEG)
  for i, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
    x, y = sx * (dx + leg_side / 2), sy * (dy + leg_side / 2)
    leg = furniture.add_part(f"leg{i}", (x, y, leg_length / 2), rot=bp.rot_z(np.pi / 2 * i),
                             geoms=legs)
    # No twist: a leg turned the wrong way would put its shelf slot outside.
    furniture.connect(leg, top, (x, y, leg_length), up=(0, 0, 1), forward=leg.rot[:, 0],
                      type_a="leg_top", type_b="top_leg_slot", twists_deg=(0,))
    out = np.array([sx, sy, 0.0]) / np.sqrt(2)
    furniture.connect(shelf, leg, (sx * dx, sy * dy, z), up=out, forward=(0, 0, 1),
                      type_a="shelf_corner", type_b="leg_shelf_slot", twists_deg=(0,))
  return furniture


def trestle_table(name, variant, length=1.4, depth=0.75, height=0.74, top_thickness=0.03,
                  leg_thickness=0.04, stem=0.08, foot=0.06, material="wood_medium",
                  leg_material=None):
  """A top on two T-shaped trestles (concave: coacd pieces) joined by a stretcher.

  The top is particleboard; trestles and stretcher are solid wood of their finish.
  """
  furniture = bp.Blueprint(name, "table", "trestle", variant,
                           f"{length:.2f} x {depth:.2f} m trestle table, {height:.2f} m high")
  leg_height = height - top_thickness
  top = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=part_geoms.board(
      furniture, (length, depth, top_thickness), material, cons.PARTICLEBOARD))
  foot_length = depth - 0.1
  trestle = shapes.extrude_polygon(shapes.t_profile(foot_length, leg_height, stem, foot),
                                   leg_thickness, plane="yz")
  leg_finish = leg_material or material
  trestle_geoms = part_geoms.concave(furniture, trestle, "trestle", leg_finish,
                                     cons.solid_wood(leg_finish))
  leg_x = length / 2 - 0.15
  legs = []
  for i, sx in enumerate((-1, 1)):
    leg = furniture.add_part(f"trestle{i}", (sx * leg_x, 0, leg_height / 2),
                             rot=bp.rot_z(0 if i == 0 else np.pi), geoms=trestle_geoms)
    furniture.connect(leg, top, (sx * leg_x, 0, leg_height), up=(0, 0, 1), forward=leg.rot[:, 0],
                      type_a="trestle_top", type_b="top_trestle_slot", twists_deg=(0, 180))
    legs.append(leg)
  span = 2 * leg_x - leg_thickness - 2 * GAP
  z = foot + 0.15
  stretcher = furniture.add_part("stretcher", (0, 0, z), geoms=part_geoms.board(
      furniture, (span, 0.02, 0.08), leg_finish, cons.solid_wood(leg_finish)))
  for leg, sx in zip(legs, (-1, 1)):
    furniture.connect(stretcher, leg, (sx * (leg_x - leg_thickness / 2), 0, z), up=(sx, 0, 0),
                      forward=(0, 0, 1), type_a="stretcher_end", type_b="trestle_stretcher_slot",
                      twists_deg=(0, 180))
  return furniture


def variants():
  four = [("lack", dict(top=cons.HONEYCOMB_BOARD, legs=cons.HOLLOW_FIBREBOARD_LEG)),
          ("w90_birch", dict(width=0.9, depth=0.6, height=0.74, top_thickness=0.03, leg_side=0.045,
                             material="birch")),
          ("w120_white", dict(width=1.2, depth=0.7, height=0.74, top_thickness=0.03, leg_side=0.05,
                              inset=0.02, material="white_laminate", leg_material="metal",
                              round_legs=True)),
          ("w75_black", dict(width=0.75, depth=0.75, height=0.74, top_thickness=0.025,
                             leg_side=0.04, material="black_laminate", round_legs=True)),
          ("side_oak", dict(width=0.45, depth=0.45, height=0.55, top_thickness=0.03,
                            leg_side=0.04, material="wood_medium", round_legs=True)),
          ("w140_dark", dict(width=1.4, depth=0.8, height=0.75, top_thickness=0.035,
                             leg_side=0.06, inset=0.03, material="wood_dark")),
          ("bar_birch", dict(width=0.6, depth=0.6, height=0.9, top_thickness=0.03, leg_side=0.05,
                             material="birch", leg_material="metal", round_legs=True)),
          ("kids_white", dict(width=0.6, depth=0.5, height=0.48, top_thickness=0.025,
                              leg_side=0.045, material="white_laminate", leg_material="birch"))]
  out = [four_leg_table(f"table_four_leg_{v}", v, **kw) for v, kw in four]
  posts = [("d60_white", {}),
           ("d80_birch", dict(diameter=0.8, material="birch", base_diameter=0.55)),
           ("d50_black", dict(diameter=0.5, height=0.6, material="black_laminate",
                              base_diameter=0.4)),
           ("bistro_oak", dict(diameter=0.7, height=1.0, material="wood_medium", base_diameter=0.5,
                               post_radius=0.03)),
           ("d90_dark", dict(diameter=0.9, material="wood_dark", base_diameter=0.6,
                             post_radius=0.045))]
  out += [round_post_table(f"table_round_post_{v}", v, **kw) for v, kw in posts]
  coffee = [("w90_birch", dict(material="birch")),
            ("w118_black", dict(width=1.18, depth=0.78, height=0.45, material="black_laminate")),
            ("w100_white_oak", dict(width=1.0, depth=0.6, height=0.42, material="white_laminate",
                                    shelf_material="wood_medium")),
            ("square_dark", dict(width=0.78, depth=0.78, height=0.4, material="wood_dark")),
            ("low_light", dict(width=1.2, depth=0.5, height=0.35, leg_side=0.06, shelf_height=0.07))]
  out += [coffee_shelf_table(f"table_coffee_shelf_{v}", v, **kw) for v, kw in coffee]
  trestles = [("l140_oak", {}),
              ("l180_pine", dict(length=1.8, depth=0.85, material="wood_light")),
              ("l120_white", dict(length=1.2, depth=0.7, material="white_laminate",
                                  leg_material="black_laminate")),
              ("l160_dark", dict(length=1.6, depth=0.8, material="wood_dark"))]
  out += [trestle_table(f"table_trestle_{v}", v, **kw) for v, kw in trestles]
  return out
