"""A gymnasium VectorEnv over the batched task: the `vector_entry_point` of ikea_suite/Assembly-v0.

All worlds step in one jitted call on the device. Observations come back as a dict
of numpy arrays with a leading env axis, under the CPU environment's keys and with
its shapes, dtypes and bounds (ikea_suite.observations), so a policy moves between
`gymnasium.make` and this env unchanged. Info holds the CPU env's `connections` and
`success` per env, plus `diverged`; `blocked_connections` (the CPU task's reasons for
a refused connect) is not computed on the device.

Autoreset is gymnasium's default, NEXT_STEP: the step that ends an episode returns
its last observation with terminated/truncated set; the next step() resets those
envs (their actions are ignored) and returns the new episode's first observation,
reward 0 and no termination.
"""

import dataclasses

import gymnasium
import jax
import numpy as np
from gymnasium.vector import AutoresetMode

from ikea_suite import errors
from ikea_suite import observations
from ikea_suite.batch import arm_env
from ikea_suite.batch import env as env_lib


def _box(spec):
  return gymnasium.spaces.Box(low=spec.minimum, high=spec.maximum, shape=spec.shape,
                              dtype=spec.dtype)


class AssemblyVectorEnv(gymnasium.vector.VectorEnv):
  """`num_envs` worlds of `furniture` for the Cursor agent or a batched arm (the Panda).

  Args:
    furniture: catalog name or model file path.
    num_envs: number of worlds.
    robot: "cursor" or an arm of arm_env.ROBOTS (batch/arm_env.py).
    impl: "warp", "jax" or None (see BatchAssembly).
    **options: ikea_suite.load's task options (batch.settings.OPTIONS).
  Raises:
    OptionValueError: another robot, or num_envs not an integer >= 1.
  """

  metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

  def __init__(self, furniture="table_four_leg_lack", num_envs=1, robot="cursor", impl=None,
               **options):
    if robot != "cursor" and robot not in arm_env.ROBOTS:
      raise errors.OptionValueError(
          f"the batched environment supports robots {', '.join(('cursor',) + arm_env.ROBOTS)}, "
          f"got {robot!r}; for another arm use gymnasium.make_vec(..., "
          f"vectorization_mode='async') (or 'sync')")
    if not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
      raise errors.OptionValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
    self._env = env_lib.load(furniture, impl=impl, num_worlds=int(num_envs), robot=robot,
                             **options)
    self.num_envs = int(num_envs)
    num_parts = self._env.num_parts
    with self._env.precision():
      shapes = jax.eval_shape(self._env.reset, jax.random.PRNGKey(0)).obs
    self._specs = {k: observations.spec(k, tuple(v.shape), num_parts)
                   for k, v in sorted(shapes.items())}
    self.single_observation_space = gymnasium.spaces.Dict(
        {k: _box(s) for k, s in self._specs.items()})
    self.observation_space = gymnasium.vector.utils.batch_space(
        self.single_observation_space, self.num_envs)
    size = self._env.action_size
    self.single_action_space = gymnasium.spaces.Box(-1.0, 1.0, (size,), np.float32)
    self.action_space = gymnasium.vector.utils.batch_space(self.single_action_space,
                                                           self.num_envs)
    self._max_episode_steps = self._env.settings.max_steps
    self._spec = None
    self._state = None
    self._autoreset = np.zeros(self.num_envs, dtype=bool)
    self._rng = jax.random.PRNGKey(0)

  @property
  def spec(self):
    """The registration spec, with `max_episode_steps` the task's time limit in steps."""
    return self._spec

  @spec.setter
  def spec(self, value):
    if value is not None:
      value = dataclasses.replace(value, max_episode_steps=self._max_episode_steps)
    self._spec = value

  @property
  def batch_env(self):
    """The underlying BatchAssembly."""
    return self._env

  def _numpy(self, obs):
    return {k: np.asarray(obs[k]).astype(s.dtype, copy=False) for k, s in self._specs.items()}

  def _infos(self, state):
    return {"connections": np.asarray(state.metrics["connections"], dtype=np.int64),
            "success": np.asarray(state.metrics["success"]),
            "diverged": np.asarray(state.info["diverged"])}

  def reset(self, *, seed=None, options=None):
    """Resets every env; the same seed gives the same batch. Returns (obs, infos)."""
    if options:
      raise errors.UnknownNameError("reset option", next(iter(options)), ())
    if seed is not None:
      self._rng = jax.random.PRNGKey(int(seed))
    self._rng, key = jax.random.split(self._rng)
    self._state = self._env.reset_batch(key, self.num_envs)
    self._autoreset[:] = False
    return self._numpy(self._state.obs), self._infos(self._state)

  def step(self, actions):
    """Steps every env; returns (obs, rewards, terminations, truncations, infos)."""
    if self._state is None:
      raise errors.ActionError("call reset() before step()")
    actions = np.asarray(actions, dtype=np.float64)
    if actions.shape != self.action_space.shape:
      raise errors.ActionError(
          f"actions must have shape {self.action_space.shape}, got {actions.shape}")
    previous = self._state
    state = self._env.step_batch(previous, actions)
    if self._autoreset.any():
      # These worlds ended last step and were reset then: this step shows their start.
      state = self._env.restart_batch(self._autoreset, previous, state)
    self._state = state
    done = np.asarray(state.done)
    truncated = np.asarray(state.info["truncation"]) & done
    self._autoreset = done.copy()
    # The last observation of an ended episode (the others': their current one).
    return (self._numpy(state.info["final_obs"]), np.asarray(state.reward, dtype=np.float64),
            done & ~truncated, truncated, self._infos(state))
