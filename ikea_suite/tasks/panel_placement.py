"""Which loose parts an arm's task stands in a panel rack (props/panel_rack.py), and how.

A part is racked when it is a thin panel (its thickness under PANEL_RATIO of its
next-smallest extent, or a board: a plinth, BOARD_RATIO of its width thick and
over BOARD_LENGTH widths long) that stands upright in the assembled furniture (its
thin axis horizontal once the root lies as placed) and is at least
MIN_HEIGHT tall standing: a box wall, a bench's stretcher, a chair back, a
cabinet side. It stands in its slot as it will stand in the furniture, up to a
turn about the vertical, so the arm carries it upright from the rack to its mate.
Rods and blocks (legs, the parts of every stool and four-leg table in the
catalog) still lie on the floor, and so does a panel that lies flat when
assembled and is at most FLAT_WIDE across (a narrow shelf or lid, which a gripper
takes across lying flat). A wider one (the far side of a bookcase, cabinet or
dresser built lying on its other side, a wide lid) stands in its slot on its long edge,
so that a gripper takes it across its thickness by that edge and turns it flat on the
way to its mate (experts/top_down_grasp.py). A wide flat panel that is a frame of bars
(is_frame: a shelving ladder, two posts joined by crossbars) is not racked: it lies on
the floor the way up it lies in the furniture (flat_frames), where a gripper takes one
of its bars from above like a leg and carries it in flat, unturned. A round panel
(a disc: a round seat, a round table top) stands in a slot with chocks
(props/panel_rack.py).

A two-arm robot gets two racks, one each side of its heading, each holding the
panels that stand on its side of the furniture (split_by_side): one rack on one
side of the Baxter's torso was out of the other arm's reach, and one arm did all
the work. The placement is the same for a learner as for the expert.
"""

import numpy as np

from ikea_suite import geometry
from ikea_suite.props import panel_rack
from ikea_suite.tasks import resting

PANEL_RATIO = 0.26   # a bench's 20 x 80 mm stretcher (a quarter) is a panel
# A plinth lying flat (8 x 18 mm at scale 0.5) rolled up between the Panda's closing
# fingertips and slipped out; stood in the rack as in the furniture it is taken by its
# top end like a box wall. A board is BOARD_RATIO of its width thick (the catalog's
# plinths: 0.32-0.43) and over BOARD_LENGTH widths long; no leg, rail or block of the
# catalog is. A bed's side rail (40 x 150 mm: 0.27) is neither board nor panel: it lies
# flat, and its bed is built at the smaller scale its width fits (experts/work_scale.py).
BOARD_RATIO, BOARD_LENGTH = (0.3, 0.5), 8.0
# Standing, a racked panel's top must clear the fins by the fingers' grip on its top edge
# (20 mm, experts/top_down_grasp.EDGE_GRIP) with room to spare (panel_rack.FINGER_ROOM); the
# expert takes a panel this tall or taller by its top edge.
MIN_HEIGHT = 0.035
# The rack stands where its farthest slot lies this far (m) within the arm's reach: the
# fingers close only within 1.5 mm of a panel's edge, which the Panda, stretched to its
# 0.8 m reach, did not attain (every box failed in two episodes with the rack farther out).
RACK_SPARE = 0.1
# A panel that hangs this far (m) below the root lying as placed (a chair's back under
# its upside-down seat) goes in once the expert has turned the assembly over
# (experts/turn_over.py), so it stands in the rack the way up it will then have.
UNDER = 0.01
# A panel lying flat when assembled and wider than this (m, across its long axis) stands
# on its long edge in the rack: lying flat it is wider than the narrowest open gripper of
# the arms (the Sawyer's, 60 mm), and nothing takes a flat panel by an edge on the floor.
FLAT_WIDE = 0.06


def is_panel(extents):
  """Whether a box of these (3,) extents is a thin panel: thickness under PANEL_RATIO of the
  next-smallest extent (a box wall, a seat; not a leg, a rail or a block), or a board
  (is_board: a carcass's plinth, 16 x 37 x 412 mm)."""
  low, middle, _ = np.sort(extents)
  return bool(low < PANEL_RATIO * middle or is_board(extents))


def is_board(extents):
  """Whether a box of these (3,) extents is a board: BOARD_RATIO of its width thick and
  over BOARD_LENGTH widths long (a plinth)."""
  low, middle, high = np.sort(extents)
  return bool(BOARD_RATIO[0] * middle <= low < BOARD_RATIO[1] * middle
              and high > BOARD_LENGTH * middle)


def _geom_extents(geom):
  """(3,) extents (m) of a box, cylinder or capsule <geom> element; None for other types."""
  size = [float(v) for v in geom.get("size", "").split()]
  kind = geom.get("type", "sphere")
  if kind == "box" and len(size) == 3:
    return 2 * np.array(size)
  if kind in ("cylinder", "capsule") and len(size) >= 2:
    return 2 * np.array([size[0], size[0], size[1] + (size[0] if kind == "capsule" else 0.0)])
  return None


