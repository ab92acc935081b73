"""Baxter's expert: the two arms take turns bringing parts, each to its own side.

Each arm has its own single-arm controller (experts/single_arm.py). Before
a new part is fetched, the part's side of the torso chooses the arm: the
right arm fetches parts on the right, the left arm those on the left, so
each arm reaches across the work area as little as possible. The arm not
working goes back to its home pose, out of the other's way. Both act only
through the action vector.
"""

import dm_env
import numpy as np

from ikea_suite.experts import arm_motion
from ikea_suite.experts import single_arm
from ikea_suite.experts import top_down_grasp


class TwoArmExpert:
  """A policy for a two-arm robot in task_space mode; call with a TimeStep.

  Args:
    env: an environment whose robot has two arms (right first).

  Raises:
    IkeaSuiteError: the robot's control mode is not one of CONTROL_MODES.
  """

  CONTROL_MODES = single_arm.ArmAssemblyController.CONTROL_MODES   # each arm's expert's

  def __init__(self, env):
    self._env = env
    self._robot = env.task.robot
    # A panel taken by its top edge from a rack beside the torso is lifted slowly: at full
    # speed the hand swung 4 cm sideways on the way up and a 6 mm box wall pivoted out of
    # the fingers (box_open_kuggis, tuning seed 1000).
    self._arms = [single_arm.ArmAssemblyController(
        env, arm=i, edge_lift_speed=top_down_grasp.HANGING_SPEED) for i in range(2)]
    self._idle_servos = [arm_motion.PoseServo() for _ in range(2)]
    self.reset()

  def reset(self) -> None:
    for controller, servo in zip(self._arms, self._idle_servos):
      controller.reset()
      servo.reset()
    self._active = 0
    self.arms_used = set()

  @property
  def active_arm(self) -> int:
    """The arm (0 right, 1 left) fetching the current part; the other waits at home."""
    return self._active

  @property
  def phase(self) -> single_arm.Phase:
    """The active arm's controller phase."""
    return self._arms[self._active].phase

  @property
  def subtask(self) -> tuple[str, int | None]:
    """The active arm's (phase name, part being brought in; None between parts)."""
    return self._arms[self._active].subtask

  @property
  def job(self) -> tuple[int, int] | None:
    """The active arm's (connector pair, moving part), or None between parts."""
    return self._arms[self._active].job

  def _side(self, part):
    """0 (right arm) for a part right of the torso, 1 (left) otherwise."""
    positions, _ = self._env.task.furniture.part_poses(self._env.physics)
    base_pos, base_rot = self._robot.base_pose
    local = base_rot.T @ (positions[part] - base_pos)
    return 0 if local[1] < 0 else 1

  def __call__(self, timestep: dm_env.TimeStep | None = None) -> np.ndarray:
    """The action (both arms, then connect) from privileged state; `timestep` may be None."""
    controller = self._arms[self._active]
    action = controller(timestep)
    job = controller.job
    if job is not None and controller.job_just_chosen:   # a part chosen, not yet approached
      side = self._side(job[1])
      if side != self._active:
        other = self._arms[side]
        other.take_over()
        self._active = side
        controller, action = other, other(timestep)
    self.arms_used.add(self._active)
    idle = 1 - self._active
    home_pos, home_rot = self._robot.home_tcp_poses()[idle]
    base = idle * self._robot.actions_per_arm
    action[base:base + 6] = self._idle_servos[idle](self._robot, self._env.physics, idle,
                                                    home_pos, home_rot)
    action[base + 6] = -1.0
    return action
