"""Bed frames: a headboard and a footboard joined by two side rails, with slats resting on
ledges along the rails. Sizes follow children's and single flat-pack beds.

Ends and rails are particleboard, or solid wood (`panels`) for a wooden bed; the
ledges and slats are solid pine, as slats are in flat-pack beds."""

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes

GAP = 0.003


def slatted_bed(name, variant, mattress_width=0.7, mattress_length=1.6, slats=8,
                rail_height=0.15, rail_z=0.12, head_height=0.7, foot_height=0.4, board=0.02,
                material="white_laminate", open_headboard=False, panels=cons.PARTICLEBOARD):
  """Side rails span between the ends; slats lie across the rails' ledges. The two rails are
  one part turned half a turn; every slat is the same part.

  With `open_headboard` the headboard is a frame with an opening (coacd pieces).
  """
  furniture = bp.Blueprint(name, "bed", "slatted", variant,
                           f"bed frame for a {mattress_width * 100:.0f} x "
                           f"{mattress_length * 100:.0f} cm mattress, {slats} slats")
  width = mattress_width + 2 * board
  rail_y = mattress_width / 2 + board / 2
  rail_len = mattress_length
  ends = []
  for i, (sx, h) in enumerate(((-1, head_height), (1, foot_height))):
    x = sx * (rail_len / 2 + board / 2)
    if i == 0 and open_headboard:
      mesh = shapes.frame(width, h, board, 0.08, plane="yz")
      geoms = part_geoms.concave(furniture, mesh, "headboard", material, panels)
    else:
      geoms = part_geoms.board(furniture, (board, width, h), material, panels)
    ends.append(furniture.add_part(("headboard", "footboard")[i], (x, 0, h / 2), geoms=geoms))
  ledge = 0.02
  rail_geoms = (part_geoms.board(furniture, (rail_len - 2 * GAP, board, rail_height), material,
                                 panels)
                + part_geoms.box((rail_len - 0.02, ledge, ledge), "wood_light", cons.PINE,
                                 pos=(0, -(board / 2 + ledge / 2), -rail_height / 2 + ledge / 2)))
  rails = []
  for i, sy in enumerate((1, -1)):
    y = sy * rail_y
    rail = furniture.add_part(f"rail{i}", (0, y, rail_z + rail_height / 2),
                              rot=bp.rot_z(0 if i == 0 else np.pi), geoms=rail_geoms)
    for end, sx in zip(ends, (-1, 1)):
      furniture.connect(rail, end, (sx * rail_len / 2, y, rail_z + rail_height / 2),
                        up=(sx, 0, 0), forward=(0, 0, 1), type_a="rail_end", type_b="end_rail_slot",
                        twists_deg=(0,))
    rails.append(rail)
  slat_len = mattress_width - 2 * ledge - 2 * GAP
  slat_w, slat_t = 0.06, 0.015
  slat_geoms = part_geoms.board(furniture, (slat_w, slat_len + 2 * ledge - 2 * GAP, slat_t),
                                "wood_light", cons.PINE, bevel=0.002)
  z = rail_z + ledge + slat_t / 2
  for k, x in enumerate(np.linspace(-rail_len / 2 + 0.1, rail_len / 2 - 0.1, slats)):
    slat = furniture.add_part(f"slat{k}", (x, 0, z), geoms=slat_geoms)
    for rail, sy in zip(rails, (1, -1)):
      y = sy * (mattress_width / 2 - ledge / 2)
      furniture.connect(slat, rail, (x, y, rail_z + ledge), up=(0, 0, -1), forward=(0, sy, 0),
                        type_a="slat_end", type_b="rail_slat_slot", twists_deg=(0, 180))
  return furniture


def variants():
  specs = [("kids_white", {}),
           ("kids_birch_open", dict(material="birch", open_headboard=True, panels=cons.BIRCH)),
           ("junior_pine", dict(mattress_length=1.7, slats=9, material="wood_light",
                                panels=cons.PINE)),
           ("toddler_white", dict(mattress_width=0.6, mattress_length=1.2, slats=6, head_height=0.6,
                                  foot_height=0.35)),
           ("kids_dark_open", dict(material="wood_dark", slats=10, open_headboard=True,
                                   panels=cons.PINE)),
           ("day_black", dict(mattress_width=0.8, mattress_length=1.6, slats=8,
                              material="black_laminate"))]
  return [slatted_bed(f"bed_slatted_{v}", v, **kw) for v, kw in specs]
