"""A composer.Environment that checks actions and steps physics in one call per control step."""

import logging
import math

import mujoco
import numpy as np
import dm_env
from dm_control import composer
from dm_control.rl import control

from ikea_suite import errors
from ikea_suite import fresh_observable


def check_action(action, spec, names, bounds=None):
  """Returns the action as a float array clipped to the spec; raises ActionError if malformed.

  An action is an array (or a sequence) of real numbers, of float or integer dtype, with
  the spec's shape and finite entries. Booleans (True is not a force), complex numbers
  (numpy would drop the imaginary part), strings (numpy would parse "0.5") and other
  objects are refused, not converted.

  `bounds`: (minimum, maximum) arrays of the spec, when the caller holds them (read
  from the spec's properties every step, they cost a control step more than the check).
  """
  given_array = isinstance(action, np.ndarray)
  try:
    array = action if given_array else np.asarray(action)
  except (TypeError, ValueError):   # e.g. a ragged list
    array = None
  holds_bool = not given_array and _holds_bool(action)
  if array is None or array.dtype.kind not in "fiu" or holds_bool:
    if given_array:
      what = f"an array of dtype {array.dtype}"
    elif holds_bool:
      what = f"a {type(action).__name__} holding a bool"
    else:
      what = f"a {type(action).__name__}" + (
          f" of {array.dtype} values" if array is not None and array.ndim else "")
    raise errors.ActionError(
        f"action must be numeric: an array of real numbers (float or integer dtype), got "
        f"{what}; booleans, complex numbers and strings are not actions")
  array = array.astype(np.float64, copy=False)
  if array.shape != spec.shape:
    raise errors.ActionError(
        f"action has shape {array.shape}, expected {spec.shape}: ({', '.join(names)})")
  # One sum finds NaN and infinity (it is then not finite); entries so large that the sum
  # overflows are looked at one by one before anything is refused. (Python floats: numpy
  # warns on overflow.)
  if not math.isfinite(sum(array.tolist())):
    bad = ~np.isfinite(array)
    if bad.any():
      entries = ", ".join(f"{names[i]}={array[i]}" for i in np.flatnonzero(bad))
      raise errors.ActionError(f"action has non-finite entries: {entries}")
  low, high = bounds if bounds is not None else (spec.minimum, spec.maximum)
  return np.minimum(np.maximum(array, low), high)


def _holds_bool(sequence):
  """Whether a (flat) list or tuple given as an action holds a bool, which numpy would
  turn into 0.0 or 1.0 beside the numbers."""
  return isinstance(sequence, (list, tuple)) and any(
      isinstance(v, (bool, np.bool_)) for v in sequence)


def advance(physics, nstep, raw=None):
  """physics.step(nstep) with dm_control's default (legacy) stepping and its check for new
  MuJoCo warnings, calling MuJoCo directly: dm_control's wrappers and context manager
  around the same calls took about 25 us of Python per control step (cProfile, Sawyer).

  `raw`: (mujoco.MjModel, mujoco.MjData, warning counts) of `physics`, from raw_handles.
  Falls back to physics.step where dm_control would do anything else (RK4, non-legacy).
  Raises control.PhysicsError as physics.step does.
  """
  if raw is None or not physics.legacy_step:
    physics.step(nstep)
    return
  model, data, warnings = raw
  before = warnings.tolist()   # a few Python ints: cheaper to keep and compare than arrays
  mujoco.mj_step2(model, data)   # finishes the step whose mj_step1 ran last time
  if nstep > 1:
    mujoco.mj_step(model, data, nstep - 1)
  mujoco.mj_step1(model, data)   # positions and velocities up to date for the observers
  if warnings.tolist() != before:   # counts only grow within a step
    names = ", ".join(np.compress(warnings > np.array(before),
                                  list(mujoco.mjtWarning.__members__)))
    message = f"Physics state is invalid. Warning(s) raised: {names}"
    if physics._warnings_cause_exception:   # False within physics.suppress_physics_errors()
      raise control.PhysicsError(message)
    logging.warning(message)


def raw_handles(physics):
  """(model, data, warning counts) for `advance`, or None where it must use physics.step."""
  model, data = physics.model.ptr, physics.data.ptr
  if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
    return None
  return model, data, data.warning.number   # a live view of the counts


def _copying_reader(enabled):
  """A callable giving an enabled observable's value as composer's buffer would hold it: a
  copy (np.array copies, as the buffer does on insert), or the value itself where the
  observable makes a new array on every read (fresh_observable.FreshGeneric, uncorrupted)."""
  read = enabled.observation_callable
  if isinstance(enabled.observable, fresh_observable.FreshGeneric) and (
      enabled.observable.corruptor is None):
    return read
  return lambda: np.array(read())


