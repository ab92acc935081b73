"""TV units: long, low carcasses with doors, drawers or open shelves, and TV benches on legs."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design.families import carcass
from ikea_suite.design.families import tables


def tv_cabinet(name, variant, width=1.2, depth=0.4, height=0.5, front="doors", board=0.018,
               plinth=0.05, material="white_laminate", front_material=None):
  """Bottom, middle shelf and top between two panels; the front is "doors" (two),
  "drawers" (two wide drawers) or "open"."""
  furniture = bp.Blueprint(name, "tv_unit", front if front != "open" else "open", variant,
                           f"{width:.2f} m TV unit, {front}, {height:.2f} m high")
  if front == "drawers":
    levels = [plinth + board / 2, height - board / 2]
  else:
    levels = carcass.even_levels(height, 3, board, plinth)
  box = carcass.build(furniture, width, depth, height, levels, board, plinth, material=material)
  if front == "doors":
    carcass.add_doors(box, plinth, height, 2, front_material or material)
  elif front == "drawers":
    carcass.add_drawers(box, plinth + board, height - board, 2,
                        front_material=front_material or material)
  return furniture


def tv_bench(name, variant, **kw):
  """A Lack-style TV bench: the coffee table's honeycomb top, hollow legs and shelf."""
  furniture = tables.coffee_shelf_table(name, variant, **kw)
  furniture.category, furniture.family = "tv_unit", "bench"
  furniture.description = "TV bench on four legs with a lower shelf"
  return furniture


def variants():
  cabinets = [("doors_white", {}),
              ("doors_oak", dict(width=1.5, material="wood_medium")),
              ("doors_black_white", dict(material="black_laminate", front_material="white_laminate")),
              ("drawers_white", dict(front="drawers", height=0.42)),
              ("drawers_birch", dict(front="drawers", width=1.0, material="birch")),
              ("open_white", dict(front="open")),
              ("open_dark_long", dict(front="open", width=1.6, height=0.45, material="wood_dark"))]
  out = [tv_cabinet(f"tv_unit_{v.split('_')[0]}_{'_'.join(v.split('_')[1:])}",
                    "_".join(v.split("_")[1:]), **kw) for v, kw in cabinets]
  benches = [("oak", dict(width=1.2, depth=0.4, height=0.45, material="wood_medium")),
             ("black", dict(width=1.5, depth=0.4, height=0.4, material="black_laminate"))]
  out += [tv_bench(f"tv_unit_bench_{v}", v, **kw) for v, kw in benches]
  return out
