"""Hollow parts: a part built of thin walls round an empty middle (a drawer box), whose
walls fill under HOLLOW_FILL of its bounding box.

A drawer box is wider than any gripper's stroke every way it lies, but its walls are
thin: standing as it stands in the furniture, a gripper takes it by the top edge of its
highest wall (experts/top_down_grasp.py). An arm's task lays such a part as it will
stand once assembled onto the root as the root lies (tasks/arm_placement.py), so the
arm carries it to its mate without turning it: turned from lying on its bottom onto its
side, the hand on its wall would end on the side the shelf above it closes.
"""

import functools

import numpy as np

from ikea_suite import geometry
from ikea_suite.props import furniture_spec

# A part whose collision boxes fill less than this of its bounding box is hollow (a
# drawer box, its 6-16 mm walls: 0.16).
HOLLOW_FILL = 0.5


def collision_boxes(part):
  """[(centre (3,), rotation (3, 3), half sizes (3,))] of a part's box collision geoms, in
  the part frame; None where it collides through another shape (a mesh, a cylinder).

  Args:
    part: a props.furniture_spec.PartSpec.
  Returns:
    The boxes, or None.
  """
  return _boxes(part.element)


@functools.lru_cache(maxsize=256)
def _boxes(element):
  boxes = []
  for geom in furniture_spec.collision_geoms(element):
    if geom.get("type") != "box":
      return None
    pos = np.array(geom.get("pos", "0 0 0").split(), dtype=float)
    quat = np.array(geom.get("quat", "1 0 0 0").split(), dtype=float)
    size = np.array(geom.get("size").split(), dtype=float)
    boxes.append((pos, geometry.quat_to_mat(quat), size))
  return boxes or None


def is_hollow(part):
  """Whether `part` (a PartSpec) is hollow: several box walls filling under HOLLOW_FILL
  of its bounds."""
  boxes = collision_boxes(part)
  if boxes is None or len(boxes) < 2:
    return False
  volume = np.prod(part.bounds[1] - part.bounds[0])
  walls = sum(8.0 * np.prod(size) for _, _, size in boxes)
  return bool(volume > 0 and walls < HOLLOW_FILL * volume)


def assembled_rest(spec, root, root_rest, part):
  """The rotation (3, 3, part to world) `part` has in the furniture assembled onto the
  root lying at `root_rest` (part to world): how a hollow part lies for an arm."""
  return root_rest @ spec.parts[root].rot.T @ spec.parts[part].rot


def top_wall(part, rot):
  """The wall whose top reaches highest with the part at rotation `rot` (part to world),
  and how far (m) that top stands above every other wall's: (centre (3,), rotation
  (3, 3), half sizes (3,)) in the part frame, and the height. None for a part that is not
  hollow."""
  if not is_hollow(part):
    return None
  boxes = collision_boxes(part)
  tops = [float(((geometry.box_corners(-size, size) @ box_rot.T + centre) @ rot.T)[:, 2].max())
          for centre, box_rot, size in boxes]
  order = np.argsort(tops)[::-1]
  return boxes[order[0]], tops[order[0]] - tops[order[1]]