class Environment(composer.Environment):
  """composer.Environment with validated, clipped actions and batched substeps.

  composer runs Python hooks and an observation update after every physics
  substep. When no entity needs per-substep hooks and no observable is due
  before the last substep, this class advances all substeps in one
  call (`advance`: physics.step(n)'s integration, without its wrappers); otherwise it runs
  composer's loop. When moreover every observable is plain (one-entry buffer,
  no delay, no aggregator, sampled every substep: composer's defaults), the
  observation is read straight from the observables after the step, the very
  values composer's buffers would hand back, without scheduling and buffering
  them. Either way a MuJoCo warning ends the episode with a reason.
  """

  def __init__(self, task, **kwargs):
    kwargs.setdefault("raise_exception_on_physics_error", False)
    kwargs.setdefault("strip_singleton_obs_buffer_dim", True)
    # Nothing in an episode changes the MJCF: compile once, and let reset restore
    # state, variations and placement on the same Physics (and its render contexts).
    kwargs.setdefault("recompile_mjcf_every_episode", False)
    super().__init__(task, **kwargs)
    self._action_names = list(task.action_names)
    self._checked_spec = None
    self._termination_reason = None
    self._trivial_substeps = None
    self._plain_observables = None
    self._raw = None   # (physics.data, raw_handles(physics)) of the physics stepped last
    self._action_bounds = None

  @property
  def termination_reason(self):
    """Why the last episode ended early: None, "complete", or the MuJoCo warnings that
    ended it (any warning, such as a diverging state or a full contact buffer, ends the
    episode with discount 0 rather than going on with a broken simulation)."""
    return self._termination_reason

  def reset(self):
    self._termination_reason = None
    self._plain_observables = None   # the updater rebuilds its observables on reset
    return super().reset()

  @property
  def time_limit(self):
    """Seconds of simulated time after which an episode is truncated."""
    return self._time_limit

  def action_spec(self):
    if self._checked_spec is None:  # fixed for the task's lifetime; built once
      self._checked_spec = super().action_spec()
      self._action_bounds = (self._checked_spec.minimum, self._checked_spec.maximum)
    return self._checked_spec

  def _recompile_physics_and_update_observables(self):
    super()._recompile_physics_and_update_observables()
    self._trivial_substeps = None   # hooks are refreshed only here
    self._plain_observables = None

  def _substep_hooks_trivial(self):
    if self._trivial_substeps is None:
      self._trivial_substeps = not any(getattr(self._hooks, "_" + name).entity_hooks
                                       or getattr(self._hooks, "_" + name).extra_hooks
                                       for name in ("before_substep", "after_substep"))
    return self._trivial_substeps

  def _nothing_due_before_last_substep(self):
    """Whether no enabled observable needs an update before the control step's last
    substep (true for the default observables, which update once per control step).

    Reads dm_control 1.0.50's observation updater internals (`_step_counter`,
    `_enabled_list`); tests/test_environment_internals.py pins them.
    """
    updater = self._observation_updater
    first_due = updater._step_counter + self._n_sub_steps
    return all(not e.update_schedule or e.update_schedule[0][0] >= first_due
               for e in updater._enabled_list)

  def _direct_observables(self):
    """[(name, callable giving the observation (_copying_reader))] when every enabled
    observable is plain, else None.

    A plain observable (one-entry buffer, no delay, no aggregator, update interval 1)
    shows after each control step a copy of its value at the step's last substep, so
    reading it then is what composer's updater returns. Reads the updater's
    `_is_nested` and `_enabled_structure` (tests/test_environment_internals.py pins them).
    """
    if self._plain_observables is None:
      updater = self._observation_updater
      plain = not updater._is_nested and all(
          e.buffer_size == 1 and e.delay == 0 and e.update_interval == 1
          and e.observable.aggregator is None for e in updater._enabled_structure.values())
      self._plain_observables = (
          [(name, _copying_reader(e)) for name, e in updater._enabled_structure.items()]
          if plain else False)
    return self._plain_observables or None

  def step(self, action):
    """Checks `action` (check_action), then steps; on a fresh environment or after the
    last step of an episode the (checked) action is ignored and the environment resets,
    as composer does."""
    action = check_action(action, self.action_spec(), self._action_names, self._action_bounds)
    if self._reset_next_step:
      return super().step(action)
    self._hooks.before_step(self._physics_proxy, action, self._random_state)
    updater = self._observation_updater
    # Batched: all substeps in one call when nothing needs Python between them;
    # otherwise composer's own loop of substep hooks and observation updates.
    direct = self._direct_observables() if self._substep_hooks_trivial() else None
    if direct is None:
      updater.prepare_for_next_control_step()
      batched = self._substep_hooks_trivial() and self._nothing_due_before_last_substep()
    else:
      batched = True   # plain observables are due at the last substep only
    try:
      if batched:
        physics = self._physics
        data = physics.data
        if self._raw is None or self._raw[0] is not data:   # recompiled or reloaded
          self._raw = (data, raw_handles(physics))
        advance(physics, self._n_sub_steps, self._raw[1])
        if direct is None:
          updater._step_counter += self._n_sub_steps - 1   # the updates that had nothing due
      else:
        for i in range(self._n_sub_steps):
          self._substep(action)
          if i < self._n_sub_steps - 1:
            updater.update()
      divergent = False
    except control.PhysicsError as e:
      divergent = True
      self._termination_reason = str(e)
      logging.warning("ikea_suite: episode ended at t=%.3f s: %s", self._physics.time(), e)
    self._hooks.after_step(self._physics_proxy, self._random_state)
    if direct is None:
      updater.update()
    else:
      observation = {name: read() for name, read in direct}
    if divergent:
      reward, discount, last = 0.0, 0.0, True
    else:
      reward = self._task.get_reward(self._physics_proxy)
      discount = self._task.get_discount(self._physics_proxy)
      complete = self._task.should_terminate_episode(self._physics_proxy)
      if complete:
        self._termination_reason = "complete"
      last = complete or self._physics.time() >= self._time_limit
    if direct is None:
      observation = updater.get_observation()
    if last:
      self._reset_next_step = True
      return dm_env.TimeStep(dm_env.StepType.LAST, reward, discount, observation)
    return dm_env.TimeStep(dm_env.StepType.MID, reward, discount, observation)
