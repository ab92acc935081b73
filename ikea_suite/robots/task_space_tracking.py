"""The task-space modes' tracking: joint targets for the arm's position actuators from the
task-space targets (control_modes.TaskSpaceTargets) by differential IK (ik.DifferentialIK).

Where the optional compiled module can run it (compiled_kernels.fused), one compiled call
per control step does task_space's target update, the frame change and the IK's QP assembly
(DifferentialIK.step_task_space); elsewhere the same numbers come from the separate steps
(TaskSpaceTargets.apply_deltas and in_frame, DifferentialIK.step).
tests/test_fused_step.py checks that both give the same joints to the bit.
"""


class TaskSpaceTracker:
  """Drives a manipulator's position actuators towards its task-space targets."""

  def __init__(self, ik, targets, base_pos, base_rot):
    """`ik`: ik.DifferentialIK; `targets`: control_modes.TaskSpaceTargets (world frame);
    base_pos, base_rot: the robot base's world pose (3 and 9 floats, row-major), the IK
    model's frame."""
    self._ik, self._targets = ik, targets
    self._origin, self._rotation = list(base_pos), list(base_rot)
    self.dt = 0.05   # the control step (s), which bounds each IK step's joint speeds
    self.use_fused = True   # tests turn it off to compare with the separate steps
    self._fused_dt = self._plans = None
    self._rows = None

  def bind(self, tcp_rows, qpos_rows, act_rows, from_ik_rows):
    """The compiled model's rows (mujoco_arrays.compact_index) of the tool sites, of the IK's
    joints in qpos, of the arm actuators, and of the IK joint vector that feeds them."""
    self._rows = tcp_rows, qpos_rows, act_rows, from_ik_rows

  @property
  def fused(self):
    """Whether the fused compiled step tracked the targets at the last step."""
    return self.use_fused and self._plans is not None

  def track(self, arrays, moves=None):
    """Sets ctrl's arm actuators from the targets, after moving them by `moves` (task_space's
    delta actions, (arms, >= 6); None where the caller set them). arrays: this physics'
    mujoco_arrays.ArrayViews with qpos, ctrl and site_xpos."""
    tcp_rows, qpos_rows, act_rows, from_ik_rows = self._rows
    plans = self._fused_plans()
    if plans is not None:
      q = self._ik.step_task_space(*plans, moves, arrays.site_xpos[tcp_rows],
                                   arrays.qpos[qpos_rows])
    else:
      if moves is not None:
        self._targets.apply_deltas(moves, arrays.site_xpos[tcp_rows])
      targets = self._targets.in_frame(self._origin, self._rotation)
      q = self._ik.step(arrays.qpos[qpos_rows], targets, self.dt)   # step copies it
    arrays.ctrl[act_rows] = q[from_ik_rows]

  def _fused_plans(self):
    """(IK plan, target plan) of the fused step, or None where it cannot run."""
    if not self.use_fused:
      return None
    if self._fused_dt != self.dt:   # the IK's velocity bounds depend on the step length
      self._fused_dt = self.dt
      plan = self._ik.fused_plan(self.dt)
      self._plans = plan and (plan, self._targets.fused_plan(self._origin, self._rotation))
    return self._plans
