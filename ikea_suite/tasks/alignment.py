"""The paper's connector alignment test (Lee et al. 2019, eqs. 1-4), over all pairs at once.

Connectors A and B are attachable when
  ||p_A - p_B|| < distance,
  cos(up_A, up_B) > up_cos,
  max over allowed twists t of cos(R(up_A, t) fwd_A, fwd_B) > forward_cos.
Because fwd_A is orthogonal to up_A, R(up_A, t) fwd_A = cos t fwd_A + sin t (up_A x fwd_A),
so every twist costs one multiply-add on two dot products. Both forward vectors
are measured in the plane normal to the mean up vector, which makes the test
symmetric in A and B; when the up vectors coincide it is exactly the paper's.
"""

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True)
class Thresholds:
  """Attachable when closer than `distance` (m) and the axes' cosines exceed `up_cos` and
  `forward_cos`; the options distance_threshold, up_threshold and forward_threshold
  (config.TaskConfig, whose defaults are 2 cm at scale 1 and ~8 degrees)."""
  distance: float
  up_cos: float
  forward_cos: float

  @classmethod
  def of(cls, task_config):
    """The thresholds of a resolved config.TaskConfig."""
    return cls(distance=task_config.distance_threshold, up_cos=task_config.up_threshold,
               forward_cos=task_config.forward_threshold)


@dataclasses.dataclass(frozen=True)
class PairAlignment:
  """Per candidate pair: distance, up cosine, best forward cosine and the twist achieving it."""
  distance: np.ndarray
  up_cos: np.ndarray
  forward_cos: np.ndarray
  twist: np.ndarray       # radians; for any-twist pairs the measured twist

  def attachable(self, thresholds):
    return ((self.distance < thresholds.distance) & (self.up_cos > thresholds.up_cos)
            & (self.forward_cos > thresholds.forward_cos))


def _dot(a, b):
  return np.einsum("pi,pi->p", a, b)


def _unit(vectors):
  return vectors / np.maximum(np.sqrt(_dot(vectors, vectors)), 1e-9)[:, None]


def _triple(a, b, c):
  """a . (b x c) per row, written out: numpy's cross costs more than the rest of the test."""
  return (a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
          + a[:, 1] * (b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2])
          + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]))


def align_pairs(pos, rot, table):
  """Scores every candidate pair of `table` given connector world frames (c,3) and (c,3,3)."""
  a, b = table.pair_a, table.pair_b
  rot_a, rot_b = rot[a], rot[b]
  gap = pos[a] - pos[b]
  distance = np.sqrt(_dot(gap, gap))
  up_cos = _dot(rot_a[:, :, 2], rot_b[:, :, 2])
  up = _unit(rot_a[:, :, 2] + rot_b[:, :, 2])
  # Forward vectors projected into the plane normal to the mean up vector.
  fwd_a, fwd_b = rot_a[:, :, 0], rot_b[:, :, 0]
  fwd_a = _unit(fwd_a - up * _dot(fwd_a, up)[:, None])
  fwd_b = _unit(fwd_b - up * _dot(fwd_b, up)[:, None])
  c = _dot(fwd_a, fwd_b)              # cos of the measured twist
  s = _triple(up, fwd_a, fwd_b)       # sin of the measured twist: (up x fwd_a) . fwd_b
  per_twist = table.twist_cos * c[:, None] + table.twist_sin * s[:, None]
  per_twist = np.where(table.twist_valid, per_twist, -np.inf)
  best = np.argmax(per_twist, axis=1)
  rows = np.arange(len(a))
  forward_cos = np.where(table.any_twist, 1.0, per_twist[rows, best])
  twist = np.where(table.any_twist, np.arctan2(s, c), table.twist_angles[rows, best])
  return PairAlignment(distance, up_cos, forward_cos, twist)
