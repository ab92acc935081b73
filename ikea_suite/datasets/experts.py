"""Which scripted expert drives which robot, and the subtask it is working on."""

import dm_env
import numpy as np

from ikea_suite import environment
from ikea_suite import errors
from ikea_suite import experts as experts_lib

# robot name -> expert kind (ikea_suite.experts.make_expert builds it): the Cursor
# oracle, the single-arm controller, and Baxter's two-arm expert.
EXPERTS = {"cursor": "cursor_oracle", "sawyer": "arm_controller", "panda": "arm_controller",
           "jaco": "arm_controller", "baxter": "two_arm"}


class Expert:
  """A scripted policy plus a reader of its current subtask.

  Args:
    env: an ikea_suite environment whose robot has an expert (`EXPERTS`).

  Raises:
    UnknownNameError: the robot has no expert yet.
  """

  def __init__(self, env: environment.Environment):
    robot = env.task.robot.mjcf_model.model
    if robot not in EXPERTS:
      raise errors.UnknownNameError("robot with an expert", robot, EXPERTS)
    self.name = EXPERTS[robot]
    self._policy = experts_lib.make_expert(env)

  def reset(self) -> None:
    """Resets the policy for a new episode (call after env.reset())."""
    self._policy.reset()

  def __call__(self, timestep: dm_env.TimeStep) -> np.ndarray:
    """The policy's action for `timestep`."""
    return self._policy(timestep)

  def subtask(self) -> tuple[str, int]:
    """(phase name, part index the expert is bringing in; -1 for none)."""
    if self.name == "cursor_oracle":
      phase, part = self._policy.subtask
    else:
      phase = self._policy.phase.value
      job = self._policy.job
      part = None if job is None else job[1]
    return phase, -1 if part is None else int(part)


def make(env: environment.Environment) -> Expert:
  """The expert for `env`'s robot.

  Args:
    env: an ikea_suite environment (arms in control_mode "task_space" or "impedance").
  Returns:
    An Expert wrapping ikea_suite.experts.make_expert(env).
  Raises:
    UnknownNameError: the robot has no expert.
    IkeaSuiteError: an arm in a mode other than task_space or impedance.
  """
  return Expert(env)