def is_frame(part):
  """Whether a part is a panel (is_panel, by its bounds) that collides through two or more
  bars and nothing else: each collision geom a box, cylinder or capsule whose middle
  extent is under PANEL_RATIO of its longest (a shelving ladder's posts and crossbars),
  so that the panel is open in the middle and a gripper takes a bar of it as it would
  take a leg."""
  if not is_panel(part.bounds[1] - part.bounds[0]):
    return False
  bars = 0
  for geom in part.collision_geoms():
    extents = _geom_extents(geom)
    if extents is None:
      return False
    _, middle, longest = np.sort(extents)
    if middle >= PANEL_RATIO * longest:
      return False
    bars += 1
  return bars >= 2


def is_disc(part, thin_axis):
  """Whether a part collides through a cylinder whose axis is its thin axis (`thin_axis`,
  0-2, of its bounds): a round panel, whose rim is round."""
  for geom in part.collision_geoms():
    if geom.get("type") != "cylinder":
      continue
    quat = [float(v) for v in geom.get("quat", "1 0 0 0").split()]
    if abs(geometry.quat_to_mat(quat)[thin_axis, 2]) > 0.99:
      return True
  return False


def _design_to_world(spec, root, root_rest):
  """The rotation from the furniture's design frame to the world, the root lying at
  `root_rest`, and a test whether a part hangs below the root lying so (goes in once the
  assembly is turned over)."""
  design_to_world = root_rest @ spec.parts[root].rot.T

  def lowest(part):
    return (part.assembled_corners() @ design_to_world.T)[:, 2].min()

  root_bottom = lowest(spec.parts[root])
  return design_to_world, lambda part: lowest(part) < root_bottom - UNDER


def flat_frames(spec, root, root_rest):
  """[(part, rotation)] of the frames (is_frame) wider than FLAT_WIDE that lie flat in the
  furniture assembled onto the root lying at `root_rest` (3, 3), with the world rotation
  each has there: it lies on the floor so, its mates facing the way they will face, and
  the arm carries it in turning it only about the vertical. Stood on its long edge in the
  rack instead, a shelving ladder taken by its top post could not be turned flat within
  the Panda's reach (its wrist joints reached their limits over the shelves)."""
  design_to_world, under = _design_to_world(spec, root, root_rest)
  out = []
  for index, part in enumerate(spec.parts):
    extents = part.bounds[1] - part.bounds[0]
    order = np.argsort(extents)
    if index == root or under(part) or not is_frame(part):
      continue
    rot = design_to_world @ part.rot
    if abs(rot[2, order[0]]) > 0.5 and extents[order[1]] > FLAT_WIDE:
      out.append((index, rot))
  return out


def upright_panels(spec, root, root_rest):
  """[(part, rotation)] of the parts to rack: each panel's world rotation in the furniture
  assembled onto the root lying at `root_rest` (3, 3) (turned over, for a panel under
  the root; stood on its long edge, for a wide one lying flat there), turned about z so
  that its thickness lies along x (the rack's row). The flat frames (flat_frames) lie on
  the floor instead."""
  design_to_world, under = _design_to_world(spec, root, root_rest)
  frames = {index for index, _ in flat_frames(spec, root, root_rest)}
  out = []
  for index, part in enumerate(spec.parts):
    extents = part.bounds[1] - part.bounds[0]
    order = np.argsort(extents)
    if index == root or index in frames or not is_panel(extents):
      continue
    rot = design_to_world @ part.rot
    if under(part):   # goes in once the assembly is turned over
      rot = geometry.HALF_TURN_X @ rot
    normal = rot[:, order[0]]
    if abs(normal[2]) > 0.5:   # lies flat when assembled
      if extents[order[1]] <= FLAT_WIDE:
        continue
      # On its long edge: a quarter turn about its long axis, which lies horizontal.
      rot = geometry.axis_angle_to_mat(rot[:, order[2]] * np.pi / 2) @ rot
      normal = rot[:, order[0]]
    rot = geometry.rot_z(-np.arctan2(normal[1], normal[0])) @ rot
    if np.ptp((geometry.box_corners(*part.bounds) @ rot.T)[:, 2]) >= MIN_HEIGHT:
      out.append((index, rot))
  return out


def split_by_side(spec, root, root_rest, parts):
  """The racked `parts` of a two-arm robot in two racks, one each side of its heading:
  [(side, parts)], side +1 for the left and -1 for the right. Each panel goes to the
  side of the root's centre where it stands in the furniture assembled onto the root
  lying at `root_rest` (its side after the turn-over, for a panel under the root), so
  that each arm carries its panels from its own side to mates on that side. Panels
  across the middle (a box's front and back walls, a bench's stretcher) even the racks
  up, and a rack left empty takes the panel nearest the middle from the other: with
  all of a box's walls in one rack the other arm never worked. A side with no panel is
  left out."""
  design_to_world, under = _design_to_world(spec, root, root_rest)
  root_centre = spec.parts[root].pos
  across = {}
  for index in parts:
    part = spec.parts[index]
    y = (design_to_world @ (part.pos - root_centre))[1]
    across[index] = -y if under(part) else y   # the half turn about x turns y round
  middle = 0.25 * max([abs(y) for y in across.values()], default=0.0)
  sides = {index: 0 if abs(y) <= middle else int(np.sign(y)) for index, y in across.items()}
  for index in sorted((i for i in parts if sides[i] == 0), key=lambda i: abs(across[i])):
    left = sum(side == 1 for side in sides.values())
    right = sum(side == -1 for side in sides.values())
    sides[index] = 1 if left < right or left == right and across[index] >= 0 else -1
  for side in (1, -1):
    mine = [i for i in parts if sides[i] == side]
    theirs = [i for i in parts if sides[i] == -side]
    if not mine and len(theirs) > 1:
      sides[min(theirs, key=lambda i: abs(across[i]))] = side
  return [(side, [i for i in parts if sides[i] == side]) for side in (1, -1)
          if any(sides[i] == side for i in parts)]


