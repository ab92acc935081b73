"""Cabinets: a carcass closed by one or two doors, and nightstands with a drawer over an
open shelf. Doors and drawers hang on the side panels (see carcass)."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design.families import carcass


def door_cabinet(name, variant, width=0.8, depth=0.4, height=0.9, shelves=1, doors=2,
                 board=0.018, plinth=0.08, material="white_laminate", door_material=None):
  """A carcass with bottom, top and `shelves` inner shelves behind `doors` overlay doors."""
  furniture = bp.Blueprint(name, "cabinet", "doors", variant,
                           f"{width:.2f} m cabinet, {doors} door{'s' * (doors > 1)}, "
                           f"{height:.2f} m high")
  box = carcass.build(furniture, width, depth, height,
                      carcass.even_levels(height, shelves + 2, board, plinth), board, plinth,
                      material=material)
  carcass.add_doors(box, plinth, height, doors, door_material or material)
  return furniture


def nightstand(name, variant, width=0.45, depth=0.38, height=0.55, drawers=1, board=0.016,
               material="white_laminate", front_material=None):
  """A small carcass: `drawers` drawers at the top, an open shelf below."""
  furniture = bp.Blueprint(name, "nightstand", "drawer", variant,
                           f"{width:.2f} m nightstand, {drawers} drawer{'s' * (drawers > 1)}")
  plinth = 0.04
  split = height - board - 0.16 * drawers
  levels = [plinth + board / 2, split - board / 2, height - board / 2]
  box = carcass.build(furniture, width, depth, height, levels, board, plinth, material=material)
  carcass.add_drawers(box, split, height - board, drawers, front_material=front_material or material)
  return furniture


def variants():
  cabinets = [("w80_white", {}),
              ("w60_one_door", dict(width=0.6, doors=1)),
              ("w80_oak_doors", dict(material="white_laminate", door_material="wood_medium")),
              ("tall_w80", dict(height=1.8, shelves=3, depth=0.45)),
              ("w40_birch", dict(width=0.4, height=0.7, doors=1, material="birch")),
              ("w100_black", dict(width=1.0, height=0.75, material="black_laminate")),
              ("wall_w60_dark", dict(width=0.6, depth=0.3, height=0.6, plinth=0.0, shelves=1,
                                     material="wood_dark")),
              ("w120_low_white", dict(width=1.2, depth=0.45, height=0.6, shelves=0))]
  out = [door_cabinet(f"cabinet_doors_{v}", v, **kw) for v, kw in cabinets]
  stands = [("white", {}), ("birch", dict(material="birch")),
            ("two_drawer_oak", dict(drawers=2, height=0.62, material="wood_medium")),
            ("black_front", dict(front_material="black_laminate")),
            ("wide_dark", dict(width=0.55, depth=0.4, material="wood_dark"))]
  out += [nightstand(f"nightstand_drawer_{v}", v, **kw) for v, kw in stands]
  return out
