"""Part placement for fixed-base arms: the parts lie flat on the floor within the arm's reach.

The root part (the one everything is built onto) lies in front of the
robot, turned over when its mates attach from below (a table top is
assembled upside down, as people do), so its open connectors face up. The
other parts are scattered without overlap in a ring around the base out to
`reach`. Furniture too large for that ring spills outwards instead of
failing, so every furniture loads with every robot.
"""

import numpy as np
from dm_control import composer

from ikea_suite import geometry
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner

_FLIP = np.diag([1.0, -1.0, -1.0])   # half a turn about the world x axis


def _corners(bounds):
  lo, hi = bounds
  return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def mates_from_below(spec, table, root):
  """Whether, in the assembled furniture, the root's mates lie mostly below its connectors."""
  by_name = spec.parts
  heights = []
  for a, b in zip(table.pair_a, table.pair_b):
    for mine, other in ((a, b), (b, a)):
      if table.part[mine] == root and table.part[other] != root:
        local = by_name[root].rot.T @ (by_name[table.part[other]].pos - by_name[root].pos)
        heights.append(local[2] - table.local_pos[mine][2])
  return bool(heights) and float(np.mean(heights)) < 0


class ReachableParts(composer.Initializer):
  """Root part in front of the base, the rest in a ring around it; random yaw and position."""

  def __init__(self, furniture, base_xy, base_rot, reach, inner=0.2, min_distance=0.55, gap=0.03,
               root_jitter=(0.03, np.radians(15)), sector=np.radians(110), max_attempts=200):
    self._furniture = furniture
    self._base_xy = np.asarray(base_xy, dtype=float)
    self._heading = np.arctan2(base_rot[1, 0], base_rot[0, 0])
    # inner: clearance around the base; min_distance: nearest a part centre may lie
    # to the base (an arm pointing down cannot reach right beside itself).
    self._reach, self._inner, self._gap = reach, inner, gap
    self._min_distance = min_distance
    self._root_jitter, self._sector, self._max_attempts = root_jitter, sector, max_attempts
    spec = furniture.spec
    self._root = planner.root_part(spec)
    rest = placement.resting_rotation(spec.parts[self._root].bounds)
    self._root_rest = _FLIP @ rest if mates_from_below(spec, furniture.connectors, self._root) else rest

  @property
  def root_part(self):
    return self._root

  def _footprint(self, index, rot):
    corners = _corners(self._furniture.spec.parts[index].bounds) @ rot.T
    centre = (corners[:, :2].max(0) + corners[:, :2].min(0)) / 2
    return corners, centre, np.linalg.norm(corners[:, :2] - centre, axis=1).max()

  def _place(self, physics, index, rot, xy):
    corners, centre, _ = self._footprint(index, rot)
    part = self._furniture.parts[index]
    part.set_pose(physics, position=np.array([*(xy - centre), -corners[:, 2].min() + 1e-3]),
                  quaternion=geometry.mat_to_quat(rot))
    part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))

  def __call__(self, physics, random_state):
    specs = self._furniture.spec.parts
    offset, yaw_jitter = self._root_jitter
    rot = geometry.rot_z(self._heading + random_state.uniform(-yaw_jitter, yaw_jitter)) @ self._root_rest
    _, _, radius = self._footprint(self._root, rot)
    forward = np.array([np.cos(self._heading), np.sin(self._heading)])
    xy = self._base_xy + forward * (self._inner + radius) + random_state.uniform(-offset, offset, 2)
    self._place(physics, self._root, rot, xy)
    placed = [(xy, radius)]
    others = sorted((i for i in range(len(specs)) if i != self._root),
                    key=lambda i: -np.ptp(_corners(specs[i].bounds), axis=0).max())
    for index in others:
      rot = (geometry.rot_z(random_state.uniform(-np.pi, np.pi))
             @ placement.resting_rotation(specs[index].bounds))
      _, _, radius = self._footprint(index, rot)
      xy = self._sample_xy(random_state, radius, placed)
      self._place(physics, index, rot, xy)
      placed.append((xy, radius))

  def _sample_xy(self, random_state, radius, placed):
    nearest = max(self._min_distance, self._inner + radius)
    outer = max(self._reach, nearest + 0.1)
    while True:
      for _ in range(self._max_attempts):
        distance = random_state.uniform(nearest, outer)
        angle = self._heading + random_state.uniform(-self._sector, self._sector)
        xy = self._base_xy + distance * np.array([np.cos(angle), np.sin(angle)])
        if all(np.linalg.norm(xy - other) > radius + other_r + self._gap for other, other_r in placed):
          return xy
      outer += 0.25   # out of room within reach: spill outwards rather than fail
      if outer > 10.0:
        raise composer.EpisodeInitializationError(f"no room for a part of radius {radius:.2f} m")
