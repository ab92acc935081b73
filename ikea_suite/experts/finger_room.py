"""Where along a lying part an arm's open fingers can go down without landing on another part.

A leg dropped beside the upside-down table top, or lying against another leg, was
taken at its middle, where one open finger came down on the other part: the hand
stopped 9 mm above its grasp height and the reach stalled, every 150 steps, until the
episode ended (Sawyer, table_four_leg_kids_white). Such a part is taken instead at the
nearest point along its long axis where both fingers land clear, while the pads still
cover it.
"""

import mujoco
import numpy as np

from ikea_suite.experts import arm_motion
from ikea_suite.experts import part_geometry

# Room (m) the fingers keep from another part's collision box.
MARGIN = 0.003
# Grasp points tried along the part, evenly spaced: the middle first, then outwards.
CANDIDATES = 9
_FILL = np.linspace(-1.0, 1.0, 4)   # points across each finger box, per axis


def finger_points(robot, physics, arm):
  """(n, 3) points filling the open fingers' collision geoms, in the tool (TCP) frame."""
  poser = arm_motion.FingerPoser(robot, physics, arm)
  poser.set(0.0)
  model, data = poser.model, poser.data
  grid = np.stack(np.meshgrid(_FILL, _FILL, _FILL), axis=-1).reshape(-1, 3)
  points = []
  for g in poser.geoms:
    if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
      points.append(poser.points(g))
    else:
      local = grid * model.geom_aabb[g, 3:] + model.geom_aabb[g, :3]
      points.append(data.geom_xpos[g] + local @ data.geom_xmat[g].reshape(3, 3).T)
  tcp_pos = data.site_xpos[poser.tcp_site]
  tcp_rot = data.site_xmat[poser.tcp_site].reshape(3, 3)
  return (np.concatenate(points) - tcp_pos) @ tcp_rot


def lands_on_another_part(physics, furniture, part, points, margin=MARGIN):
  """Whether any of the world `points` lies within `margin` of another part's collision box."""
  for other in range(len(furniture.parts)):
    if other == part:
      continue
    pos, rot = part_geometry.part_pose(physics, furniture, other)
    low, high = furniture.spec.parts[other].bounds
    local = (points - pos) @ rot
    if np.any(np.all((local > low - margin) & (local < high + margin), axis=1)):
      return True
  return False


def clear_shift(physics, furniture, part, point, tool_rot, tool_points, pad_room):
  """World offset from the grasp `point` along the part's long axis to the nearest point
  where the open fingers (`tool_points`, tool frame, with the tool at `tool_rot`) land
  clear of every other part, at most to `pad_room` from the part's ends; zero when its
  middle is clear or no point along it is."""
  pos, rot = part_geometry.part_pose(physics, furniture, part)
  low, high = furniture.spec.parts[part].bounds
  axis = int(np.argmax(high - low))
  at = (rot.T @ (point - pos))[axis]
  first, last = min(0.0, low[axis] + pad_room - at), max(0.0, high[axis] - pad_room - at)
  fingers = tool_points @ tool_rot.T
  half = CANDIDATES // 2
  step = max(-first, last) / half
  # The middle, then outwards alternately, the -axis side first: a fixed order, so that
  # points equally far from the middle are not taken in turn as the part jitters.
  for k in sorted(range(-half, half + 1), key=lambda k: (abs(k), k)):
    along = k * step
    if not first - 1e-9 <= along <= last + 1e-9:
      continue
    shift = along * rot[:, axis]
    shift[2] = 0.0   # the grasp height stays the controller's
    if not lands_on_another_part(physics, furniture, part, point + shift + fingers):
      return shift
  return np.zeros(3)
