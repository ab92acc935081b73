"""Dressers (chests of drawers): a carcass on a plinth filled with identical drawers."""

from ikea_suite.design import blueprint as bp
from ikea_suite.design.families import carcass


def chest(name, variant, width=0.8, depth=0.48, height=0.78, drawers=3, board=0.018,
          plinth=0.06, material="white_laminate", front_material=None):
  """Bottom and top boards between the side panels, `drawers` drawers stacked between them."""
  furniture = bp.Blueprint(name, "dresser", "chest", variant,
                           f"{width:.2f} m chest of {drawers} drawers, {height:.2f} m high")
  levels = [plinth + board / 2, height - board / 2]
  box = carcass.build(furniture, width, depth, height, levels, board, plinth, material=material)
  carcass.add_drawers(box, plinth + board, height - board, drawers,
                      front_material=front_material or material)
  return furniture


def variants():
  specs = [("three_white", {}),
           ("four_white", dict(height=1.0, drawers=4)),
           ("five_tall_birch", dict(width=0.6, height=1.24, drawers=5, material="birch")),
           ("two_low_oak", dict(width=0.8, height=0.5, drawers=2, material="wood_medium")),
           ("three_black", dict(material="black_laminate")),
           ("four_wide_dark", dict(width=1.0, height=0.95, drawers=4, material="wood_dark")),
           ("three_white_oak", dict(front_material="wood_medium")),
           ("six_tall_white", dict(width=0.6, height=1.4, drawers=6))]
  return [chest(f"dresser_chest_{v}", v, **kw) for v, kw in specs]
