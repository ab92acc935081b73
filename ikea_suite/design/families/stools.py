"""Stools: round seats on round legs, square seats on square legs, two-step step stools and
pedestal stools.

Wooden stool parts are solid wood (painted ones pine, construction.solid_wood);
metal legs are steel tube; a pedestal is a steel tube on a steel-plate foot under a
particleboard seat (birch plywood for a birch one)."""

import math

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design.families import tables

GAP = 0.003


def round_stool(name, variant, legs=3, seat_radius=0.17, seat_thickness=0.03, height=0.45,
                leg_radius=0.018, leg_circle=0.12, material="birch", leg_material=None):
  """A disc seat on `legs` cylindrical legs; a round leg fits its socket at any twist."""
  furniture = bp.Blueprint(name, "stool", "round", variant,
                           f"round stool, {legs} legs, {height:.2f} m high")
  leg_length = height - seat_thickness
  seat = furniture.add_part("seat", (0, 0, height - seat_thickness / 2), geoms=part_geoms.cylinder(
      seat_radius, seat_thickness, material, cons.solid_wood(material)))
  leg_finish = leg_material or material
  leg_geoms = part_geoms.round_leg(furniture, leg_radius, leg_length, leg_finish,
                                   cons.leg(leg_finish))
  for i in range(legs):
    angle = 2 * math.pi * i / legs
    x, y = leg_circle * math.cos(angle), leg_circle * math.sin(angle)
    leg = furniture.add_part(f"leg{i}", (x, y, leg_length / 2), geoms=leg_geoms)
    furniture.connect(leg, seat, (x, y, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="seat_leg_socket", twists_deg=())
  return furniture


def square_stool(name, variant, side=0.36, height=0.45, seat_thickness=0.03, leg_side=0.035,
                 material="wood_light"):
  furniture = tables.four_leg_table(name, variant, side, side, height, seat_thickness, leg_side,
                                    material=material, top=cons.solid_wood(material))
  furniture.category, furniture.family = "stool", "square"
  furniture.description = f"square stool, {side:.2f} m seat, {height:.2f} m high"
  return furniture


def step_stool(name, variant, width=0.43, depth=0.40, height=0.50, board=0.018,
               material="birch"):
  """Two side panels and two treads: a low one at the front, a high one at the back."""
  furniture = bp.Blueprint(name, "stool", "step", variant,
                           f"two-step stool, {height:.2f} m high")
  inner = width - 2 * board
  wood = cons.solid_wood(material)
  sides = [furniture.add_part(f"side{i}", (sx * (width / 2 - board / 2), 0, height / 2),
                              geoms=part_geoms.board(furniture, (board, depth, height), material,
                                                     wood))
           for i, sx in enumerate((-1, 1))]
  tread_depth = depth / 2 - GAP
  for k, (y, z) in enumerate(((-depth / 4, height / 2 - board / 2),
                              (depth / 4, height - board / 2))):
    tread = furniture.add_part(f"tread{k}", (0, y, z), geoms=part_geoms.board(
        furniture, (inner - 2 * GAP, tread_depth, board), material, wood))
    for side, sx in zip(sides, (-1, 1)):
      furniture.connect(tread, side, (sx * inner / 2, y, z), up=(sx, 0, 0), forward=(0, 0, 1),
                        type_a="tread_end", type_b="side_tread_slot", twists_deg=(0, 180))
  return furniture


def pedestal_stool(name, variant, seat_radius=0.18, height=0.46, seat_thickness=0.03,
                   base_radius=0.16, column_radius=0.03, material="white_laminate",
                   base_material="metal"):
  """Two parts: a seat that turns onto a pedestal (a foot disc and column in one part)."""
  furniture = bp.Blueprint(name, "stool", "pedestal", variant,
                           f"pedestal stool, {height:.2f} m high")
  column = height - seat_thickness - 0.02
  metal = base_material == "metal"
  pedestal = furniture.add_part("pedestal", (0, 0, 0.01), geoms=part_geoms.cylinder(
      base_radius, 0.02, base_material,
      cons.STEEL_PLATE if metal else cons.solid_wood(base_material)) + part_geoms.round_leg(
          furniture, column_radius, column, base_material, cons.leg(base_material),
          pos=(0, 0, 0.01 + column / 2)))
  seat = furniture.add_part("seat", (0, 0, height - seat_thickness / 2), geoms=part_geoms.cylinder(
      seat_radius, seat_thickness, material,
      cons.BIRCH if material == "birch" else cons.PARTICLEBOARD))
  furniture.connect(pedestal, seat, (0, 0, height - seat_thickness), up=(0, 0, 1),
                    forward=(1, 0, 0), type_a="pedestal_top", type_b="seat_socket", twists_deg=())
  return furniture


def variants():
  rounds = [("frosta", {}),
            ("four_leg", dict(legs=4, seat_radius=0.18, leg_circle=0.13)),
            ("bar_birch", dict(height=0.74, seat_radius=0.18, leg_circle=0.14, leg_radius=0.02)),
            ("low_white", dict(height=0.35, material="white_laminate", leg_material="birch")),
            ("black_metal", dict(legs=4, material="black_laminate", leg_material="metal",
                                 leg_radius=0.013))]
  out = [round_stool(f"stool_round_{v}", v, **kw) for v, kw in rounds]
  squares = [("pine", {}), ("white_tall", dict(height=0.63, material="white_laminate")),
             ("dark_low", dict(side=0.32, height=0.4, material="wood_dark"))]
  out += [square_stool(f"stool_square_{v}", v, **kw) for v, kw in squares]
  steps = [("birch", {}), ("white", dict(material="white_laminate", width=0.4)),
           ("tall_oak", dict(height=0.6, depth=0.46, material="wood_medium"))]
  out += [step_stool(f"stool_step_{v}", v, **kw) for v, kw in steps]
  pedestals = [("white", {}), ("birch_bar", dict(height=0.7, material="birch", base_radius=0.2))]
  out += [pedestal_stool(f"stool_pedestal_{v}", v, **kw) for v, kw in pedestals]
  return out
