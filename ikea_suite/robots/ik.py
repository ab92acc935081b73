"""Differential inverse kinematics with mink on the robot's own compiled model.

The robot's MJCF alone (base at the origin, no furniture) is compiled once,
so each solve touches only the robot's joints. Targets are tool-centre-point
poses in the robot base frame; one QP per call gives joint velocities that
respect joint limits and per-joint velocity limits.

mink's tasks and limits define the QP. The per-control-step `step` assembles
it in ik_qp (the same H, c and limits, solved by DAQP with box bounds) because
mink's general path costs most of a task-space control step; `step_mink`
builds it with mink.build_ik + qpsolvers, which `solve` uses and tests compare
`step` against.
"""

import math

import mink
import mujoco
import numpy as np
import qpsolvers
from dm_control import mjcf

from ikea_suite.robots import ik_qp

_TURN = 2 * np.pi
# Regularizes the redundant (null-space) motion of 7-DoF arms towards home.
_POSTURE_COST = 1e-2
_DAMPING = 1e-3


class DifferentialIK:
  """One mink QP over all of a robot's joints, with a frame task per arm."""

  def __init__(self, mjcf_model, tcp_sites, arm_joints, velocity_limit, solver="daqp",
               working_ranges=None):
    """`tcp_sites`: one site element per arm; `arm_joints`: joint elements velocity-limited;
    `working_ranges`: {joint element: (low, high)} the IK keeps those joints in, within
    their physical limits (see Manipulator.IK_WORKING_RANGES)."""
    self._physics = mjcf.Physics.from_mjcf_model(mjcf_model)
    model = self._physics.model.ptr   # the raw mujoco.MjModel, as mink wants
    self.model = model
    self.joints = [j for j in mjcf_model.find_all("joint") if j.tag == "joint"]
    self.qpos_index = np.array(self._physics.bind(self.joints).qposadr)
    for joint, (low, high) in (working_ranges or {}).items():
      index = int(self._physics.bind(joint).element_id)
      physical = model.jnt_range[index].copy()
      model.jnt_range[index] = [max(low, physical[0]), min(high, physical[1])]
    self._configuration = mink.Configuration(model)
    site_ids = self._physics.bind(tcp_sites).element_id
    self._tasks = [mink.FrameTask(model.site(int(s)).name, "site", position_cost=1.0,
                                  orientation_cost=0.5) for s in site_ids]
    self._posture = mink.PostureTask(model, cost=_POSTURE_COST)
    names = [model.joint(int(j)).name for j in self._physics.bind(arm_joints).element_id]
    self._limits = [mink.ConfigurationLimit(model),
                    mink.VelocityLimit(model, {n: velocity_limit for n in names})]
    self._position_limit = [mink.ConfigurationLimit(model)]
    self._solver = solver
    self.failures = 0   # IK steps with no solution, in which the arm held still
    self.arm_qpos_index = np.array(self._physics.bind(arm_joints).qposadr)
    limited = model.jnt_limited.astype(bool) & (model.jnt_type >= int(mujoco.mjtJoint.mjJNT_SLIDE))
    self._low = np.full(model.nq, -np.inf)
    self._high = np.full(model.nq, np.inf)
    self._low[model.jnt_qposadr[limited]] = model.jnt_range[limited, 0] + 1e-6
    self._high[model.jnt_qposadr[limited]] = model.jnt_range[limited, 1] - 1e-6
    self._qp = ik_qp.DirectQP(model, site_ids, self._tasks, self._posture, *self._limits,
                              damping=_DAMPING)
    # Unlimited hinges (the Jaco's joints 1, 4, 5, 6) turn for ever: their posture target is
    # the home angle's nearest whole-turn equivalent, else a joint wound a turn or two from
    # home (the Jaco's wrist reached 16 rad in one episode) pulls the tool off its target.
    endless = ~model.jnt_limited.astype(bool) & (model.jnt_type == int(mujoco.mjtJoint.mjJNT_HINGE))
    self._endless_qpos = model.jnt_qposadr[endless]
    self._posture_q = None
    self._turns = None   # whole turns of each endless joint the posture target was set for
    self._endless_home = []

  def set_posture(self, q):
    self._posture_q = np.array(q, dtype=float)
    self._posture.set_target(self._posture_q)
    self._qp.set_posture_target(self._posture_q)
    self._turns = None
    self._endless_home = self._posture_q[self._endless_qpos].tolist()

  def posture_near(self, q):
    """The posture target (the robot's home joints), each endless joint turned by whole
    turns to lie nearest its angle in q."""
    target = self._posture_q.copy()
    index = self._endless_qpos
    target[index] += 2 * np.pi * np.round((q[index] - target[index]) / (2 * np.pi))
    return target

  def _wrap_posture(self, q):
    if self._posture_q is None or not len(self._endless_qpos):
      return
    # The turns as posture_near counts them (round half to even, as np.round), in Python
    # floats: they change only when a joint winds past half a turn from its target, and
    # building the target every control step cost the Jaco 10 us of its 50 ms step.
    turns = [(angle - home) / _TURN
             for angle, home in zip(q[self._endless_qpos].tolist(), self._endless_home)]
    turns = [round(t) if math.isfinite(t) else None for t in turns]
    if turns == self._turns and None not in turns:
      return
    self._turns = turns
    target = self.posture_near(q)
    self._posture.set_target(target)
    self._qp.set_posture_target(target)

  def tcp_poses(self, q):
    """Base-frame (position, rotation) of every arm's tool-centre point at joint vector q."""
    self._configuration.update(q)
    poses = []
    for task in self._tasks:
      transform = self._configuration.get_transform_frame_to_world(task.frame_name, "site")
      poses.append((transform.translation(), transform.rotation().as_matrix()))
    return poses

  def step(self, q, targets, dt, velocity_limited=True):
    """Joint vector after one IK step of length dt from q towards `targets` [(pos, rot)]
    (rot a 3x3 matrix, or 9 numbers row-major).

    When the QP has no solution (targets far outside the limits) the arm holds
    still: the step returns q (clipped to the limits) and counts the failure.
    """
    # Limits are enforced on the step, so q must itself lie within them.
    q = self.clip_to_limits(q)
    self._wrap_posture(q)
    x = self._qp.solve(q, targets, dt, velocity_limited)
    if x is None:
      self.failures += 1
      return q
    q += x   # hinge and slide joints: integrating the displacement is adding it
    return q

  def step_mink(self, q, targets, dt, velocity_limited=True):
    """`step` through mink.build_ik and qpsolvers: the reference definition of the step."""
    configuration = self._configuration
    for task, (pos, rot) in zip(self._tasks, targets):
      rot = mink.SO3.from_matrix(np.asarray(rot, dtype=float).reshape(3, 3))
      task.set_target(mink.SE3.from_rotation_and_translation(rot, np.asarray(pos, dtype=float)))
    limits = self._limits if velocity_limited else self._position_limit
    configuration.update(self.clip_to_limits(q))
    self._wrap_posture(configuration.q)
    # build_ik + solve_problem is mink.solve_ik without its per-call limit check
    # (q was just clipped).
    problem = mink.build_ik(configuration, self._tasks + [self._posture], dt, _DAMPING, limits)
    result = qpsolvers.solve_problem(problem, solver=self._solver)
    if not result.found:
      self.failures += 1
      return configuration.q.copy()
    return configuration.integrate(result.x, 1.0)   # x is the step's displacement, not a velocity

  @property
  def limits(self):
    """(low, high) per qpos entry of the ranges the IK keeps in (working ranges applied;
    infinite for unlimited joints), shrunk by 1e-6 rad."""
    return self._low.copy(), self._high.copy()

  def clip_to_limits(self, q):
    """A copy of q within the joint limits (less 1e-6)."""
    return np.minimum(np.maximum(np.asarray(q, dtype=float), self._low), self._high)

  def solve(self, q, targets, iterations=200, tolerance=1e-4):
    """Converged IK (no velocity limit) from seed q: for home poses at build time."""
    for _ in range(iterations):
      q = self.step_mink(q, targets, dt=0.1, velocity_limited=False)
      errors = [np.linalg.norm(t.compute_error(self._configuration)) for t in self._tasks]
      if max(errors) < tolerance:
        break
    return q
