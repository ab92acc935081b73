"""Which scripted expert drives which robot (the experts' registry), and the subtask it is
working on."""

import dm_env
import numpy as np

from ikea_suite import environment
from ikea_suite.experts import registry


class Expert:
  """A scripted policy plus a reader of its current subtask.

  Args:
    env: an ikea_suite environment whose robot has an expert (ikea_suite.experts.ROBOTS).

  Raises:
    UnknownNameError: the robot has no expert.
    IkeaSuiteError: an arm in a control mode its expert does not drive.
  """

  def __init__(self, env: environment.Environment):
    self.name = registry.expert(env.task.robot.mjcf_model.model).kind
    self._policy = registry.make_expert(env)

  def reset(self) -> None:
    """Resets the policy for a new episode (call after env.reset())."""
    self._policy.reset()

  def __call__(self, timestep: dm_env.TimeStep) -> np.ndarray:
    """The policy's action for `timestep`."""
    return self._policy(timestep)

  def subtask(self) -> tuple[str, int]:
    """(phase name, part index the expert is bringing in; -1 for none)."""
    phase, part = self._policy.subtask
    return phase, -1 if part is None else int(part)


def make(env: environment.Environment) -> Expert:
  """The expert for `env`'s robot.

  Args:
    env: an ikea_suite environment (arms in control_mode "task_space" or "impedance").
  Returns:
    An Expert wrapping ikea_suite.experts.make_expert(env).
  Raises:
    UnknownNameError: the robot has no expert.
    IkeaSuiteError: an arm in a control mode its expert does not drive.
  """
  return Expert(env)
