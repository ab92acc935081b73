"""Initial placement: every part lies flat on the floor, scattered around the assembly area."""

import numpy as np
from dm_control import composer
from dm_control.composer.variation import distributions

from ikea_suite import geometry

_LIE_FLAT = {0: np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]]),   # part x axis to world z
             1: np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),   # part y axis to world z
             2: np.eye(3)}


def _corners(bounds):
  lo, hi = bounds
  return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def resting_rotation(bounds):
  """Rotation laying a part on its largest face: its thinnest extent becomes vertical."""
  return _LIE_FLAT[int(np.argmin(bounds[1] - bounds[0]))]


def assembled_radius(spec):
  """Horizontal radius of the assembled furniture around the origin."""
  return max(np.linalg.norm((_corners(p.bounds) @ p.rot.T + p.pos)[:, :2], axis=1).max()
             for p in spec.parts)


class ScatteredParts(composer.Initializer):
  """Places parts lying flat, random yaw, in a ring around the origin without overlap.

  The ring starts `clearance` beyond the assembled furniture's radius and is
  `spread` metres wide; `yaw` is a dm_control distribution (radians).
  """

  def __init__(self, furniture, spread=0.9, clearance=0.15, gap=0.03,
               yaw=distributions.Uniform(-np.pi, np.pi), max_attempts=500):
    self._furniture = furniture
    self._spread, self._gap, self._yaw = spread, gap, yaw
    self._inner = assembled_radius(furniture.spec) + clearance
    self._max_attempts = max_attempts

  def __call__(self, physics, random_state):
    placed = []   # (xy, radius)
    specs = self._furniture.spec.parts
    order = sorted(range(len(specs)), key=lambda i: -np.ptp(_corners(specs[i].bounds), axis=0).max())
    for index in order:
      spec = specs[index]
      rot = geometry.rot_z(self._yaw(random_state=random_state)) @ resting_rotation(spec.bounds)
      corners = _corners(spec.bounds) @ rot.T
      center_xy = (corners[:, :2].max(0) + corners[:, :2].min(0)) / 2
      radius = np.linalg.norm(corners[:, :2] - center_xy, axis=1).max()
      xy = self._sample_xy(random_state, radius, placed)
      placed.append((xy, radius))
      pos = np.array([*(xy - center_xy), -corners[:, 2].min() + 1e-3])
      part = self._furniture.parts[index]
      part.set_pose(physics, position=pos, quaternion=geometry.mat_to_quat(rot))
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))

  def _sample_xy(self, random_state, radius, placed):
    for _ in range(self._max_attempts):
      r = random_state.uniform(self._inner + radius, self._inner + radius + self._spread)
      angle = random_state.uniform(-np.pi, np.pi)
      xy = r * np.array([np.cos(angle), np.sin(angle)])
      if all(np.linalg.norm(xy - other) > radius + other_r + self._gap for other, other_r in placed):
        return xy
    raise composer.EpisodeInitializationError(
        f"could not place a part of radius {radius:.2f} m without overlap; raise `spread`")
