"""Storage boxes: a bottom panel with four walls standing on it, optionally a divider or a lid.

Every board of a box is one construction (`construction`): solid pine or birch
plywood for wooden boxes, MDF for painted ones, a polypropylene sheet for plastic
ones (the Kuggis-style box)."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms

GAP = 0.006   # wide enough that walls go in without scraping their neighbours


def open_box(name, variant, length=0.40, width=0.30, height=0.15, board=0.012,
             material="wood_light", divider=False, lid=False, construction=cons.PINE):
  """Long walls run the full length; short walls fit between them. A divider splits the box
  across the middle; a lid lies on the walls."""
  extras = " with a divider" if divider else (" with a lid" if lid else "")
  family = "divided" if divider else ("lidded" if lid else "open")
  furniture = bp.Blueprint(name, "box", family, variant,
                           f"{length:.2f} x {width:.2f} x {height:.2f} m storage box{extras}")
  bottom = furniture.add_part("bottom", (0, 0, board / 2), geoms=part_geoms.board(
      furniture, (length, width, board), material, construction, bevel=0.002))
  wall_z = board + height / 2
  long_wall = part_geoms.board(furniture, (length, board, height), material, construction,
                               bevel=0.002)
  for i, sy in enumerate((1, -1)):
    y = sy * (width / 2 - board / 2)
    wall = furniture.add_part(f"long_wall{i}", (0, y, wall_z), geoms=long_wall)
    furniture.connect(bottom, wall, (0, y, board), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="bottom_long_slot", type_b="long_wall_bottom", twists_deg=(0, 180))
  inner = width - 2 * board
  short_wall = part_geoms.board(furniture, (board, inner - 2 * GAP, height), material,
                                construction, bevel=0.002)
  for i, sx in enumerate((1, -1)):
    x = sx * (length / 2 - board / 2)
    wall = furniture.add_part(f"short_wall{i}", (x, 0, wall_z), geoms=short_wall)
    furniture.connect(bottom, wall, (x, 0, board), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="bottom_short_slot", type_b="short_wall_bottom", twists_deg=(0, 180))
  if divider:
    part = furniture.add_part("divider", (0, 0, board + (height - 0.02) / 2), geoms=part_geoms.board(
        furniture, (board, inner - 2 * GAP, height - 0.02), material, construction, bevel=0.002))
    furniture.connect(bottom, part, (0, 0, board), up=(0, 0, 1), forward=(1, 0, 0),
                      type_a="bottom_divider_slot", type_b="divider_bottom", twists_deg=(0, 180))
  if lid:
    # The lid overhangs the walls by 5 mm and rests on both long walls.
    top_z = board + height
    part = furniture.add_part("lid", (0, 0, top_z + board / 2), geoms=part_geoms.board(
        furniture, (length + 0.01, width + 0.01, board), material, construction, bevel=0.002))
    for i, sy in enumerate((1, -1)):
      furniture.connect(furniture.part(f"long_wall{i}"), part, (0, sy * (width / 2 - board / 2), top_z),
                        up=(0, 0, 1), forward=(1, 0, 0), type_a="wall_lid_slot", type_b="lid_rim",
                        twists_deg=(0, 180))
  return furniture


def variants():
  specs = [("kuggis", dict(construction=cons.PLASTIC_SHEET)),
           ("small_white", dict(length=0.26, width=0.18, height=0.12, material="white_laminate",
                                construction=cons.MDF)),
           ("large_birch", dict(length=0.55, width=0.37, height=0.2, material="birch",
                                construction=cons.BIRCH)),
           ("shoe_dark", dict(length=0.5, width=0.3, height=0.12, material="wood_dark")),
           ("tall_black", dict(length=0.33, width=0.33, height=0.3, material="black_laminate",
                               construction=cons.MDF))]
  out = [open_box(f"box_open_{v}", v, **kw) for v, kw in specs]
  divided = [("birch", dict(material="birch", construction=cons.BIRCH)),
             ("white_long", dict(length=0.6, width=0.3, material="white_laminate",
                                 construction=cons.MDF))]
  out += [open_box(f"box_divided_{v}", v, divider=True, **kw) for v, kw in divided]
  lidded = [("oak", dict(material="wood_medium", construction=cons.OAK)),
            ("white_flat", dict(length=0.5, width=0.35, height=0.1, material="white_laminate",
                                construction=cons.MDF)),
            ("toy_pine", dict(length=0.6, width=0.4, height=0.3, board=0.015))]
  out += [open_box(f"box_lidded_{v}", v, lid=True, **kw) for v, kw in lidded]
  return out
