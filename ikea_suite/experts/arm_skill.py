"""What a one-arm skill that runs as a fixed sequence of steps keeps (turn_over.TurnOver,
stand_up.StandUp): the arm, the surface, the route over the assembly, how long the
fingers take to close and open, how long a step may take, and where in its sequence it
is. A skill names its steps in an enum, in the order they run, with OPEN (the fingers
let go) and DONE among them; on OPEN it sets up where the hand backs out to
(`_set_out`).
"""

import enum


class SteppedSkill:
  """A skill's steps and their bookkeeping; subclasses set STEPS and write `reset`,
  `_set_out` and the control step itself.

  Args:
    env: the environment.
    arm: the arm's index.
    surface: height (m) of the surface the parts lie or the assembly stands on.
    route: the arm's clearance.AssemblyClearance.
    close_steps: control steps the fingers take to close.
    open_steps: control steps the fingers take to open.
    step_budget: control steps a step may take before the skill gives up.
  """

  STEPS: type[enum.Enum]

  def __init__(self, env, arm, surface, route, close_steps=8, open_steps=6, step_budget=250):
    self._env, self._arm, self._surface, self._route = env, arm, surface, route
    self._close_steps, self._open_steps, self._budget = close_steps, open_steps, step_budget
    self.reset()

  def reset(self):
    """Forgets the episode's runs of the skill."""
    raise NotImplementedError

  def _set_out(self):
    """Sets where the hand backs out to once it lets go."""
    raise NotImplementedError

  def _fingers_done(self):
    """Whether the fingers have had their time to close (CLOSE) or open (any other step)."""
    return self._count >= (self._close_steps if self.step == self.STEPS.CLOSE
                           else self._open_steps)

  def _next(self):
    """On to the next step, its count of control steps at 0."""
    order = list(self.STEPS)
    self.step = order[order.index(self.step) + 1]
    self._count = 0
    if self.step == self.STEPS.OPEN:
      self._set_out()
