"""Bookcases: two side panels, evenly spaced shelves (bottom and top included), a hardboard
back and a plinth; dimensions follow the common 40/80 cm wide, 28 cm deep flat-pack units."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design.families import carcass


def shelf_unit(name, variant, width=0.80, depth=0.28, height=1.06, shelves=4, board=0.018,
               plinth=0.06, material="white_laminate", back=True):
  """`shelves` identical boards between two identical side panels."""
  furniture = bp.Blueprint(name, "bookcase", "shelf_unit", variant,
                           f"{width:.2f} m wide bookcase, {shelves} shelves, {height:.2f} m high")
  carcass.build(furniture, width, depth, height, carcass.even_levels(height, shelves, board, plinth),
                board, plinth, back, material, back_material="white_laminate")
  return furniture


def variants():
  specs = [("billy", dict(width=0.5, height=0.8, shelves=3, plinth=0.0, back=False)),
           ("w40_h106_white", dict(width=0.4)),
           ("w80_h106_white", {}),
           ("w80_h106_birch", dict(material="birch")),
           ("w80_h202_white", dict(height=2.02, shelves=7)),
           ("w40_h202_oak", dict(width=0.4, height=2.02, shelves=7, material="wood_medium")),
           ("w80_h202_black", dict(height=2.02, shelves=8, material="black_laminate")),
           ("cd_tower", dict(width=0.4, depth=0.2, height=2.02, shelves=10)),
           ("w60_h140_pine", dict(width=0.6, height=1.4, shelves=5, material="wood_light")),
           ("low_w120_dark", dict(width=1.2, depth=0.35, height=0.6, shelves=3, material="wood_dark")),
           ("w60_h80_open", dict(width=0.6, height=0.8, shelves=3, back=False, plinth=0.0,
                                 material="birch")),
           ("kids_w60_white", dict(width=0.6, depth=0.3, height=0.9, shelves=3, plinth=0.05))]
  return [shelf_unit(f"bookcase_shelf_unit_{v}", v, **kw) for v, kw in specs]
