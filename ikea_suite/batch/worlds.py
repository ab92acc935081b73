"""What every batched environment shares: the MJX implementation and its float precision,
the device model and one world's data with Warp's buffers sized and watched, and the
jitted, vmapped forms of a subclass's single-world `reset(rng)` and `step(state, action)`.

A subclass (env.BatchAssembly for the Cursor, arm_env.BatchArmAssembly for an arm) sets
`_batch_model` (a model.BatchModel), `_settings` and `_tables`, calls `_put` with its
compiled model, and defines `reset`, `step`, `action_size` and `buffer_sizing`. Its State
is a NamedTuple with the fields data, reward, done, metrics and info (plus its own).
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np

from ikea_suite import errors
from ikea_suite.batch import backend
from ikea_suite.batch import contact_buffers


class BatchWorlds:
  """Many worlds of one task, stepped by MJX.

  Args:
    impl: "warp", "jax" or None (warp on a GPU with warp-lang, else jax).
    num_worlds: worlds stepped together (sizes Warp's shared contact buffer; unused by jax).
    buffer_sizes: (nconmax, njmax) per world for Warp instead of the measured sizing.
  """

  def __init__(self, impl=None, num_worlds=None, buffer_sizes=None):
    self._impl = backend.check_impl(impl)
    self._num_worlds = num_worlds
    self._buffer_sizes = buffer_sizes

  def _put(self, model):
    """Puts `model` on the device with Warp's buffers sized (buffer_sizing) and watched."""
    sizing = self.buffer_sizing if self._impl == "warp" else None   # JAX: no fixed buffers
    self._mx, self._data0 = backend.put(model, self._impl, sizing, num_worlds=self._num_worlds)
    self.overflow_watch = contact_buffers.OverflowWatch(sizing, self._num_worlds)
    self._reset_batch = jax.jit(jax.vmap(self.reset))
    self._step_batch = jax.jit(jax.vmap(self.step))

  def _given_sizing(self):
    """contact_buffers.Sizing of the sizes given by hand, or None."""
    if self._buffer_sizes is None:
      return None
    return contact_buffers.given(self._buffer_sizes)

  def precision(self):
    """Context in which this environment's functions must be traced and called: float64 for
    MJX's JAX implementation, float32 (jax's default) for Warp.

    MJX's JAX solver with elliptic cones (physics_settings) is unstable in float32 on these
    contacts: a table's legs lying on the floor reached 52 m/s, then NaN, within 0.4 s, where
    MuJoCo (float64) and the same MJX code in float64 hold them still (< 1e-6 m/s).
    `reset_batch` and `step_batch` enter it themselves; wrap your own jit of `reset`/`step`.
    """
    return jax.enable_x64(self._impl == "jax")

  # -- description ---------------------------------------------------------------

  @property
  def impl(self):
    """The MJX implementation in use, "warp" or "jax"."""
    return self._impl

  @property
  def batch_model(self):
    return self._batch_model

  @property
  def tables(self):
    return self._tables

  @property
  def settings(self):
    return self._settings

  @property
  def mjx_model(self):
    return self._mx

  @property
  def num_parts(self):
    return self._batch_model.num_parts

  # -- many worlds -----------------------------------------------------------------

  @functools.cached_property
  def _restart_batch(self):
    def restart(keep, fresh, stepped):
      pick = lambda a, b: jax.tree.map(lambda x, y: jnp.where(keep, x, y), a, b)
      shown = fresh._replace(
          reward=jnp.zeros_like(fresh.reward), done=jnp.bool_(False),
          metrics={"connections": jnp.int32(0), "success": jnp.bool_(False)},
          info={"rng": fresh.info["rng"], "truncation": jnp.bool_(False),
                "diverged": jnp.bool_(False), "final_obs": fresh.obs,
                "contact_overflow": stepped.info["contact_overflow"],
                "buffer_peak": stepped.info["buffer_peak"]})
      return type(fresh)(data=fresh.data.where(keep, stepped.data),
                         **{f: pick(getattr(shown, f), getattr(stepped, f))
                            for f in type(fresh)._fields if f != "data"})
    return jax.jit(jax.vmap(restart))

  def restart_batch(self, keep, fresh, stepped):
    """Per world, the episode start `fresh` where `keep` (worlds,) is true (reward 0, not
    done, nothing connected), else `stepped` (jitted): a vector env's next-step autoreset
    shows the worlds that ended last step at the start their step then reset them to."""
    with self.precision():
      return self._restart_batch(jnp.asarray(keep), fresh, stepped)

  def reset_batch(self, rng, num_worlds):
    """`num_worlds` fresh worlds, each with its own key split from `rng` (jitted)."""
    if not isinstance(num_worlds, (int, np.integer)) or num_worlds < 1:
      raise errors.OptionValueError(f"num_worlds must be an integer >= 1, got {num_worlds!r}")
    if self._impl == "warp" and (self._num_worlds is None or num_worlds > self._num_worlds):
      raise errors.OptionValueError(
          f"the Warp implementation sizes its contact buffer for all worlds: load with "
          f"num_worlds >= {num_worlds} (got num_worlds={self._num_worlds})")
    with self.precision():
      return self._reset_batch(jax.random.split(rng, num_worlds))

  def _check_actions(self, state, actions):
    expected = (state.reward.shape[0], self.action_size)
    if tuple(np.shape(actions)) != expected:
      raise errors.ActionError(f"actions must have shape {expected}, got {np.shape(actions)}")

  def step_batch(self, state, actions):
    """One step of every world: actions (worlds, action_size) (jitted, vmapped `step`);
    raises ActionError for another shape. `overflow_watch` reads the step's buffer
    overflows (while the next step runs) and warns naming the buffer."""
    self._check_actions(state, actions)
    with self.precision():
      state = self._step_batch(state, actions)
    self.overflow_watch.watch(state.info["contact_overflow"], state.info["buffer_peak"])
    return state