def slot_sizes(spec, panels):
  """(thickness, length, height) of each racked panel standing in its slot (PanelRack's slots)."""
  sizes = []
  for index, rot in panels:
    corners = geometry.box_corners(*spec.parts[index].bounds) @ rot.T
    sizes.append(np.ptp(corners, axis=0))
  return np.array(sizes)


class RackedPanels:
  """Builds the rack for a furniture's upright panels and places it and them each episode.

  A panel stands upright in the middle of its slot, just above the plate; one that would
  lean into its slot from there starts leaning as it comes to rest (resting.py), every
  such panel leaning the same way along the rack, whichever way round it stands.

  Args:
    spec: the furniture's spec.
    root: the root part's index.
    root_rest: the root's resting rotation (3, 3) before its yaw.
    only: the racked parts this rack holds (split_by_side); None: every one.
    name: the rack's model name.
  """

  def __init__(self, spec, root, root_rest, only=None, name="panel_rack"):
    self._spec = spec
    self._panels = [(index, rot) for index, rot in upright_panels(spec, root, root_rest)
                    if only is None or index in only]
    discs = [is_disc(spec.parts[index], int(np.argmin(np.ptp(spec.parts[index].bounds, axis=0))))
             for index, _ in self._panels]
    self.rack = (panel_rack.PanelRack(slots=slot_sizes(spec, self._panels), discs=discs,
                                      name=name) if self._panels else None)
    self._rests = (resting.rests_in_rack(
        spec, self.rack.boxes, [(index, rot, self._stand(slot, rot, np.eye(3), np.zeros(3)))
                                for slot, (index, rot) in enumerate(self._panels)],
        self.rack.lean) if self._panels else [])

  def _stand(self, slot, rot, rack_rot, origin):
    """Position of a panel at world rotation `rot` stood upright in the middle of `slot`,
    resting.LANDING above the plate, of the rack at `origin` turned by `rack_rot`."""
    corners = geometry.box_corners(*self._spec.parts[self._panels[slot][0]].bounds) @ rot.T
    bottom_middle = np.array([*(corners[:, :2].max(0) + corners[:, :2].min(0)) / 2,
                              corners[:, 2].min()])
    target = origin + rack_rot @ self.rack.slot_centre(slot) + [0.0, 0.0, resting.LANDING]
    return target - bottom_middle

  @property
  def parts(self):
    """Indices of the racked parts."""
    return [index for index, _ in self._panels]

  @property
  def farthest_slot(self):
    """Distance (m) along the rack from its centre to its end slots' panels."""
    return float(np.abs(self.rack.slot_centre(0)[0]))

  @property
  def radius(self):
    """Radius (m) of the rack's footprint about its centre."""
    return float(np.linalg.norm(self.rack.half_size))

  @property
  def height(self):
    """Height (m) above the surface the rack stands on of its tallest panel's top, stood
    upright (a leaning panel's is lower)."""
    return float(panel_rack.PLATE + slot_sizes(self._spec, self._panels)[:, 2].max()
                 + resting.LANDING)

  def place(self, physics, furniture, xy, yaw, height, random_state, skip=()):
    """Sets the rack at world `xy` turned by `yaw` on a surface at `height`, and stands each
    panel (but those in `skip`, placed otherwise: preassembled) in its slot, turned half
    a turn at random."""
    rack_rot = geometry.rot_z(yaw)
    origin = np.array([xy[0], xy[1], height])
    self.rack.set_pose(physics, position=origin, quaternion=geometry.mat_to_quat(rack_rot))
    for slot, ((index, rot), rests) in enumerate(zip(self._panels, self._rests)):
      if index in skip:
        continue
      half_turns = random_state.randint(2)
      turn = geometry.rot_z(np.pi * half_turns)
      rest = rests[half_turns]   # turned, the rest leaning the other way leans this way
      if rest.position is None:
        rot = rack_rot @ turn @ rot
        position = self._stand(slot, rot, rack_rot, origin)
      else:   # the rest found in the slot, turned with the panel about the slot's middle
        centre = self.rack.slot_centre(slot)
        rot = rack_rot @ turn @ rest.rotation
        position = origin + rack_rot @ (centre + turn @ (rest.position - centre))
      part = furniture.parts[index]
      part.set_pose(physics, position=position, quaternion=geometry.mat_to_quat(rot))
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))
