"""A flat-pack carcass: two side panels holding horizontal boards, a back panel and a plinth.

Bookcases, cabinets, dressers, TV units, nightstands and desk drawer units
are all this box with different fronts. Coordinates: the floor is z = 0,
the front faces -y, x runs across. Horizontal boards (bottom, shelves, top)
are one size, so all of them are the same interchangeable part; the two side
panels are identical too. Doors and drawers attach to the side panels.

Constructions: sides, horizontal boards, plinth, doors, drawer fronts and drawer
sides are particleboard; the back panel and drawer bottoms are 3 mm hardboard
(construction.HARDBOARD), modelled as thicker collision boxes that weigh what
the sheet weighs.
"""

import dataclasses

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import part_geoms

BACK = 0.008      # collision thickness of the back panel; it weighs as 3 mm hardboard
GAP = 0.003       # clearance around fronts, drawers and back panels


@dataclasses.dataclass
class Carcass:
  furniture: bp.Blueprint
  width: float
  depth: float
  height: float
  board: float
  plinth: float
  sides: list
  levels: list       # z centres of the horizontal boards, bottom first

  @property
  def inner_width(self):
    return self.width - 2 * self.board

  def side_x(self, i):
    return (-1, 1)[i] * (self.width / 2 - self.board / 2)


def build(furniture, width, depth, height, levels, board=0.018, plinth=0.0, back=True,
          material="white_laminate", back_material=None):
  """Sides, one horizontal board at each z in `levels` (centres), back panel and plinth."""
  inner = width - 2 * board
  shelf_depth = depth - (BACK + GAP if back else 0)
  shelf_y = -depth / 2 + shelf_depth / 2
  sides = []
  for i, sx in enumerate((-1, 1)):
    x = sx * (width / 2 - board / 2)
    sides.append(furniture.add_part(f"side{i}", (x, 0, height / 2), geoms=part_geoms.board(
        furniture, (board, depth, height), material, cons.PARTICLEBOARD)))
  shelf_geoms = part_geoms.board(furniture, (inner - 2 * GAP, shelf_depth, board), material,
                                 cons.PARTICLEBOARD)
  for k, z in enumerate(levels):
    shelf = furniture.add_part(f"shelf{k}", (0, shelf_y, z), geoms=shelf_geoms)
    for side, sx in zip(sides, (-1, 1)):
      # Up points from the board's end into the panel, forward up the panel.
      furniture.connect(shelf, side, (sx * inner / 2, shelf_y, z), up=(sx, 0, 0),
                        forward=(0, 0, 1), type_a="shelf_end", type_b="side_shelf_slot",
                        twists_deg=(0, 180))
  if back:
    back_height = height - plinth - 2 * GAP
    y = depth / 2 - BACK / 2
    panel = furniture.add_part("back", (0, y, plinth + GAP + back_height / 2),
                               geoms=part_geoms.board(furniture, (inner - 2 * GAP, BACK, back_height),
                                                      back_material or material, cons.HARDBOARD,
                                                      bevel=0.001))
    for side, sx in zip(sides, (-1, 1)):
      furniture.connect(panel, side, (sx * inner / 2, y, plinth + GAP + back_height / 2),
                        up=(sx, 0, 0), forward=(0, 0, 1), type_a="back_edge",
                        type_b="side_back_slot", twists_deg=(0, 180))
  if plinth > 0:
    y = -depth / 2 + 0.03 + board / 2
    kick = furniture.add_part("plinth", (0, y, plinth / 2 - GAP / 2), geoms=part_geoms.board(
        furniture, (inner - 2 * GAP, board, plinth - GAP), material, cons.PARTICLEBOARD))
    for side, sx in zip(sides, (-1, 1)):
      furniture.connect(kick, side, (sx * inner / 2, y, plinth / 2), up=(sx, 0, 0),
                        forward=(0, 0, 1), type_a="plinth_end", type_b="side_plinth_slot",
                        twists_deg=(0, 180))
  return Carcass(furniture, width, depth, height, board, plinth, sides, list(levels))


def even_levels(height, count, board, plinth=0.0):
  """`count` board centres from the bottom (on the plinth) to the top, evenly spaced."""
  return list(np.linspace(plinth + board / 2, height - board / 2, count))


def add_doors(carcass, bottom, top, count=2, material=None):
  """`count` (1 or 2) overlay doors covering the front between heights bottom and top.

  Every door is the same part: its hinge connector sits on one long edge, so
  the right door is the left door turned half a turn about its normal.
  """
  c, f = carcass, carcass.furniture
  width = c.width / count - 2 * GAP
  height = top - bottom - 2 * GAP
  y = -c.depth / 2 - GAP - c.board / 2
  geoms = part_geoms.board(f, (width, c.board, height), material or "white_laminate",
                           cons.PARTICLEBOARD)
  z = (bottom + top) / 2
  for i in range(count):
    sx = (-1, 1)[i]
    x = sx * (c.width / 2 - GAP - width / 2)
    rot = np.eye(3) if i == 0 else bp.rot_y(np.pi)
    door = f.add_part(f"door{i}", (x, y, z), rot=rot, geoms=geoms)
    # Hinge at the panel's front edge; forward runs up for the left door, down for the right.
    f.connect(door, c.sides[i], (c.side_x(i), -c.depth / 2, z), up=(0, -1, 0),
              forward=(0, 0, -sx), type_a="door_hinge", type_b="side_hinge_slot")


def add_drawers(carcass, bottom, top, count, material=None, front_material=None):
  """`count` equal drawers (open boxes of five boards) stacked between two heights.

  A drawer's runners mate runner slots on both panels; all drawers are the
  same part.
  """
  c, f = carcass, carcass.furniture
  t = 0.012
  pitch = (top - bottom) / count
  box_w = c.inner_width - 2 * GAP - 0.02        # room for the runners
  box_d = c.depth - BACK - 2 * GAP - 0.02
  box_h = pitch - 0.04
  front = (c.width - 2 * GAP, t + 0.004, pitch - 2 * GAP)
  mat, front_mat = material or "birch", front_material or "white_laminate"
  pb = cons.PARTICLEBOARD
  geoms = (part_geoms.box((box_w, box_d, t), mat, cons.HARDBOARD, pos=(0, 0, -box_h / 2 + t / 2))
           + part_geoms.board(f, front, front_mat, pos=(0, -box_d / 2 - front[1] / 2, 0),
                              construction=pb)
           + part_geoms.box((box_w, t, box_h - t), mat, pb, pos=(0, box_d / 2 - t / 2, t / 2))
           + sum((part_geoms.box((t, box_d - 2 * t, box_h - t), mat, pb,
                                 pos=(sx * (box_w / 2 - t / 2), 0, t / 2)) for sx in (-1, 1)), []))
  y = -c.depth / 2 - GAP + box_d / 2      # the front overlays the carcass edges
  for k in range(count):
    z_mid = bottom + pitch * (k + 0.5)
    drawer = f.add_part(f"drawer{k}", (0, y, z_mid), geoms=geoms)
    for side, sx in zip(c.sides, (-1, 1)):   # a runner on each side
      f.connect(drawer, side, (sx * c.inner_width / 2, y, z_mid), up=(sx, 0, 0),
                forward=(0, 0, 1), type_a="drawer_runner", type_b="side_runner_slot")
