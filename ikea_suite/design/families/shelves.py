"""Shelving: two side panels holding shelves between them."""

import numpy as np

from ikea_suite.design import blueprint as bp


def shelf_unit(name, variant, width=0.50, depth=0.28, height=0.80, shelves=3,
               board=0.018, material="white_laminate"):
  """Side panels at x = +-(width/2 + board/2); shelves span the gap, bottom and top included.

  Each shelf end mates any side-panel slot, so identical shelves and the two
  identical side panels are interchangeable.
  """
  furniture = bp.Blueprint(name, "bookcase", "shelf_unit", variant,
                           f"{width:.2f} m wide shelf unit, {shelves} shelves, {height:.2f} m high")
  side_x = width / 2 + board / 2
  sides = [furniture.add_part(f"side{i}", (sx * side_x, 0, height / 2), geoms=[
      bp.Geom("box", (board / 2, depth / 2, height / 2), material=material)])
      for i, sx in enumerate((-1, 1))]
  levels = np.linspace(board / 2 + 0.04, height - board / 2, shelves)
  for i, z in enumerate(levels):
    shelf = furniture.add_part(f"shelf{i}", (0, 0, z), geoms=[
        bp.Geom("box", (width / 2, depth / 2, board / 2), material=material)])
    for side, sx in zip(sides, (-1, 1)):
      # Up points from the shelf out into the panel; forward along +z of the world.
      furniture.connect(shelf, side, (sx * width / 2, 0, z), up=(sx, 0, 0), forward=(0, 0, 1),
                        type_a="shelf_end", type_b="side_slot", twists_deg=(0, 180))
  return furniture


def variants():
  return [shelf_unit("bookcase_shelf_unit_billy", "billy")]
