"""`AssemblyEnv`: an ikea_suite environment behind the gymnasium 1.x `Env` API.

The adapter is thin: it builds the dm_env environment with `ikea_suite.load`,
mirrors its specs as spaces (`spaces.py`) and translates time steps.

- `reset(seed=s)` reseeds the environment's random state, so the episode is
  the one `ikea_suite.load(..., seed=s)` starts with; `reset()` continues the
  random stream.
- `terminated` is a final step with discount 0 (assembled, or a physics
  blow-up); `truncated` a final step with discount 1 (the time limit).
- `info`: `connections` (connections made so far), `success` (the furniture
  is one group) and `blocked_connections` (the task's reasons why `connect`
  made no connection on this step, a tuple of strings).
- `render_mode="rgb_array"`: `render()` returns an (h, w, 3) uint8 frame of
  `render_camera` at `render_size`.
"""

import dataclasses
from typing import Any

import dm_env
import gymnasium
import numpy as np

import ikea_suite
from ikea_suite import config
from ikea_suite import errors
from ikea_suite.gym import spaces as spaces_lib
from ikea_suite.tasks import cameras

RENDER_MODES = ("rgb_array",)


class ResetNeeded(errors.IkeaSuiteError, RuntimeError):
  """`step` was called before `reset` or after the episode ended."""


class AssemblyEnv(gymnasium.Env):
  """gymnasium view of `ikea_suite.load(furniture, robot, **load_options)`.

  Args:
    furniture: furniture model name (`ikea_suite.furniture_names()`).
    robot: robot name (`ikea_suite.robot_names()`).
    render_mode, render_camera, render_size: the adapter's own options (config.GymConfig):
      None or "rgb_array"; the arena camera `render()` draws ("front", "top" or "side");
      (height, width) of its frames, pixels.
    **load_options: any option of `ikea_suite.load` (time_limit, reward, cameras, ...).
  Raises:
    UnknownNameError: an unknown render mode, render camera, or load() name.
    OptionValueError: a load() option or render size out of range.
  """

  metadata = {"render_modes": list(RENDER_MODES), "render_fps": 20}

  def __init__(self, furniture: str = ikea_suite.DEFAULT_FURNITURE,
               robot: str = ikea_suite.DEFAULT_ROBOT,
               render_mode: str | None = config.GymConfig.render_mode,
               render_camera: str = config.GymConfig.render_camera,
               render_size: tuple[int, int] = config.GymConfig.render_size,
               **load_options: Any):
    self.config = config.GymConfig(render_mode=render_mode, render_camera=render_camera,
                                   render_size=render_size)
    self._env = ikea_suite.load(furniture, robot, **load_options)
    physics = self._env.physics
    self.render_mode = self.config.render_mode
    self._render_camera = physics.bind(
        self._env.task.arena.cameras[self.config.render_camera]).element_id
    self._render_size = self.config.render_size
    # MuJoCo's offscreen buffer bounds the frame: made room for in the MJCF (the first reset
    # compiles it again) and in the model compiled now. No rendering context exists yet, so
    # the one made at the first render has that room.
    height, width = self._render_size
    offscreen = getattr(self._env.task.arena.mjcf_model.visual, "global")
    offscreen.offheight = max(height, offscreen.offheight or 480)
    offscreen.offwidth = max(width, offscreen.offwidth or 640)
    buffer = physics.model.vis.global_
    buffer.offheight, buffer.offwidth = max(buffer.offheight, height), max(buffer.offwidth, width)
    self.metadata = dict(self.metadata, render_fps=round(1.0 / self._env.control_timestep()))
    self.observation_space = spaces_lib.dict_from_specs(self._env.observation_spec())
    # float32, as learners send them; step() widens to the suite's float64 exactly.
    self.action_space = spaces_lib.box_from_spec(self._env.action_spec(), dtype=np.float32)
    self._max_episode_steps = self._env.task.config.max_steps
    self._spec = None
    self._needs_reset = True

  @property
  def spec(self) -> gymnasium.envs.registration.EnvSpec | None:
    """The registration spec, with `max_episode_steps` the suite's own time limit in control
    steps for these options (no TimeLimit wrapper: the suite truncates)."""
    return self._spec

  @spec.setter
  def spec(self, value: gymnasium.envs.registration.EnvSpec | None) -> None:
    if value is not None:
      value = dataclasses.replace(value, max_episode_steps=self._max_episode_steps)
    self._spec = value

  @property
  def suite_env(self) -> ikea_suite.environment.Environment:
    """The wrapped dm_control environment (physics, task, specs)."""
    return self._env

  def _observation(self, timestep: dm_env.TimeStep) -> dict[str, np.ndarray]:
    # Each value is already the caller's own array (composer's buffers copy on read; the
    # environment's direct readers give fresh arrays), so none is copied again.
    return {name: np.asarray(value) for name, value in timestep.observation.items()}

  def _info(self) -> dict[str, Any]:
    task = self._env.task
    return {"connections": len(task.state.connections), "success": bool(task.state.complete),
            "blocked_connections": tuple(task.blocked_connections)}

  def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
            ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    """Starts an episode.

    Args:
      seed: reseeds the environment (0 .. 2**32 - 1); the same seed gives the same episode.
      options: no reset options exist; must be None or empty.

    Returns:
      (observation, info).

    Raises:
      OptionValueError: a seed that is not a whole number in range.
      UnknownNameError: any reset option.
    """
    seed = config.seed_argument(seed)
    if options:
      raise errors.UnknownNameError("reset option", next(iter(options)), ())
    super().reset(seed=seed)
    if seed is not None:
      self._env.random_state.seed(int(seed))
    timestep = self._env.reset()
    self._needs_reset = False
    return self._observation(timestep), self._info()

  def step(self, action: np.ndarray
           ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
    """Advances one control step.

    Args:
      action: array in `action_space` (entries outside [-1, 1] are clipped).

    Returns:
      (observation, reward, terminated, truncated, info).

    Raises:
      ResetNeeded: before reset() or after the episode ended.
      ActionError: an action of the wrong shape or with non-finite entries.
    """
    if self._needs_reset:
      raise ResetNeeded("call reset() before step() and after an episode ends")
    timestep = self._env.step(action)
    terminated = timestep.last() and timestep.discount == 0.0
    truncated = timestep.last() and not terminated
    self._needs_reset = timestep.last()
    return (self._observation(timestep), float(timestep.reward), bool(terminated),
            bool(truncated), self._info())

  def render(self) -> np.ndarray | None:
    """An (h, w, 3) uint8 frame with render_mode "rgb_array"; None without a render mode."""
    if self.render_mode is None:
      return None
    height, width = self._render_size
    cameras.claim_gl()
    return self._env.physics.render(height, width, camera_id=self._render_camera)

  def close(self) -> None:
    """Frees the physics and renderers; closing twice is harmless."""
    if self._env is not None:
      self._env.close()
      self._env = None
