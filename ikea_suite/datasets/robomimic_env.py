"""robomimic's environment interface over an ikea_suite environment, for rollouts.

A demonstration file's `env_args` (robomimic's `env_meta`) carry `type`
hdf5.ENV_TYPE, an int as robomimic's `EnvType` values are, and `env_kwargs`, the
keyword arguments of `ikea_suite.load`. robomimic dispatches only on its own
three types (robosuite, gym, iGibson), so a rollout builds the environment here:

    from robomimic.utils import file_utils
    from ikea_suite.datasets import robomimic_env
    env_meta = file_utils.get_env_metadata_from_dataset("demos.hdf5")
    env = robomimic_env.create_env_from_metadata(env_meta, use_image_obs=True)
    obs = env.reset()
    obs, reward, done, info = env.step(action)

`EnvIkeaSuite` has robomimic's `EnvBase` methods (reset, reset_to, step,
get_observation, get_state, is_success, serialize, ...) and subclasses
`EnvBase` where robomimic is installed, so robomimic's rollout helpers accept
it. Observations use the file's keys (`robot.joint_positions`,
`cameras.front_rgb`), so a policy trained on the file reads them unchanged.
"""

import copy
from typing import Any

import numpy as np

from ikea_suite import composer_internals
from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.datasets import hdf5
from ikea_suite.datasets import mj_state

try:
  from robomimic.envs import env_base as _robomimic_env_base
  _Base: type = _robomimic_env_base.EnvBase
except ImportError:   # robomimic is optional (the interop extra); the adapter stands alone
  _robomimic_env_base = None
  _Base = object


def env_from_env_args(env_args: dict[str, Any], **overrides: Any) -> environment.Environment:
  """The ikea_suite environment a demonstration file's env_args describe.

  Args:
    env_args: the file's env_args (hdf5.read_env_args, or robomimic's
      get_env_metadata_from_dataset).
    **overrides: ikea_suite.load options that replace the stored ones.
  Returns:
    The environment.
  Raises:
    UnknownNameError, OptionValueError: as ikea_suite.load.
  """
  return hdf5.load_env(env_args, **overrides)


