"""Which loose parts an arm's task stands in a panel rack (props/panel_rack.py), and how.

A part is racked when it is a thin panel (its thickness under PANEL_RATIO of its
next-smallest extent) that stands upright in the assembled furniture (its
thin axis horizontal once the root lies as placed) and is at least
MIN_HEIGHT tall standing: a box wall, a bench's stretcher, a chair back, a
cabinet side. It stands in its slot as it will stand in the furniture, up to a
turn about the vertical, so the arm carries it upright from the rack to its mate.
Rods and blocks (legs, the parts of every stool and four-leg table in the
catalog) still lie on the floor, and so does a panel that lies flat when
assembled (a shelf, a lid).
"""

import numpy as np

from ikea_suite import geometry
from ikea_suite.props import panel_rack

PANEL_RATIO = 0.26   # a bench's 20 x 80 mm stretcher (a quarter) is a panel
# Standing, a racked panel's top must clear the fins by the fingers' grip on its top edge
# (20 mm, experts/top_down_grasp.EDGE_GRIP) with room to spare (panel_rack.FINGER_ROOM); the
# expert takes a panel this tall or taller by its top edge.
MIN_HEIGHT = 0.035
# The rack stands where its farthest slot lies this far (m) within the arm's reach: the
# fingers close only within 1.5 mm of a panel's edge, which the Panda, stretched to its
# 0.8 m reach, did not attain (fresh seeds 14005 and 14010: every box failed there).
RACK_SPARE = 0.1
# A panel that hangs this far (m) below the root lying as placed (a chair's back under
# its upside-down seat) goes in once the expert has turned the assembly over
# (experts/turn_over.py), so it stands in the rack the way up it will then have.
UNDER = 0.01


def is_panel(extents):
  """Whether a box of these (3,) extents is a thin panel: thickness under PANEL_RATIO of the
  next-smallest extent (a box wall, a seat; not a leg, a rail or a block)."""
  low, middle, _ = np.sort(extents)
  return bool(low < PANEL_RATIO * middle)


def upright_panels(spec, root, root_rest):
  """[(part, rotation)] of the parts to rack: each panel's world rotation in the furniture
  assembled onto the root lying at `root_rest` (3, 3) (turned over, for a panel under
  the root), turned about z so that its thickness lies along x (the rack's row)."""
  design_to_world = root_rest @ spec.parts[root].rot.T

  def lowest(part):
    return (part.assembled_corners() @ design_to_world.T)[:, 2].min()

  root_bottom = lowest(spec.parts[root])
  out = []
  for index, part in enumerate(spec.parts):
    extents = part.bounds[1] - part.bounds[0]
    order = np.argsort(extents)
    if index == root or not is_panel(extents):
      continue
    rot = design_to_world @ part.rot
    if lowest(part) < root_bottom - UNDER:   # goes in once the assembly is turned over
      rot = geometry.HALF_TURN_X @ rot
    normal = rot[:, order[0]]
    if abs(normal[2]) > 0.5:   # lies flat when assembled
      continue
    rot = geometry.rot_z(-np.arctan2(normal[1], normal[0])) @ rot
    if np.ptp((geometry.box_corners(*part.bounds) @ rot.T)[:, 2]) >= MIN_HEIGHT:
      out.append((index, rot))
  return out


def slot_sizes(spec, panels):
  """(thickness, length, height) of each racked panel standing in its slot (PanelRack's slots)."""
  sizes = []
  for index, rot in panels:
    corners = geometry.box_corners(*spec.parts[index].bounds) @ rot.T
    sizes.append(np.ptp(corners, axis=0))
  return np.array(sizes)


class RackedPanels:
  """Builds the rack for a furniture's upright panels and places it and them each episode.

  Args:
    spec: the furniture's spec.
    root: the root part's index.
    root_rest: the root's resting rotation (3, 3) before its yaw.
  """

  def __init__(self, spec, root, root_rest):
    self._spec = spec
    self._panels = upright_panels(spec, root, root_rest)
    self.rack = (panel_rack.PanelRack(slots=slot_sizes(spec, self._panels))
                 if self._panels else None)

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

  def place(self, physics, furniture, xy, yaw, height, random_state, skip=()):
    """Sets the rack at world `xy` turned by `yaw` on a surface at `height`, and stands each
    panel (but those in `skip`, placed otherwise: preassembled) in its slot, turned half
    a turn at random."""
    rack_rot = geometry.rot_z(yaw)
    origin = np.array([xy[0], xy[1], height])
    self.rack.set_pose(physics, position=origin, quaternion=geometry.mat_to_quat(rack_rot))
    for slot, (index, rot) in enumerate(self._panels):
      if index in skip:
        continue
      rot = rack_rot @ geometry.rot_z(np.pi * random_state.randint(2)) @ rot
      corners = geometry.box_corners(*self._spec.parts[index].bounds) @ rot.T
      bottom_middle = np.array([*(corners[:, :2].max(0) + corners[:, :2].min(0)) / 2,
                                corners[:, 2].min()])
      target = origin + rack_rot @ self.rack.slot_centre(slot) + [0.0, 0.0, 1e-3]
      part = furniture.parts[index]
      part.set_pose(physics, position=target - bottom_middle, quaternion=geometry.mat_to_quat(rot))
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))
