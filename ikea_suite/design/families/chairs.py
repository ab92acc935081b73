"""Chairs: four legs under a seat with a backrest (flat, framed with an opening, or curved),
and armchairs whose two side frames are legs and armrests in one.

Every chair part is solid wood (docs/physics.md: "dining chair, solid wood"); painted
ones are pine (construction.solid_wood)."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes
from ikea_suite.design.families import tables

GAP = 0.003


def _seat_and_legs(furniture, seat_width, seat_depth, seat_height, seat_thickness, leg_side,
                   material, round_legs):
  leg_length = seat_height - seat_thickness
  seat = furniture.add_part("seat", (0, 0, seat_height - seat_thickness / 2), geoms=part_geoms.board(
      furniture, (seat_width, seat_depth, seat_thickness), material, cons.solid_wood(material)))
  dx, dy = seat_width / 2 - leg_side / 2, seat_depth / 2 - leg_side / 2
  legs = tables.leg_geoms(furniture, leg_side, leg_length, material, round_legs,
                          cons.solid_wood(material))
  for i, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
    leg = furniture.add_part(f"leg{i}", (sx * dx, sy * dy, leg_length / 2), geoms=legs)
    furniture.connect(leg, seat, (sx * dx, sy * dy, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="seat_leg_slot",
                      twists_deg=() if round_legs else tables.SQUARE_TWISTS)
  return seat


def back_chair(name, variant, seat_width=0.42, seat_depth=0.42, seat_height=0.45,
               seat_thickness=0.03, leg_side=0.035, back_height=0.40, back_thickness=0.02,
               back="board", material="wood_medium", round_legs=False):
  """Four legs under a seat and a backrest standing on the seat's rear edge.

  `back` is "board" (a flat board), "frame" (a frame with an opening) or
  "curved" (a board bent towards the rear); the last two are concave and
  collide through coacd pieces.
  """
  family = {"board": "back", "frame": "frame_back", "curved": "curved_back"}[back]
  furniture = bp.Blueprint(name, "chair", family, variant,
                           f"chair with a {back} backrest, seat at {seat_height:.2f} m")
  seat = _seat_and_legs(furniture, seat_width, seat_depth, seat_height, seat_thickness, leg_side,
                        material, round_legs)
  wood = cons.solid_wood(material)
  if back == "board":
    geoms = part_geoms.board(furniture, (seat_width, back_thickness, back_height), material, wood)
    back_depth = back_thickness
  elif back == "frame":
    mesh = shapes.frame(seat_width, back_height, back_thickness, 0.05)
    geoms = part_geoms.concave(furniture, mesh, "chair_frame", material, wood)
    back_depth = back_thickness
  else:
    sagitta = 0.05
    mesh = shapes.curved_board(seat_width, sagitta, back_height, back_thickness)
    geoms = part_geoms.concave(furniture, mesh, "chair_curve", material, wood,
                               rot=bp.rot_z(np.pi))
    back_depth = sagitta + back_thickness
  back_y = -seat_depth / 2 + back_depth / 2
  part = furniture.add_part("back", (0, back_y, seat_height + back_height / 2), geoms=geoms)
  furniture.connect(seat, part, (0, back_y, seat_height), up=(0, 0, 1), forward=(1, 0, 0),
                    type_a="seat_back_slot", type_b="back_bottom", twists_deg=(0,))
  return furniture


def armchair(name, variant, width=0.62, depth=0.62, seat_height=0.42, arm_height=0.62,
             frame_thickness=0.04, border=0.06, seat_thickness=0.03, back_height=0.40,
             material="birch", seat_material=None):
  """Two side frames (legs and armrest in one, an opening in the middle), a seat between them
  and a backrest board on the seat. The side frames are one part turned half a turn."""
  furniture = bp.Blueprint(name, "chair", "armrest", variant,
                           f"armchair, {width:.2f} m wide, seat at {seat_height:.2f} m")
  mesh = shapes.frame(depth, arm_height, frame_thickness, border, plane="yz")
  frame_geoms = part_geoms.concave(furniture, mesh, "arm_frame", material, cons.solid_wood(material))
  seat_finish = seat_material or material
  inner = width - 2 * frame_thickness
  frames = [furniture.add_part(f"side{i}", (sx * (width / 2 - frame_thickness / 2), 0, arm_height / 2),
                               rot=bp.rot_z(0 if i == 0 else np.pi), geoms=frame_geoms)
            for i, sx in enumerate((-1, 1))]
  z = seat_height - seat_thickness / 2
  seat_depth = depth - 0.04
  seat = furniture.add_part("seat", (0, 0, z), geoms=part_geoms.board(
      furniture, (inner - 2 * GAP, seat_depth, seat_thickness), seat_finish,
      cons.solid_wood(seat_finish)))
  for side, sx in zip(frames, (-1, 1)):
    furniture.connect(seat, side, (sx * inner / 2, 0, z), up=(sx, 0, 0), forward=(0, 0, 1),
                      type_a="seat_end", type_b="frame_seat_slot", twists_deg=(0, 180))
  back_t = 0.02
  back_y = seat_depth / 2 - back_t / 2
  back = furniture.add_part("back", (0, back_y, seat_height + back_height / 2),
                            geoms=part_geoms.board(furniture, (inner - 2 * GAP, back_t, back_height),
                                                   seat_finish, cons.solid_wood(seat_finish)))
  furniture.connect(seat, back, (0, back_y, seat_height), up=(0, 0, 1), forward=(1, 0, 0),
                    type_a="seat_back_slot", type_b="back_bottom", twists_deg=(0,))
  return furniture


def variants():
  backs = [("ivar", {}),
           ("pine_high", dict(back_height=0.5, material="wood_light")),
           ("white_round", dict(material="white_laminate", round_legs=True)),
           ("black_wide", dict(seat_width=0.48, seat_depth=0.46, material="black_laminate")),
           ("kids_birch", dict(seat_width=0.32, seat_depth=0.32, seat_height=0.33,
                               back_height=0.3, leg_side=0.03, material="birch")),
           ("dark_bar", dict(seat_height=0.65, seat_width=0.4, seat_depth=0.4, back_height=0.3,
                             material="wood_dark", round_legs=True))]
  out = [back_chair(f"chair_back_{v}", v, **kw) for v, kw in backs]
  frames = [("oak", {}), ("white", dict(material="white_laminate")),
            ("black_tall", dict(back_height=0.5, material="black_laminate", round_legs=True))]
  out += [back_chair(f"chair_frame_back_{v}", v, back="frame", **kw) for v, kw in frames]
  curves = [("birch", dict(material="birch")), ("dark", dict(material="wood_dark")),
            ("white_round", dict(material="white_laminate", round_legs=True))]
  out += [back_chair(f"chair_curved_back_{v}", v, back="curved", **kw) for v, kw in curves]
  arms = [("birch", {}), ("oak_wide", dict(width=0.7, material="wood_medium")),
          ("black_low", dict(seat_height=0.38, arm_height=0.56, material="black_laminate",
                             seat_material="wood_light")),
          ("white", dict(material="white_laminate", seat_material="birch"))]
  out += [armchair(f"chair_armrest_{v}", v, **kw) for v, kw in arms]
  return out
