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

from ikea_suite import geometry
from ikea_suite.robots import control_modes

# N m/rad per joint towards the home posture: small against the spring as felt at the
# joints (hundreds of N m/rad), so the tool's steady error stays near a millimetre.
POSTURE_STIFFNESS = 2.0
_AXES = ("x", "y", "z")


def add(root, arm, mode, kp_per_nm, mount, home_q, stiffness):
  """Adds one arm's actuators under MJCF `root` and returns them.

  Impedance only: `mount` is the fixed body the target site sits on, `home_q`
  the arm's home joint angles the posture spring pulls towards, `stiffness`
  the spring's (N/m, N m/rad; the option impedance_stiffness, config.ArmConfig).
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


# The largest physics time step an arm takes: MuJoCo integrates a position servo's
# stiffness explicitly (implicitfast treats only damping implicitly), so a servo of
# gain kp moving an effective mass m, natural frequency w = sqrt(kp / m), oscillates
# unstably once w * dt exceeds 2 undamped (4.8 critically damped), and loses accuracy
# well before. Measured with 100 random task-space actions at scale 0.5: every
# arm's joint speeds stayed at the default's (<= 2 rad/s, the IK's limit) up to
# w * dt = 0.5 and grew beyond from about 0.7 (Baxter at 10 ms: 3.1 rad/s; Sawyer at
# 25 ms: 18 rad/s, diverging at 50 ms). So dt <= 0.5 / w: 12.6 steps per period of the
# stiffest servo. At the default 2 ms every arm has a margin of 3 or more (Baxter's
# stiffest servo: 74 rad/s, 6.7 ms; Sawyer 8.4, Panda 11.6, Jaco 34 ms).
SERVO_STEP_FRACTION = 0.5


def moved_masses(physics, actuator_ids, qpos_index, q):
  """{actuator id: the mass (kg, or kg m^2 for a hinge) it moves} at joint angles `q`
  (written at `qpos_index` of a scratch copy of the state): 1 / (moment M^-1 moment^T)."""
  model = physics.model.ptr
  data = mujoco.MjData(model)
  data.qpos[qpos_index] = q
  mujoco.mj_forward(model, data)
  inertia = np.zeros((model.nv, model.nv))
  mujoco.mj_fullM(model, data, inertia)
  masses = {}
  for i in actuator_ids:
    moment = np.zeros(model.nv)
    start, count = data.moment_rowadr[i], data.moment_rownnz[i]
    moment[data.moment_colind[start:start + count]] = data.actuator_moment[start:start + count]
    masses[int(i)] = 1.0 / (moment @ np.linalg.solve(inertia, moment))
  return masses


def stiffest_servo(physics, actuator_ids, qpos_index, q):
  """The natural frequency (rad/s) and id of the stiffest position servo among
  `actuator_ids` at joint angles `q`, from its gain and the mass it moves."""
  model = physics.model.ptr
  servos = [i for i in actuator_ids
            if model.actuator_biastype[i] == mujoco.mjtBias.mjBIAS_AFFINE]
  best = (0.0, -1)
  for i, mass in moved_masses(physics, servos, qpos_index, q).items():
    best = max(best, (float(np.sqrt(model.actuator_gainprm[i, 0] / mass)), i))
  return best


def critical_damping(physics, actuator_ids, qpos_index, q):
  """Sets each impedance actuator's damping to critical at joint angles `q` (the home pose).

  MuJoCo's dampratio takes the mass an actuator moves at the model's reference
  pose (all joints at 0): there a stretched arm is singular, and two of the
  Jaco's axes got no damping at all. At the working pose the mass per axis is
  1 / (moment M^-1 moment^T), from a scratch copy of the state.
  """
  model = physics.model.ptr
  for i, mass in moved_masses(physics, actuator_ids, qpos_index, q).items():
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
