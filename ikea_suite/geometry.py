"""Rigid-transform helpers on numpy arrays; quaternions are (w, x, y, z) like MuJoCo's."""

import mujoco
import numpy as np


def quat_to_mat(quat):
  """Rotation matrix (3, 3) of one unit quaternion, via MuJoCo's C routine."""
  out = np.empty(9)
  mujoco.mju_quat2Mat(out, np.asarray(quat, dtype=float))
  return out.reshape(3, 3)


def quats_to_mats(quat):
  """Rotation matrices (..., 3, 3) from unit quaternions (..., 4), vectorised."""
  w, x, y, z = np.moveaxis(np.asarray(quat, dtype=float), -1, 0)
  return np.stack([
      np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
      np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
      np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
  ], -2)


def mat_to_quat(mat):
  """Unit quaternion (w >= 0) of one rotation matrix."""
  q = np.empty(4)
  mujoco.mju_mat2Quat(q, np.ascontiguousarray(mat, dtype=float).ravel())
  return q if q[0] >= 0 else -q


def axis_angle_to_quat(axis_angle):
  """Unit quaternion of a rotation vector (axis times angle in radians)."""
  v = np.asarray(axis_angle, dtype=float)
  angle = float(np.sqrt(v @ v))
  q = np.array([1.0, 0.0, 0.0, 0.0])
  if angle > 1e-12:
    mujoco.mju_axisAngle2Quat(q, v / angle, angle)
  return q


def axis_angle_to_mat(axis_angle):
  """Rotation matrix of a rotation vector (axis times angle in radians)."""
  return quat_to_mat(axis_angle_to_quat(axis_angle))


def quat_mul(a, b):
  out = np.empty(4)
  mujoco.mju_mulQuat(out, np.asarray(a, dtype=float), np.asarray(b, dtype=float))
  return out


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


HALF_TURN_X = np.diag([1.0, -1.0, -1.0])   # half a turn about the x axis: turned over


_CORNERS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=bool)


def box_corners(low, high):
  """(8, 3) corners of the axis-aligned box from `low` to `high`."""
  return np.where(_CORNERS, np.asarray(high, float), np.asarray(low, float))


def rot_z(angle):
  c, s = np.cos(angle), np.sin(angle)
  return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def frame_from_axes(zaxis, xaxis):
  """Rotation whose z column is `zaxis` and x column is `xaxis` (both unit, orthogonal)."""
  z = np.asarray(zaxis, dtype=float)
  x = np.asarray(xaxis, dtype=float)
  return np.column_stack([x, np.cross(z, x), z])


def pointing_down(rot):
  """The rotation nearest `rot` whose z axis (a tool's approach direction) points straight down."""
  x = np.array([rot[0, 0], rot[1, 0], 0.0])
  if np.linalg.norm(x) < 1e-6:
    x = np.array([rot[0, 1], rot[1, 1], 0.0])
  x /= np.linalg.norm(x)
  return frame_from_axes(np.array([0.0, 0.0, -1.0]), x)
