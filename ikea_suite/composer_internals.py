"""The private state of dm_control's composer that ikea_suite.environment reads, in one place.

environment.Environment runs a control step's physics substeps in one MuJoCo call where
composer would run Python hooks and an observation update after each of them for nothing,
and reads plain observables straight from their callables instead of through composer's
buffers. To know that it may, and to leave composer's bookkeeping as composer's own step
would, it needs state that dm_control 1.0.50 keeps private:

- composer.Environment (the base class): its hooks, physics, substep count, observation
  updater and one substep (`_substep`);
- composer's hooks (`_EnvironmentHooks`): which entity and extra hooks run at each substep;
- the observation updater (`observation.Updater`): its step counter, its enabled observables
  in order and by name, whether their structure is nested, and each one's buffer size,
  delay, update interval and schedule;
- the physics (`mujoco.Physics`): whether a new MuJoCo warning raises (not within
  `suppress_physics_errors()`).

`read(env)` fetches them after each reset and checks every name and type it relies on
(`problems`); where one is not as expected (a dm_control other than the one pyproject.toml
pins) it returns None and the environment runs composer's own step: the same episodes,
slower. tests/test_composer_internals.py pins every name and type.
"""

import collections
import collections.abc
import logging
import numbers

import numpy as np
from dm_control import mujoco as dm_mujoco
from dm_control.composer import environment as composer_environment
from dm_control.composer.observation import updater as updater_lib
from dm_control.composer.observation.observable import base as observable_base

from ikea_suite import mujoco_arrays

_SUBSTEP_HOOKS = ("_before_substep", "_after_substep")

# What `read` relies on: (dotted path from the environment, the types its value may have).
PINNED = (
    ("_hooks", getattr(composer_environment, "_EnvironmentHooks", None)),
    ("_hooks._before_substep.entity_hooks", list),
    ("_hooks._before_substep.extra_hooks", list),
    ("_hooks._after_substep.entity_hooks", list),
    ("_hooks._after_substep.extra_hooks", list),
    ("_physics", dm_mujoco.Physics),
    ("_physics._warnings_cause_exception", bool),
    ("_n_sub_steps", numbers.Integral),
    ("_substep", collections.abc.Callable),
    ("_observation_updater", updater_lib.Updater),
    ("_observation_updater._step_counter", numbers.Integral),
    ("_observation_updater._is_nested", bool),
    ("_observation_updater._enabled_structure", (dict, list, tuple)),
    ("_observation_updater._enabled_list", (collections.abc.ValuesView, list)),
)
# And of every enabled observable in the updater's list: (attribute, types). Buffer size,
# delay and update interval may be numbers or callables (variations), so any type will do.
PINNED_PER_OBSERVABLE = (
    ("observable", observable_base.Observable),
    ("observation_callable", collections.abc.Callable),
    ("buffer_size", object),
    ("delay", object),
    ("update_interval", object),
    ("update_schedule", collections.deque),
)


class Internals:
  """One environment's composer state, as its batched step reads it (fetched by `read`)."""

  __slots__ = ("hooks", "physics", "proxy", "random_state", "task", "n_sub_steps", "updater",
               "substep")

  def __init__(self, env):
    self.hooks = env._hooks
    self.physics = env._physics
    self.proxy = env.physics                  # the weak proxy composer hands to every hook
    self.random_state = env.random_state
    self.task = env.task
    self.n_sub_steps = env._n_sub_steps
    self.updater = env._observation_updater
    self.substep = env._substep               # one physics substep with its hooks


def _mismatch(owner, path, kinds):
  """A line saying why `path` (dotted, from `owner`) is missing or not of `kinds`, or None."""
  value = owner
  for name in path.split("."):
    if not hasattr(value, name):
      return f"{path}: {type(value).__name__} has no attribute {name!r}"
    value = getattr(value, name)
  if kinds is None or not isinstance(value, kinds):
    expected = "a class dm_control no longer has" if kinds is None else kinds
    return f"{path}: {type(value).__name__}, expected {expected}"
  return None


def problems(env) -> list[str]:
  """What is not as this module expects in `env`'s private state (PINNED, after a reset).

  Args:
    env: a composer.Environment that has been reset.
  Returns:
    One line per missing or mistyped attribute; empty when `read` may use them.
  """
  found = [_mismatch(env, path, kinds) for path, kinds in PINNED]
  if found[-1] is None:
    for enabled in env._observation_updater._enabled_list:
      found += [_mismatch(enabled, name, kinds) for name, kinds in PINNED_PER_OBSERVABLE]
  return [line for line in found if line is not None]


_warned = []   # the problems already logged, so that each reset does not log them again


def read(env) -> Internals | None:
  """`env`'s composer state for the batched step, or None where `problems` finds any (logged
  once per process).

  Args:
    env: a composer.Environment that has been reset.
  Returns:
    An Internals, or None: then the environment runs composer's own step.
  """
  found = problems(env)
  if not found:
    return Internals(env)
  if found not in _warned:
    _warned.append(found)
    logging.warning("ikea_suite: this dm_control's composer differs from the one ikea_suite "
                    "reads (%s); its environments run composer's own step, slower",
                    "; ".join(found))
  return None


def substep_hooks_trivial(internals: Internals) -> bool:
  """Whether no entity and no extra hook runs before or after a physics substep."""
  return not any(getattr(internals.hooks, name).entity_hooks
                 or getattr(internals.hooks, name).extra_hooks for name in _SUBSTEP_HOOKS)


def direct_readers(internals: Internals) -> list | None:
  """[(name, callable giving the observation)] when every enabled observable is plain, else
  None.

  A plain observable (one-entry buffer, no delay, no aggregator, update interval 1) shows
  after each control step a copy of its value at the step's last substep, so reading it then
  is what composer's updater returns. Each callable gives such a copy (np.array copies, as
  the buffer does on insert), or the value itself where the observable makes a new array on
  every read (mujoco_arrays.FreshGeneric, uncorrupted).
  """
  updater = internals.updater
  entries = updater._enabled_structure
  if updater._is_nested or not all(
      e.buffer_size == 1 and e.delay == 0 and e.update_interval == 1
      and e.observable.aggregator is None for e in entries.values()):
    return None
  return [(name, _reader(e)) for name, e in entries.items()]


def _reader(enabled):
  read = enabled.observation_callable
  if isinstance(enabled.observable, mujoco_arrays.FreshGeneric) and (
      enabled.observable.corruptor is None):
    return read
  return lambda: np.array(read())


def nothing_due_before_last_substep(internals: Internals) -> bool:
  """Whether no enabled observable needs an update before the coming control step's last
  substep (true for the default observables, which update once per control step); call
  after the updater's prepare_for_next_control_step."""
  first_due = internals.updater._step_counter + internals.n_sub_steps
  return all(not e.update_schedule or e.update_schedule[0][0] >= first_due
             for e in internals.updater._enabled_list)


def skip_updates(internals: Internals, count: int) -> None:
  """Counts `count` substeps at which the updater had nothing to do as done, as its update()
  would have."""
  internals.updater._step_counter += count


def warnings_raise(physics) -> bool:
  """Whether a new MuJoCo warning raises PhysicsError (False within the physics'
  suppress_physics_errors())."""
  return physics._warnings_cause_exception
