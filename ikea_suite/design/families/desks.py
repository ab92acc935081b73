"""Desks: a top on two legs and a drawer unit (the side unit), and simple desks on two panels
with a modesty board between them."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design.families import carcass
from ikea_suite.design.families import tables

GAP = 0.003


def side_unit_desk(name, variant, width=1.2, depth=0.6, height=0.74, top_thickness=0.025,
                   unit_width=0.42, drawers=2, leg_side=0.05, material="white_laminate",
                   leg_material="metal", front_material=None):
  """Two round legs under the left end; a drawer unit (carcass without a top) under the right.

  The unit's side panels screw into the top's underside, its drawers hang on
  its left panel. The top is particleboard, the unit a carcass (see carcass),
  legs steel tube or solid wood by their finish.
  """
  furniture = bp.Blueprint(name, "desk", "side_unit", variant,
                           f"{width:.2f} m desk with a {drawers}-drawer side unit")
  top = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=part_geoms.board(
      furniture, (width, depth, top_thickness), material, cons.PARTICLEBOARD))
  unit_height = height - top_thickness
  unit = bp.Blueprint("unit", "", "", "", "")
  board = 0.016
  box = carcass.build(unit, unit_width, depth - 0.04, unit_height, [0.05 + board / 2], board,
                      plinth=0.05, material=material)
  carcass.add_drawers(box, 0.05 + board, unit_height - 0.01, drawers,
                      front_material=front_material or material)
  shift = width / 2 - unit_width / 2 - 0.02
  for part in unit.parts:
    part.name = f"unit_{part.name}"
    part.pos = part.pos + [shift, 0.0, 0.0]
    for c in part.connectors:
      c.name = f"unit_{c.name}"
    furniture.parts.append(part)
  furniture.meshes.update(unit.meshes)
  for side in box.sides:
    x, z = side.pos[0], unit_height
    furniture.connect(side, top, (x, 0, z), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="unit_side_top", type_b="top_unit_slot", twists_deg=(0, 180))
  leg_length = height - top_thickness
  legs = part_geoms.round_leg(furniture, leg_side / 2, leg_length, leg_material,
                              cons.leg(leg_material))
  lx = -width / 2 + 0.06
  for i, sy in enumerate((-1, 1)):
    y = sy * (depth / 2 - 0.06)
    leg = furniture.add_part(f"leg{i}", (lx, y, leg_length / 2), geoms=legs)
    furniture.connect(leg, top, (lx, y, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="top_leg_slot", twists_deg=())
  return furniture


def panel_desk(name, variant, width=1.0, depth=0.5, height=0.74, board=0.025,
               material="birch"):
  """A top on two identical end panels with a modesty board across the back."""
  furniture = tables.trestle_table(name, variant, width, depth, height, board,
                                   material=material)
  furniture.category, furniture.family = "desk", "trestle"
  furniture.description = f"{width:.2f} m desk on two T-shaped trestles"
  return furniture


def variants():
  units = [("w120_white", {}),
           ("w140_oak", dict(width=1.4, depth=0.7, material="wood_medium", drawers=3)),
           ("w100_birch", dict(width=1.0, material="birch", leg_material="birch")),
           ("w120_black", dict(material="black_laminate", front_material="white_laminate")),
           ("w160_dark", dict(width=1.6, depth=0.8, material="wood_dark", drawers=3))]
  out = [side_unit_desk(f"desk_side_unit_{v}", v, **kw) for v, kw in units]
  panels = [("w100_birch", {}), ("w120_white", dict(width=1.2, depth=0.6, material="white_laminate"))]
  out += [panel_desk(f"desk_trestle_{v}", v, **kw) for v, kw in panels]
  return out
