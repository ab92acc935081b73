"""Chairs: a seat on four legs with a backrest board."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design.families import tables


def back_chair(name, variant, seat_width=0.42, seat_depth=0.42, seat_height=0.45,
               seat_thickness=0.03, leg_side=0.035, back_height=0.40, back_thickness=0.02,
               material="wood_medium"):
  """Four legs under a seat, a backrest board standing on the seat's rear edge."""
  furniture = bp.Blueprint(name, "chair", "back", variant,
                           f"chair with a backrest, seat at {seat_height:.2f} m")
  leg_length = seat_height - seat_thickness
  seat = furniture.add_part("seat", (0, 0, seat_height - seat_thickness / 2), geoms=[
      bp.Geom("box", (seat_width / 2, seat_depth / 2, seat_thickness / 2), material=material)])
  dx, dy = seat_width / 2 - leg_side / 2, seat_depth / 2 - leg_side / 2
  for i, (sx, sy) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
    leg = furniture.add_part(f"leg{i}", (sx * dx, sy * dy, leg_length / 2), geoms=[
        bp.Geom("box", (leg_side / 2, leg_side / 2, leg_length / 2), material=material)])
    furniture.connect(leg, seat, (sx * dx, sy * dy, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="seat_leg_slot", twists_deg=tables.SQUARE_TWISTS)
  back_y = -seat_depth / 2 + back_thickness / 2
  back = furniture.add_part("back", (0, back_y, seat_height + back_height / 2), geoms=[
      bp.Geom("box", (seat_width / 2, back_thickness / 2, back_height / 2), material=material)])
  furniture.connect(seat, back, (0, back_y, seat_height), up=(0, 0, 1), forward=(1, 0, 0),
                    type_a="seat_back_slot", type_b="back_bottom", twists_deg=(0,))
  return furniture


def variants():
  return [back_chair("chair_back_ivar", "ivar")]
