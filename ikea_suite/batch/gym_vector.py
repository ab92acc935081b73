"""A gymnasium VectorEnv over the batched task: the `vector_entry_point` of ikea_suite/Assembly-v0.

All worlds step in one jitted call on the device; observations come back as a
dict of numpy arrays with a leading env axis, named as the batched task's
(observe.observe). Episodes reset inside the step that ends them (gymnasium's
SAME_STEP autoreset): that step returns the new episode's first observation
and puts the ended episode's last one in info["final_obs"], with
info["_final_obs"] marking the envs that reset.
"""

import gymnasium
import jax
import numpy as np
from gymnasium.vector import AutoresetMode

from ikea_suite import errors
from ikea_suite.batch import env as env_lib


def _box(shape, low=-np.inf, high=np.inf):
  return gymnasium.spaces.Box(low=low, high=high, shape=shape, dtype=np.float32)


class AssemblyVectorEnv(gymnasium.vector.VectorEnv):
  """`num_envs` worlds of `furniture` for the Cursor agent.

  Args:
    furniture: catalog name or model file path.
    num_envs: number of worlds.
    robot: only "cursor" (the batched task has no arms).
    impl: "warp", "jax" or None (see BatchAssembly).
    **options: ikea_suite.load's task options (batch.settings.OPTIONS).
  """

  metadata = {"autoreset_mode": AutoresetMode.SAME_STEP, "render_modes": []}

  def __init__(self, furniture="table_four_leg_lack", num_envs=1, robot="cursor", impl=None,
               **options):
    if robot != "cursor":
      raise errors.OptionValueError(
          f"the batched environment supports robot 'cursor' only, got {robot!r}")
    if not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
      raise errors.OptionValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
    self._env = env_lib.load(furniture, impl=impl, num_worlds=int(num_envs), **options)
    self.num_envs = int(num_envs)
    p, c = self._env.num_parts, len(self._env.batch_model.table)
    shapes = {"part_positions": (p, 3), "part_quaternions": (p, 4), "connections": (p, p),
              "connectors_used": (c,), "next_pair": (2,), "cursor_positions": (2, 3),
              "cursor_quaternions": (2, 4), "cursor_held_parts": (2,)}
    self.single_observation_space = gymnasium.spaces.Dict(
        {k: _box(v) for k, v in shapes.items()})
    self.observation_space = gymnasium.spaces.Dict(
        {k: _box((self.num_envs,) + v) for k, v in shapes.items()})
    size = self._env.action_size
    self.single_action_space = _box((size,), -1.0, 1.0)
    self.action_space = _box((self.num_envs, size), -1.0, 1.0)
    self._state = None
    self._rng = jax.random.PRNGKey(0)

  @property
  def batch_env(self):
    """The underlying BatchAssembly."""
    return self._env

  @staticmethod
  def _numpy(obs):
    return {k: np.asarray(v, dtype=np.float32) for k, v in obs.items()}

  def reset(self, *, seed=None, options=None):
    """Resets every env; the same seed gives the same batch."""
    if seed is not None:
      self._rng = jax.random.PRNGKey(int(seed))
    self._rng, key = jax.random.split(self._rng)
    self._state = self._env.reset_batch(key, self.num_envs)
    return self._numpy(self._state.obs), {}

  def step(self, actions):
    """Steps every env; returns (obs, rewards, terminations, truncations, infos)."""
    if self._state is None:
      raise errors.ActionError("call reset() before step()")
    actions = np.asarray(actions, dtype=np.float64)
    if actions.shape != self.action_space.shape:
      raise errors.ActionError(
          f"actions must have shape {self.action_space.shape}, got {actions.shape}")
    self._state = self._env.step_batch(self._state, actions)
    s = self._state
    done = np.asarray(s.done)
    truncated = np.asarray(s.info["truncation"])
    infos = {"final_obs": self._numpy(s.info["final_obs"]), "_final_obs": done,
             "success": np.asarray(s.metrics["success"]),
             "diverged": np.asarray(s.info["diverged"])}
    return (self._numpy(s.obs), np.asarray(s.reward, dtype=np.float64), done & ~truncated,
            truncated, infos)
