"""A composer.Environment that checks actions and steps physics in one call per control step."""

import logging
import math

import dm_env
import mujoco
import numpy as np
from dm_control import composer
from dm_control.rl import control

from ikea_suite import composer_internals
from ikea_suite import errors
from ikea_suite import observations

_MID, _LAST = dm_env.StepType.MID, dm_env.StepType.LAST   # looked up once, not every step

# Resets retried when the parts cannot be laid out (composer's EpisodeInitializationError):
# load() accepts furniture that fits the work table in at least half its layouts, so ten
# tries fail together at most once in 2**10 resets.
RESET_ATTEMPTS = 10


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
    if composer_internals.warnings_raise(physics):   # not within suppress_physics_errors()
      raise control.PhysicsError(message)
    logging.warning(message)


def raw_handles(physics):
  """(model, data, warning counts) for `advance`, or None where it must use physics.step."""
  model, data = physics.model.ptr, physics.data.ptr
  if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
    return None
  return model, data, data.warning.number   # a live view of the counts


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

  Deciding and doing this reads composer's private state (composer_internals); where a
  dm_control release has changed it, the environment runs composer's own step instead.
  """

  def __init__(self, task, **kwargs):
    kwargs.setdefault("raise_exception_on_physics_error", False)
    kwargs.setdefault("strip_singleton_obs_buffer_dim", True)
    # Nothing in an episode changes the MJCF: compile once, and let reset restore
    # state, variations and placement on the same Physics (and its render contexts).
    kwargs.setdefault("recompile_mjcf_every_episode", False)
    kwargs.setdefault("max_reset_attempts", RESET_ATTEMPTS)
    super().__init__(task, **kwargs)
    self._time_limit_s = kwargs.get("time_limit", float("inf"))   # composer keeps its own, private
    self._action_names = list(task.action_names)
    self._checked_spec = None
    self._termination_reason = None
    self._reset_due = True   # composer's own flag is private: this one follows it
    self._internals = None   # composer_internals.Internals of this episode, or None
    self._trivial_substeps = False
    self._direct = None      # composer_internals.direct_readers of this episode
    self._raw = None   # (physics.data, raw_handles(physics)) of the physics stepped last
    self._action_bounds = None

  @property
  def termination_reason(self):
    """Why the last episode ended early: None, "complete", or the MuJoCo warnings that
    ended it (any warning, such as a diverging state or a full contact buffer, ends the
    episode with discount 0 rather than going on with a broken simulation)."""
    return self._termination_reason

  def reset(self):
    """Starts an episode; raises EpisodeStartError when it cannot start (composer's
    EpisodeInitializationError, or a MuJoCo warning on the first state)."""
    self._termination_reason = None
    try:
      timestep = super().reset()
    except (composer.EpisodeInitializationError, control.PhysicsError) as e:
      raise errors.EpisodeStartError(f"the episode could not start: {e}") from e
    # A reset may recompile the physics and always rebuilds the updater's observables.
    self._internals = internals = composer_internals.read(self)
    if internals is not None:
      self._trivial_substeps = composer_internals.substep_hooks_trivial(internals)
      self._direct = (composer_internals.direct_readers(internals)
                      if self._trivial_substeps else None)
    self._reset_due = False
    return timestep

  @property
  def time_limit(self):
    """Seconds of simulated time after which an episode is truncated."""
    return self._time_limit_s

  def action_spec(self):
    if self._checked_spec is None:  # fixed for the task's lifetime; built once
      self._checked_spec = super().action_spec()
      self._action_bounds = (self._checked_spec.minimum, self._checked_spec.maximum)
    return self._checked_spec

  def observation_spec(self):
    """Composer's specs, bounded and typed by the observation vocabulary (observations.py)."""
    return observations.bounded_specs(super().observation_spec(),
                                      len(self.task.furniture.parts))

  def step(self, action):
    """Checks `action` (check_action), then steps; on a fresh environment or after the
    last step of an episode the (checked) action is ignored and the environment resets,
    as composer does."""
    action = check_action(action, self.action_spec(), self._action_names, self._action_bounds)
    if self._reset_due:
      return self.reset()   # as composer's step does at an episode's end
    internals = self._internals
    if internals is None:
      return self._composer_step(action)
    physics, proxy, random_state = internals.physics, internals.proxy, internals.random_state
    internals.hooks.before_step(proxy, action, random_state)
    updater = internals.updater
    n_sub_steps = internals.n_sub_steps
    # Batched: all substeps in one call when nothing needs Python between them;
    # otherwise composer's own loop of substep hooks and observation updates.
    direct = self._direct
    if direct is None:
      updater.prepare_for_next_control_step()
      batched = self._trivial_substeps and composer_internals.nothing_due_before_last_substep(
          internals)
    else:
      batched = True   # plain observables are due at the last substep only
    try:
      if batched:
        data = physics.data
        if self._raw is None or self._raw[0] is not data:   # recompiled or reloaded
          self._raw = (data, raw_handles(physics))
        advance(physics, n_sub_steps, self._raw[1])
        if direct is None:
          composer_internals.skip_updates(internals, n_sub_steps - 1)
      else:
        for i in range(n_sub_steps):
          internals.substep(action)
          if i < n_sub_steps - 1:
            updater.update()
      divergent = False
    except control.PhysicsError as e:
      divergent = True
      self._termination_reason = str(e)
      logging.warning("ikea_suite: episode ended at t=%.3f s: %s", physics.time(), e)
    internals.hooks.after_step(proxy, random_state)
    if direct is None:
      updater.update()
    else:
      observation = {name: read() for name, read in direct}
    task = internals.task
    if divergent:
      reward, discount, last = 0.0, 0.0, True
    else:
      reward = task.get_reward(proxy)
      discount = task.get_discount(proxy)
      complete = task.should_terminate_episode(proxy)
      if complete:
        self._termination_reason = "complete"
      last = complete or physics.time() >= self._time_limit_s
    if direct is None:
      observation = updater.get_observation()
    if last:
      self._reset_due = True
      return dm_env.TimeStep(_LAST, reward, discount, observation)
    return dm_env.TimeStep(_MID, reward, discount, observation)

  def _composer_step(self, action):
    """composer's own step of a checked action, with the episode's end and its reason noted."""
    timestep = super().step(action)
    if timestep.last():
      self._reset_due = True
      if self.task.should_terminate_episode(self.physics):
        self._termination_reason = "complete"
      elif timestep.discount == 0.0:   # composer logged the warnings that ended it
        self._termination_reason = "Physics state is invalid (MuJoCo warnings, logged)"
    return timestep
