"""Options of the batched task: the same names, defaults and range checks as ikea_suite.load."""

import dataclasses

import numpy as np

from ikea_suite import errors
from ikea_suite import options as ranges
from ikea_suite import physics_settings
from ikea_suite import suite
from ikea_suite.batch import cursor as cursor_lib
from ikea_suite.robots import cursor as cpu_cursor
from ikea_suite.tasks import alignment
from ikea_suite.tasks import assembly

_CURSOR_DEFAULTS = {name: default for name, default in cpu_cursor.Cursor.option_defaults().items()
                    if name in ("move_speed", "rotate_speed", "grasp_margin", "workspace")}
OPTIONS = ("time_limit", "control_timestep", "distance_threshold", "up_threshold",
           "forward_threshold", "connection_reward", "completion_bonus", "spread", "yaw_range"
           ) + tuple(_CURSOR_DEFAULTS)


@dataclasses.dataclass(frozen=True)
class Settings:
  """Resolved options of one batched task (units as in the README's option table)."""
  thresholds: alignment.Thresholds
  cursor: cursor_lib.CursorSettings
  control_timestep: float
  substeps: int
  max_steps: int
  connection_reward: float
  completion_bonus: float
  spread: float
  yaw_range: float


def resolve(num_parts, **options):
  """Settings from load()-style options; raises UnknownNameError / OptionValueError.

  Args:
    num_parts: parts of the furniture (the default time limit grows with them).
    **options: any of OPTIONS.

  Returns:
    Settings.
  """
  for key in options:
    if key not in OPTIONS:
      raise errors.UnknownNameError("option", key, OPTIONS)
  get = options.get
  control = ranges.positive("control_timestep", get("control_timestep", assembly.CONTROL_TIMESTEP))
  substeps = control / physics_settings.TIMESTEP
  if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
    raise errors.OptionValueError(f"control_timestep ({control!r}) must be a whole multiple of "
                                  f"physics_timestep ({physics_settings.TIMESTEP!r})")
  time_limit = ranges.positive("time_limit", get("time_limit", suite.default_time_limit(num_parts)))
  thresholds = alignment.Thresholds(
      distance=ranges.positive("distance_threshold", get("distance_threshold", 0.02)),
      up_cos=ranges.number("up_threshold", get("up_threshold", 0.99), -1.0, 1.0, high_open=True),
      forward_cos=ranges.number("forward_threshold", get("forward_threshold", 0.99), -1.0, 1.0,
                                high_open=True))
  workspace = ranges.box("workspace", get("workspace", _CURSOR_DEFAULTS["workspace"]))
  cursor = cursor_lib.CursorSettings(
      move_speed=ranges.positive("move_speed", get("move_speed", _CURSOR_DEFAULTS["move_speed"])),
      rotate_speed=ranges.positive("rotate_speed",
                                   get("rotate_speed", _CURSOR_DEFAULTS["rotate_speed"])),
      grasp_margin=ranges.non_negative("grasp_margin",
                                       get("grasp_margin", _CURSOR_DEFAULTS["grasp_margin"])),
      workspace_low=tuple(workspace[0]), workspace_high=tuple(workspace[1]))
  return Settings(
      thresholds=thresholds, cursor=cursor, control_timestep=control, substeps=int(round(substeps)),
      # dm_control ends the episode at the first step whose time reaches the limit.
      max_steps=int(np.ceil(time_limit / control - 1e-9)),
      connection_reward=ranges.number("connection_reward", get("connection_reward", 1.0)),
      completion_bonus=ranges.number("completion_bonus", get("completion_bonus", 10.0)),
      spread=ranges.non_negative("spread", get("spread", 0.9)),
      yaw_range=ranges.non_negative("yaw_range", get("yaw_range", np.pi)))
