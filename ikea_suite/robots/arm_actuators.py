"""The actuators that drive one arm's joints, per control mode.

- Position modes (task_space, task_space_pose, joint_position): a PD position
  actuator per joint, its gain proportional to the joint's torque limit.
- joint_torque: a motor per joint, limited to the joint's torque.
- impedance: a Cartesian spring and damper between the tool-centre point and a
  target frame, as six MuJoCo position actuators with a site transmission
  whose reference site is the target (three along its axes, three about
  them). MuJoCo computes the pose error (position, and the rotation vector of
  the tool relative to the target) and maps the forces onto the joints through
  the tool's Jacobian every substep, so no Python runs per substep: Python only
  moves the target site once per control step (`ImpedanceTargets`). Gravity is
  compensated by the bodies' gravcomp, as the real arms' torque controllers do;
  each joint's total actuator torque is clamped to its limit (MuJoCo's joint
  actuatorfrcrange), and on 7-joint arms a weak joint spring towards the home
  posture keeps the redundant elbow from drifting.
"""

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite import options
from ikea_suite.robots import control_modes

# Default Cartesian stiffness of impedance mode (load option `impedance_stiffness`):
# 1500 N/m and 60 N m/rad, ten times libfranka's Cartesian impedance example (150 N/m,
# 10 N m/rad, examples/cartesian_impedance_control.cpp, a soft hand-guiding setting) so
# that a 1 kg part sags 6.5 mm and the tool settles within 2-3 mm of its target.
# Damping is critical per axis at the home pose (critical_damping).
IMPEDANCE_STIFFNESS = (1500.0, 60.0)
# N m/rad per joint towards the home posture: small against the spring as felt at the
# joints (hundreds of N m/rad), so the tool's steady error stays near a millimetre.
POSTURE_STIFFNESS = 2.0
_AXES = ("x", "y", "z")


def impedance_stiffness(value, mode):
  """The (N/m, N m/rad) Cartesian stiffness of impedance mode, from the load option
  (None: the default); None in other modes, where giving it is an error."""
  if mode != control_modes.IMPEDANCE:
    if value is not None:
      raise errors.OptionValueError(f"impedance_stiffness applies to control_mode='impedance' "
                                    f"only, got control_mode={mode!r}")
    return None
  value = options.vector("impedance_stiffness", IMPEDANCE_STIFFNESS if value is None else value,
                         (2,))
  if not (value > 0).all():
    raise errors.OptionValueError(f"impedance_stiffness must be two numbers > 0 "
                                  f"(N/m, N m/rad), got {value.tolist()!r}")
  return tuple(float(v) for v in value)


def add(root, arm, mode, kp_per_nm, mount, home_q, stiffness):
  """Adds one arm's actuators under MJCF `root` and returns them.

  Impedance only: `mount` is the fixed body the target site sits on, `home_q`
  the arm's home joint angles the posture spring pulls towards, `stiffness`
  the spring's (N/m, N m/rad).
  """
  if mode == control_modes.IMPEDANCE:
    return _impedance(root, arm, mount, home_q, stiffness)
  actuators = []
  for joint, limit in zip(arm.joints, arm.torque_limits):
    if mode in control_modes.POSITION_ACTUATED:
      kwargs = dict(kp=kp_per_nm * limit, dampratio=1.0, forcelimited=True,
                    forcerange=(-limit, limit))
      if joint.range is not None:
        kwargs.update(ctrllimited=True, ctrlrange=joint.range)
      actuators.append(root.actuator.add(
          "position", name=f"{joint.name}_position", joint=joint, **kwargs))
    else:
      actuators.append(root.actuator.add(
          "motor", name=f"{joint.name}_torque", joint=joint, ctrllimited=True,
          ctrlrange=(-limit, limit)))
  return actuators


def _impedance(root, arm, mount, home_q, stiffness):
  tcp = arm.gripper.tcp_site
  target = mount.add("site", name=f"{arm.prefix}impedance_target", size=[0.01], group=4,
                     rgba=(0.1, 0.9, 0.1, 0.5))
  arm.impedance_target = target
  translational, rotational = stiffness
  actuators = []
  for k in range(6):
    gear = np.zeros(6)
    gear[k] = 1.0
    name = f"{arm.prefix}impedance_{'move' if k < 3 else 'rotate'}_{_AXES[k % 3]}"
    actuators.append(root.actuator.add(
        "position", name=name, site=tcp, refsite=target, gear=gear,
        kp=translational if k < 3 else rotational, dampratio=1.0,
        ctrllimited=True, ctrlrange=(-1.0, 1.0)))
  redundant = len(arm.joints) > 6   # a 6-joint arm (the Jaco) has no null space to hold
  for joint, limit, angle in zip(arm.joints, arm.torque_limits, home_q):
    joint.actuatorfrcrange = (-limit, limit)
    if redundant:
      joint.stiffness = POSTURE_STIFFNESS
      joint.springref = angle
  return actuators


def critical_damping(physics, actuator_ids, qpos_index, q):
  """Sets each impedance actuator's damping to critical at joint angles `q` (the home pose).

  MuJoCo's dampratio takes the mass an actuator moves at the model's reference
  pose (all joints at 0): there a stretched arm is singular, and two of the
  Jaco's axes got no damping at all. At the working pose the mass per axis is
  1 / (moment M^-1 moment^T), from a scratch copy of the state.
  """
  model = physics.model.ptr
  data = mujoco.MjData(model)
  data.qpos[qpos_index] = q
  mujoco.mj_forward(model, data)
  inertia = np.zeros((model.nv, model.nv))
  mujoco.mj_fullM(model, data, inertia)
  for i in actuator_ids:
    moment = np.zeros(model.nv)
    start, count = data.moment_rowadr[i], data.moment_rownnz[i]
    moment[data.moment_colind[start:start + count]] = data.actuator_moment[start:start + count]
    mass = 1.0 / (moment @ np.linalg.solve(inertia, moment))
    model.actuator_biasprm[i, 2] = -2.0 * np.sqrt(model.actuator_gainprm[i, 0] * mass)


class ImpedanceTargets:
  """Moves each arm's impedance target site to its task-space target, once per control step.

  The site sits on a fixed body, so its pose in that body is the target's
  pose seen from the body (MuJoCo recomputes its world pose each substep).
  """

  def __init__(self, physics, targets, mounts):
    """`targets`: the target site elements, one per arm; `mounts`: their bodies."""
    self._site_ids = np.array(physics.bind(targets).element_id)
    self._mount_ids = np.array(physics.bind(mounts).element_id)
    # Built at its body's origin, the site is flagged as sharing the body's frame, and
    # MuJoCo's kinematics would then ignore the site_pos and site_quat written here.
    physics.model.site_sameframe[self._site_ids] = 0

  def place(self, physics, positions, rotations):
    """Puts every arm's target at world `positions` (arms, 3), `rotations` (arms, 3, 3)."""
    data, model = physics.data, physics.model
    for site, body, pos, rot in zip(self._site_ids, self._mount_ids, positions, rotations):
      body_rot = data.xmat[body].reshape(3, 3)
      model.site_pos[site] = body_rot.T @ (pos - data.xpos[body])
      model.site_quat[site] = geometry.mat_to_quat(body_rot.T @ rot)
