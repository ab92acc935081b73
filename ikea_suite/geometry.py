"""Rigid-transform helpers on numpy arrays; quaternions are (w, x, y, z) like MuJoCo's."""

import numpy as np


def quat_to_mat(quat):
  """Rotation matrices (..., 3, 3) from unit quaternions (..., 4)."""
  w, x, y, z = np.moveaxis(np.asarray(quat, dtype=float), -1, 0)
  return np.stack([
      np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
      np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
      np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
  ], -2)


def mat_to_quat(mat):
  """Unit quaternion (w positive) of one rotation matrix."""
  m = np.asarray(mat, dtype=float)
  trace = m[0, 0] + m[1, 1] + m[2, 2]
  if trace > 0:
    s = 2.0 * np.sqrt(trace + 1.0)
    q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
  elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
    s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
    q = [(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s]
  elif m[1, 1] > m[2, 2]:
    s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
    q = [(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s]
  else:
    s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
    q = [(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s]
  q = np.asarray(q)
  q /= np.linalg.norm(q)
  return q if q[0] >= 0 else -q


def axis_angle_to_mat(axis_angle):
  """Rotation matrix of a rotation vector (axis times angle in radians)."""
  v = np.asarray(axis_angle, dtype=float)
  angle = np.linalg.norm(v)
  if angle < 1e-12:
    return np.eye(3)
  k = v / angle
  kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
  return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def mat_to_axis_angle(mat):
  """Rotation vector of a rotation matrix, angle in [0, pi]."""
  m = np.asarray(mat, dtype=float)
  cos = np.clip((np.trace(m) - 1) / 2, -1.0, 1.0)
  angle = np.arccos(cos)
  if angle < 1e-9:
    return np.zeros(3)
  if np.pi - angle < 1e-6:  # near pi the antisymmetric part vanishes
    col = np.argmax(np.diag(m))
    axis = (m[:, col] + np.eye(3)[col]) / np.sqrt(2 * (1 + m[col, col]))
    return axis / np.linalg.norm(axis) * angle
  axis = np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
  return axis / (2 * np.sin(angle)) * angle


def rot_z(angle):
  c, s = np.cos(angle), np.sin(angle)
  return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def frame_from_axes(zaxis, xaxis):
  """Rotation whose z column is `zaxis` and x column is `xaxis` (both unit, orthogonal)."""
  z = np.asarray(zaxis, dtype=float)
  x = np.asarray(xaxis, dtype=float)
  return np.column_stack([x, np.cross(z, x), z])
