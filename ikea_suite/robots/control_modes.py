"""How a manipulator's [-1, 1] action slice becomes actuator controls, per control mode.

Every mode's per-arm action ends with `gripper` (-1 open, +1 closed):

- task_space: move_x, move_y, move_z (tool-centre-point displacement in the
  world frame, `max_translation` m per control step at 1), rotate_x, rotate_y,
  rotate_z (a world-frame axis-angle rotation, `max_rotation` rad per step at 1).
- task_space_pose: x, y, z (absolute tool position mapped onto the robot's
  workspace box), rot_x, rot_y, rot_z (axis-angle times pi applied to the home
  tool orientation, gripper pointing down).
- joint_position: one target per arm joint mapped onto the joint's range,
  tracked by PD position actuators.
- joint_torque: one torque per arm joint scaled to the joint's torque limit.

Both task-space modes are solved once per control step by mink differential
IK and tracked during the physics substeps by the joint position actuators.
"""

import math

import numpy as np

from ikea_suite import errors
from ikea_suite import geometry

TASK_SPACE = "task_space"
TASK_SPACE_POSE = "task_space_pose"
JOINT_POSITION = "joint_position"
JOINT_TORQUE = "joint_torque"
MODES = (TASK_SPACE, TASK_SPACE_POSE, JOINT_POSITION, JOINT_TORQUE)
POSITION_ACTUATED = (TASK_SPACE, TASK_SPACE_POSE, JOINT_POSITION)


def check(mode):
  if mode not in MODES:
    raise errors.UnknownNameError("control mode", mode, MODES)
  return mode


def arm_action_names(mode, joint_names):
  """Names of one arm's action entries (without the arm's prefix)."""
  if mode == TASK_SPACE:
    names = ["move_x", "move_y", "move_z", "rotate_x", "rotate_y", "rotate_z"]
  elif mode == TASK_SPACE_POSE:
    names = ["x", "y", "z", "rot_x", "rot_y", "rot_z"]
  elif mode == JOINT_POSITION:
    names = [f"{j}_position" for j in joint_names]
  else:
    names = [f"{j}_torque" for j in joint_names]
  return names + ["gripper"]


class TaskSpaceTargets:
  """Tool-centre-point targets (world frame) of every arm, updated from actions.

  A delta target is kept at most `max_lag` metres from the measured tool so
  that pushing against an obstacle cannot wind it up.
  """

  def __init__(self, num_arms, max_translation, max_rotation, workspace, max_lag=0.1):
    self.pos = np.zeros((num_arms, 3))
    self.rot = np.tile(np.eye(3), (num_arms, 1, 1))
    self._max_translation, self._max_rotation = max_translation, max_rotation
    self._workspace = np.asarray(workspace, dtype=float)   # (num_arms, 2, 3) world boxes
    self._low, self._high = self._workspace[:, 0], self._workspace[:, 1]
    self._max_lag = max_lag

  @property
  def max_translation(self):
    """Metres a delta target moves per step at an action of 1."""
    return self._max_translation

  @property
  def max_rotation(self):
    """Radians a delta target turns per step at an action of 1."""
    return self._max_rotation

  def reset(self, poses):
    for i, (pos, rot) in enumerate(poses):
      self.pos[i], self.rot[i] = pos, rot

  def apply_deltas(self, actions, tcp_pos):
    """Moves every arm's target by its delta action; actions (arms, >= 6), tcp_pos (arms, 3)."""
    target = self.pos + actions[:, :3] * self._max_translation
    lag = target - tcp_pos
    distance = np.sqrt(np.einsum("ij,ij->i", lag, lag))
    far = distance > self._max_lag
    if far.any():
      target[far] = tcp_pos[far] + lag[far] * (self._max_lag / distance[far])[:, None]
    self.pos[:] = np.minimum(np.maximum(target, self._low), self._high)
    for i, rotation in enumerate((actions[:, 3:6] * self._max_rotation).tolist()):
      if rotation != [0.0, 0.0, 0.0]:
        self.rot[i] = _axis_angle_rows(*rotation) @ self.rot[i]

  def apply_pose(self, i, action, home_rot):
    low, high = self._workspace[i]
    self.pos[i] = (low + high) / 2 + action[:3] * (high - low) / 2
    self.rot[i] = geometry.axis_angle_to_mat(action[3:6] * np.pi) @ home_rot


def _axis_angle_rows(x, y, z):
  """Rotation matrix of a rotation vector in Python floats (the formulas of MuJoCo's
  mju_axisAngle2Quat and mju_quat2Mat): a few numpy calls would cost more."""
  angle = math.sqrt(x * x + y * y + z * z)
  if angle <= 1e-12:
    return np.eye(3)
  s = math.sin(angle * 0.5) / angle
  w, x, y, z = math.cos(angle * 0.5), x * s, y * s, z * s
  ww, xx, yy, zz = w * w, x * x, y * y, z * z
  wx, wy, wz, xy, xz, yz = w * x, w * y, w * z, x * y, x * z, y * z
  return np.array([[ww + xx - yy - zz, 2 * (xy - wz), 2 * (xz + wy)],
                   [2 * (xy + wz), ww - xx + yy - zz, 2 * (yz - wx)],
                   [2 * (xz - wy), 2 * (yz + wx), ww - xx - yy + zz]])


def joint_targets(action, low, high):
  """Joint position targets: [-1, 1] onto [low, high]."""
  return (low + high) / 2 + action * (high - low) / 2
