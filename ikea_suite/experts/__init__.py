"""Scripted experts: policies that assemble furniture through the action vector a learner sends.

    env = ikea_suite.load("table_four_leg_lack", "sawyer", scale=0.5, seed=1000)
    expert = ikea_suite.experts.make_expert(env)
    expert.reset(); timestep = env.reset()
    while not timestep.last():
      timestep = env.step(expert(timestep))

They read privileged state (part and connector poses, the assembly graph)
but move parts only with the robot: the Cursor oracle (experts/cursor_oracle.py),
the single-arm controller for Sawyer, Panda and Jaco (experts/single_arm.py),
and Baxter's two-arm expert (experts/bimanual.py). `supported(robot)` lists
the furniture an expert assembled in at least 8 of 10 fresh seeds
(experts/supported.py, measured by benchmarks/expert_sweep.py).
"""

from typing import Any, Callable

from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.experts import bimanual
from ikea_suite.experts import cursor_oracle
from ikea_suite.experts import single_arm
from ikea_suite.experts import supported as supported_lib
from ikea_suite.props import catalog
from ikea_suite.robots import control_modes

ROBOTS = tuple(supported_lib.SUPPORTED)


def supported(robot: str) -> tuple[str, ...]:
  """Furniture names `robot`'s expert assembles (measured; see experts/supported.py).

  Args:
    robot: a robot name.
  Returns:
    Sorted furniture names.
  Raises:
    UnknownNameError: a robot with no expert.
  """
  if robot not in supported_lib.SUPPORTED:
    raise errors.UnknownNameError("robot with an expert", robot, ROBOTS)
  table = supported_lib.SUPPORTED[robot]
  return tuple(catalog.names()) if table is None else tuple(sorted(table))


def supported_scale(robot: str, furniture: str) -> float:
  """The scale `robot`'s expert assembles `furniture` at (1.0 for the Cursor).

  Args:
    robot: a robot name with an expert (ROBOTS).
    furniture: a furniture name in supported(robot).
  Returns:
    The load(scale=...) factor the expert's measurement used.
  Raises:
    UnknownNameError: the pair is not supported.
  """
  if furniture not in supported(robot):
    raise errors.UnknownNameError(f"furniture the {robot} expert assembles", furniture,
                                  supported(robot))
  table = supported_lib.SUPPORTED[robot]
  return 1.0 if table is None else float(table[furniture])


def supported_pairs() -> tuple[tuple[str, str], ...]:
  """Every (furniture, robot) pair with an expert that assembles it.

  Returns:
    (furniture, robot) pairs, robot-major in ROBOTS order.
  """
  return tuple((f, r) for r in ROBOTS for f in supported(r))


def make_expert(env: environment.Environment,
                require_supported: bool = False) -> Callable[[Any], Any]:
  """The scripted expert for `env`'s robot: a callable TimeStep -> action with reset().

  Args:
    env: an ikea_suite environment (arms in control_mode "task_space" or "impedance").
    require_supported: raise unless the (furniture, robot) pair is in supported().
  Returns:
    A policy object with reset() and __call__(timestep).
  Raises:
    UnknownNameError: a robot with no expert, or (require_supported) an unsupported pair.
    IkeaSuiteError: an arm in a mode other than task_space or impedance.
  """
  robot = env.task.robot
  name = robot.mjcf_model.model
  if name not in supported_lib.SUPPORTED:
    raise errors.UnknownNameError("robot with an expert", name, ROBOTS)
  if require_supported:
    supported_scale(name, env.task.furniture.name)
  if name == "cursor":
    return cursor_oracle.CursorOracle(env)
  if robot.control_mode not in control_modes.DELTA_TARGETS:
    raise errors.IkeaSuiteError(
        f"the {name} expert drives the arm by task-space moves, in control_mode "
        f"{' or '.join(map(repr, control_modes.DELTA_TARGETS))}, got "
        f"control_mode={robot.control_mode!r}")
  if robot.num_arms == 2:
    return bimanual.TwoArmExpert(env)
  return single_arm.ArmAssemblyController(env)
