"""Stools: a round seat on round legs."""

import math

from ikea_suite.design import blueprint as bp


def round_stool(name, variant, legs=3, seat_radius=0.17, seat_thickness=0.03, height=0.45,
                leg_radius=0.018, leg_circle=0.12, material="birch"):
  """A disc seat on `legs` cylindrical legs; a round leg fits its socket at any twist."""
  furniture = bp.Blueprint(name, "stool", "round", variant,
                           f"round stool, {legs} legs, {height:.2f} m high")
  leg_length = height - seat_thickness
  seat = furniture.add_part("seat", (0, 0, height - seat_thickness / 2), geoms=[
      bp.Geom("cylinder", (seat_radius, seat_thickness / 2), material=material)])
  for i in range(legs):
    angle = 2 * math.pi * i / legs
    x, y = leg_circle * math.cos(angle), leg_circle * math.sin(angle)
    leg = furniture.add_part(f"leg{i}", (x, y, leg_length / 2), geoms=[
        bp.Geom("cylinder", (leg_radius, leg_length / 2), material=material)])
    furniture.connect(leg, seat, (x, y, leg_length), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="leg_top", type_b="seat_leg_socket", twists_deg=())
  return furniture


def variants():
  return [round_stool("stool_round_frosta", "frosta")]
