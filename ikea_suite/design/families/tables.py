"""Tables: a top on four legs (dimensions follow small flat-pack side tables)."""

import numpy as np

from ikea_suite.design import blueprint as bp

SQUARE_TWISTS = (0, 90, 180, 270)


def four_leg_table(name, variant, width=0.55, depth=0.55, height=0.45, top_thickness=0.05,
                   leg_side=0.05, inset=0.0, material="wood_light", leg_material=None):
  """A rectangular top on four square legs screwed into its underside."""
  furniture = bp.Blueprint(name, "table", "four_leg", variant,
                           f"{width:.2f} x {depth:.2f} m table, {height:.2f} m high, four legs")
  leg_length = height - top_thickness
  top = furniture.add_part("top", (0, 0, height - top_thickness / 2), geoms=[
      bp.Geom("box", (width / 2, depth / 2, top_thickness / 2), material=material)])
  dx = width / 2 - leg_side / 2 - inset
  dy = depth / 2 - leg_side / 2 - inset
  for i, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
    leg = furniture.add_part(f"leg{i}", (sx * dx, sy * dy, leg_length / 2), geoms=[
        bp.Geom("box", (leg_side / 2, leg_side / 2, leg_length / 2),
                material=leg_material or material)])
    furniture.connect(leg, top, (sx * dx, sy * dy, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="top_leg_slot", twists_deg=SQUARE_TWISTS)
  return furniture


def variants():
  return [four_leg_table("table_four_leg_lack", "lack")]
