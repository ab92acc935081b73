"""Benches: a plank on two panel legs with a stretcher, and slatted benches on framed ends.

All parts are solid wood of their finish (painted ones pine, construction.solid_wood)."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes

GAP = 0.003


def plank_bench(name, variant, length=1.0, depth=0.32, height=0.45, board=0.03,
                material="wood_light"):
  """A seat plank on two identical end panels, braced by a stretcher under the seat."""
  furniture = bp.Blueprint(name, "bench", "plank", variant,
                           f"{length:.2f} m plank bench, {height:.2f} m high")
  leg_height = height - board
  wood = cons.solid_wood(material)
  seat = furniture.add_part("seat", (0, 0, height - board / 2), geoms=part_geoms.board(
      furniture, (length, depth, board), material, wood))
  leg_x = length / 2 - 0.08
  panel = part_geoms.board(furniture, (board, depth - 0.02, leg_height), material, wood)
  legs = []
  for i, sx in enumerate((-1, 1)):
    # The second end is the first turned half a turn, so the two are one part.
    leg = furniture.add_part(f"end{i}", (sx * leg_x, 0, leg_height / 2),
                             rot=bp.rot_z(0 if i == 0 else np.pi), geoms=panel)
    furniture.connect(leg, seat, (sx * leg_x, 0, leg_height), up=(0, 0, 1), forward=leg.rot[:, 0],
                      type_a="end_top", type_b="seat_end_slot", twists_deg=(0, 180))
    legs.append(leg)
  z = leg_height - 0.06
  span = 2 * leg_x - board - 2 * GAP
  stretcher = furniture.add_part("stretcher", (0, 0, z), geoms=part_geoms.board(
      furniture, (span, 0.02, 0.08), material, wood))
  for leg, sx in zip(legs, (-1, 1)):
    furniture.connect(stretcher, leg, (sx * (leg_x - board / 2), 0, z), up=(sx, 0, 0),
                      forward=(0, 0, 1), type_a="stretcher_end", type_b="end_stretcher_slot",
                      twists_deg=(0, 180))
  return furniture


def slatted_bench(name, variant, length=1.2, depth=0.4, height=0.45, slats=4, slat_thickness=0.025,
                  frame_thickness=0.045, border=0.05, material="wood_medium", frame_material=None):
  """Slats laid across two framed ends (a frame with an opening: coacd pieces).

  The two ends are one part turned half a turn; every slat is the same part.
  """
  furniture = bp.Blueprint(name, "bench", "slatted", variant,
                           f"{length:.2f} m bench, {slats} slats, {height:.2f} m high")
  frame_height = height - slat_thickness
  mesh = shapes.frame(depth, frame_height, frame_thickness, border, plane="yz")
  frame_finish = frame_material or material
  frame_geoms = part_geoms.concave(furniture, mesh, "bench_frame", frame_finish,
                                   cons.solid_wood(frame_finish))
  end_x = length / 2 - 0.1
  ends = [furniture.add_part(f"end{i}", (sx * end_x, 0, frame_height / 2),
                             rot=bp.rot_z(0 if i == 0 else np.pi), geoms=frame_geoms)
          for i, sx in enumerate((-1, 1))]
  slat_width = (depth - (slats - 1) * 0.01) / slats
  slat_geoms = part_geoms.board(furniture, (length, slat_width, slat_thickness), material,
                                cons.solid_wood(material))
  for k in range(slats):
    y = -depth / 2 + slat_width / 2 + k * (slat_width + 0.01)
    slat = furniture.add_part(f"slat{k}", (0, y, height - slat_thickness / 2), geoms=slat_geoms)
    for end, sx in zip(ends, (-1, 1)):
      furniture.connect(slat, end, (sx * end_x, y, frame_height), up=(0, 0, -1), forward=end.rot[:, 0],
                        type_a="slat_end", type_b="end_slat_slot", twists_deg=(0, 180))
  return furniture


def variants():
  planks = [("pine", {}), ("oak_long", dict(length=1.4, material="wood_medium")),
            ("white_short", dict(length=0.8, material="white_laminate")),
            ("dark_low", dict(length=1.1, height=0.4, depth=0.35, material="wood_dark"))]
  out = [plank_bench(f"bench_plank_{v}", v, **kw) for v, kw in planks]
  slatted = [("oak", {}), ("pine_three", dict(slats=3, length=1.0, depth=0.33, material="wood_light")),
             ("black_frame", dict(material="birch", frame_material="black_laminate"))]
  out += [slatted_bench(f"bench_slatted_{v}", v, **kw) for v, kw in slatted]
  return out