class EnvIkeaSuite(_Base):
  """robomimic's EnvBase interface over an ikea_suite environment.

  Args:
    env_name: the gymnasium id the file stores (kept for serialize()).
    render: on-screen rendering; not supported (ikea_suite renders offscreen).
    render_offscreen: ignored: render() always renders offscreen.
    use_image_obs: keep camera observations (the env_kwargs' cameras); False drops them
      (loads the environment without cameras, which is faster).
    use_depth_obs: ignored; depth is an ikea_suite camera output option.
    postprocess_visual_obs: pass RGB observations through robomimic's ObsUtils.process_obs
      (channels first, [0, 1]) as robomimic's own wrappers do, when robomimic is installed
      and its obs utils know the key.
    **kwargs: ikea_suite.load keyword arguments (the file's env_kwargs).
  """

  def __init__(self, env_name: str, render: bool = False, render_offscreen: bool = False,
               use_image_obs: bool = False, use_depth_obs: bool = False,
               postprocess_visual_obs: bool = True, **kwargs: Any):
    del render_offscreen, use_depth_obs
    if render:
      raise NotImplementedError("ikea_suite renders offscreen only: render(mode='rgb_array')")
    self._env_name = env_name
    self._init_kwargs = copy.deepcopy(kwargs)
    overrides = {} if use_image_obs else {"cameras": ()}
    self.env = env_from_env_args({"env_kwargs": kwargs}, **overrides)
    self._postprocess = postprocess_visual_obs
    self._timestep = None

  def _observation(self, obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    out = {}
    for key, value in obs.items():
      name = hdf5.obs_key(key)
      value = np.array(value)
      if self._postprocess and _robomimic_env_base is not None and value.ndim == 3:
        from robomimic.utils import obs_utils   # pylint: disable=import-outside-toplevel
        if (obs_utils.OBS_KEYS_TO_MODALITIES and name in obs_utils.OBS_KEYS_TO_MODALITIES
            and obs_utils.key_is_obs_modality(key=name, obs_modality="rgb")):
          value = obs_utils.process_obs(obs=value, obs_key=name)
      out[name] = value
    return out

  def step(self, action: np.ndarray) -> tuple[dict[str, np.ndarray], float, bool, dict]:
    """One control step.

    Args:
      action: the action vector (as in the file's actions).
    Returns:
      (observation, reward, done, info); done at the time limit or on completion;
      info["is_success"] as is_success().
    """
    self._timestep = self.env.step(action)
    return (self._observation(self._timestep.observation), self.get_reward(), self.is_done(),
            {"is_success": self.is_success()})

  def reset(self) -> dict[str, np.ndarray]:
    """Starts an episode; returns its first observation."""
    self._timestep = self.env.reset()
    return self._observation(self._timestep.observation)

  def reset_to(self, state: dict[str, Any]) -> dict[str, np.ndarray] | None:
    """Sets the simulator to a stored state (a file's `states[t]`).

    With "seed" (a demo's seed attribute) the episode is first reset from that seed,
    so the task's own per-episode choices (which parts start mated) are the demo's;
    without it, the current episode's are kept.

    Args:
      state: {"states": flattened MuJoCo state, optional "seed": int}.
    Returns:
      The observation at that state.
    """
    if "seed" in state:
      self.env.random_state.seed(int(state["seed"]))
      self.reset()
    elif self._timestep is None:
      self.reset()
    mj_state.set_state(self.env.physics, state["states"])
    return self.get_observation()

  def render(self, mode: str = "rgb_array", height: int | None = None,
             width: int | None = None, camera_name: str | None = None) -> np.ndarray:
    """An offscreen image (mode "rgb_array" only).

    Args:
      mode: "rgb_array".
      height, width: pixels (default 240 x 320).
      camera_name: a camera of the scene (default the front camera).
    Returns:
      (height, width, 3) uint8.
    """
    if mode != "rgb_array":
      raise NotImplementedError(f"render mode {mode!r}: ikea_suite renders 'rgb_array' only")
    return self.env.physics.render(height or 240, width or 320,
                                   camera_id=camera_name or "front")

  def get_observation(self) -> dict[str, np.ndarray]:
    """The observation of the simulator's current state, file keys.

    Raises:
      IkeaSuiteError: observables that are not plain (delayed, buffered), whose value
        depends on more than the current state.
    """
    internals = composer_internals.read(self.env)
    readers = composer_internals.direct_readers(internals) if internals is not None else None
    if readers is None:
      raise errors.IkeaSuiteError(
          "the observation of a set state needs plain observables (no delay, buffer or "
          "aggregator)")
    return self._observation({name: read() for name, read in readers})

  def get_state(self) -> dict[str, np.ndarray]:
    """{"states": the flattened MuJoCo state}, as a file's `states` rows."""
    return {"states": mj_state.get_state(self.env.physics)}

  def get_reward(self) -> float:
    """Reward of the last step (0 before the first)."""
    if self._timestep is None or self._timestep.reward is None:
      return 0.0
    return float(self._timestep.reward)

  def get_goal(self) -> None:
    """No goal observation: the task's goal is the furniture's assembled state."""
    return None

  def set_goal(self, **kwargs: Any) -> None:
    """Goals are fixed by the furniture; setting one is not supported."""
    raise NotImplementedError("ikea_suite tasks have no settable goal")

  def is_done(self) -> bool:
    """Whether the episode has ended (completion or time limit)."""
    return self._timestep is not None and self._timestep.last()

  def is_success(self) -> dict[str, bool]:
    """{"task": every connection made}."""
    return {"task": bool(self.env.task.state.complete)}

  @property
  def action_dimension(self) -> int:
    """Length of the action vector."""
    return int(self.env.action_spec().shape[0])

  @property
  def name(self) -> str:
    """The gymnasium id stored as env_name."""
    return self._env_name

  @property
  def type(self) -> int:
    """hdf5.ENV_TYPE."""
    return hdf5.ENV_TYPE

  @property
  def version(self) -> str:
    """The ikea_suite version."""
    return hdf5.package_version()

  def serialize(self) -> dict[str, Any]:
    """env_meta that rebuilds this environment (the file's env_args)."""
    return {"env_name": self._env_name, "type": hdf5.ENV_TYPE,
            "env_kwargs": copy.deepcopy(self._init_kwargs)}

  @classmethod
  def create_for_data_processing(cls, camera_names: list[str], camera_height: int,
                                 camera_width: int, reward_shaping: bool,
                                 **kwargs: Any) -> "EnvIkeaSuite":
    """An environment that renders `camera_names` (robomimic's dataset_states_to_obs).

    Args:
      camera_names: cameras to observe.
      camera_height, camera_width: image size; ikea_suite images are square, so the
        larger side is used.
      reward_shaping: dense rewards ("dense") instead of sparse ones.
      **kwargs: env_name and the other env_kwargs.
    Returns:
      The environment.
    """
    env_name = kwargs.pop("env_name", hdf5.GYM_ID)
    kwargs.update(cameras=list(camera_names), image_size=max(camera_height, camera_width),
                  reward="dense" if reward_shaping else kwargs.get("reward", "sparse"))
    return cls(env_name, use_image_obs=True, **kwargs)

  @property
  def rollout_exceptions(self) -> tuple:
    """Exceptions a rollout treats as a failed episode rather than a crash."""
    return (errors.IkeaSuiteError,)

  @property
  def base_env(self) -> environment.Environment:
    """The ikea_suite environment."""
    return self.env

  def __repr__(self) -> str:
    return f"EnvIkeaSuite({self._env_name!r}, {self._init_kwargs!r})"


def create_env_from_metadata(env_meta: dict[str, Any], env_name: str | None = None,
                             render: bool = False, render_offscreen: bool = False,
                             use_image_obs: bool = False,
                             use_depth_obs: bool = False) -> EnvIkeaSuite:
  """robomimic's create_env_from_metadata for ikea_suite files.

  Args:
    env_meta: the file's env_args.
    env_name: overrides env_meta["env_name"].
    render, render_offscreen, use_image_obs, use_depth_obs: as EnvIkeaSuite.
  Returns:
    The wrapped environment.
  """
  return EnvIkeaSuite(env_name or env_meta["env_name"], render=render,
                      render_offscreen=render_offscreen, use_image_obs=use_image_obs,
                      use_depth_obs=use_depth_obs, **copy.deepcopy(env_meta["env_kwargs"]))
