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
- impedance: the task_space action (tool-centre-point moves and rotations,
  gripper), tracked not by IK but by a Cartesian spring and damper from the
  tool to its target that MuJoCo evaluates every substep (arm_actuators):
  the arm yields to contact the way a torque-controlled arm does.

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
IMPEDANCE = "impedance"
MODES = (TASK_SPACE, TASK_SPACE_POSE, JOINT_POSITION, JOINT_TORQUE, IMPEDANCE)
# Modes whose action moves task-space targets by deltas (TaskSpaceTargets.apply_deltas).
DELTA_TARGETS = (TASK_SPACE, IMPEDANCE)
POSITION_ACTUATED = (TASK_SPACE, TASK_SPACE_POSE, JOINT_POSITION)


def check(mode):
  if mode not in MODES:
    raise errors.UnknownNameError("control mode", mode, MODES)
  return mode


def arm_action_names(mode, joint_names):
  """Names of one arm's action entries (without the arm's prefix)."""
  if mode in DELTA_TARGETS:
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
  that pushing against an obstacle cannot wind it up. Positions are held as
  Python floats, which the per-step update and DifferentialIK.step read and write
  (with three numbers per arm each numpy call would cost more than its arithmetic).
  Rotations stay numpy products, whose rounding (BLAS's, not Python's) the experts'
  measured episodes were run with.
  """

  def __init__(self, num_arms, max_translation, max_rotation, workspace, max_lag=0.1):
    self._pos = [[0.0, 0.0, 0.0] for _ in range(num_arms)]   # per arm, x y z
    self._rot = np.tile(np.eye(3), (num_arms, 1, 1))
    self._max_translation, self._max_rotation = max_translation, max_rotation
    self._workspace = np.asarray(workspace, dtype=float)   # (num_arms, 2, 3) world boxes
    self._low, self._high = self._workspace[:, 0].tolist(), self._workspace[:, 1].tolist()
    self._max_lag = max_lag

  @property
  def pos(self):
    """(arms, 3) target positions (a copy)."""
    return np.array(self._pos)

  @property
  def rot(self):
    """(arms, 3, 3) target rotations (a copy)."""
    return self._rot.copy()

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
      self._set(i, pos, rot)

  def _set(self, i, pos, rot):
    self._pos[i] = np.asarray(pos, dtype=float).reshape(3).tolist()
    self._rot[i] = rot

  def apply_deltas(self, actions, tcp_pos):
    """Moves every arm's target by its delta action; actions (arms, >= 6), tcp_pos (arms, 3)."""
    step, turn, max_lag = self._max_translation, self._max_rotation, self._max_lag
    positions, rotations = self._pos, self._rot
    for i, (move, tcp, low, high) in enumerate(zip(actions.tolist(), tcp_pos.tolist(),
                                                    self._low, self._high)):
      x, y, z = positions[i]
      x, y, z = x + move[0] * step, y + move[1] * step, z + move[2] * step
      lag_x, lag_y, lag_z = x - tcp[0], y - tcp[1], z - tcp[2]
      distance = math.sqrt(lag_x * lag_x + lag_y * lag_y + lag_z * lag_z)
      if distance > max_lag:
        shrink = max_lag / distance
        x, y, z = tcp[0] + lag_x * shrink, tcp[1] + lag_y * shrink, tcp[2] + lag_z * shrink
      positions[i] = [min(max(x, low[0]), high[0]), min(max(y, low[1]), high[1]),
                      min(max(z, low[2]), high[2])]
      x, y, z = move[3] * turn, move[4] * turn, move[5] * turn
      if x or y or z:
        rotations[i] = _axis_angle_rows(x, y, z) @ rotations[i]

  def in_frame(self, origin, rotation):
    """Every arm's target in the frame at `origin` (3 floats) turned by `rotation` (9
    floats, row-major), both world frame: [(position (3 floats), rotation (9 floats,
    row-major))], as DifferentialIK.step takes."""
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = rotation
    ox, oy, oz = origin
    out = []
    for (x, y, z), (m0, m1, m2, m3, m4, m5, m6, m7, m8) in zip(
        self._pos, self._rot.reshape(-1, 9).tolist()):
      x, y, z = x - ox, y - oy, z - oz
      out.append(([r0 * x + r3 * y + r6 * z, r1 * x + r4 * y + r7 * z, r2 * x + r5 * y + r8 * z],
                  [r0 * m0 + r3 * m3 + r6 * m6, r0 * m1 + r3 * m4 + r6 * m7,
                   r0 * m2 + r3 * m5 + r6 * m8, r1 * m0 + r4 * m3 + r7 * m6,
                   r1 * m1 + r4 * m4 + r7 * m7, r1 * m2 + r4 * m5 + r7 * m8,
                   r2 * m0 + r5 * m3 + r8 * m6, r2 * m1 + r5 * m4 + r8 * m7,
                   r2 * m2 + r5 * m5 + r8 * m8]))
    return out

  def apply_pose(self, i, action, home_rot):
    low, high = self._workspace[i]
    self._set(i, (low + high) / 2 + action[:3] * (high - low) / 2,
              geometry.axis_angle_to_mat(action[3:6] * np.pi) @ home_rot)


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
