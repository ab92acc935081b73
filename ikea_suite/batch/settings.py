"""Options of the batched task: its subset of load()'s, through the same config dataclasses.

The batched task takes the task options that its fixed model and scattered layout
leave free, and the Cursor's, with config.TaskConfig's and config.CursorConfig's
defaults and checks; the physics time step is the model's (physics_settings).
"""

import dataclasses


from ikea_suite import config
from ikea_suite import errors
from ikea_suite.batch import cursor as cursor_lib
from ikea_suite.tasks import alignment

TASK_OPTIONS = ("time_limit", "control_timestep", "distance_threshold", "up_threshold",
                "forward_threshold", "connection_reward", "completion_bonus", "spread",
                "yaw_range")
CURSOR_OPTIONS = ("move_speed", "rotate_speed", "grasp_margin", "workspace")
OPTIONS = TASK_OPTIONS + CURSOR_OPTIONS


@dataclasses.dataclass(frozen=True)
class Settings:
  """Resolved options of one batched task (units as in config.option_rows())."""
  thresholds: alignment.Thresholds
  cursor: cursor_lib.CursorSettings
  control_timestep: float
  substeps: int
  max_steps: int
  connection_reward: float
  completion_bonus: float
  spread: float
  yaw_range: float
  task: config.TaskConfig           # the resolved task config the rest come from
  cursor_config: config.CursorConfig


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
  cursor = config.CursorConfig(**{k: v for k, v in options.items() if k in CURSOR_OPTIONS})
  task = config.TaskConfig(**{k: v for k, v in options.items() if k in TASK_OPTIONS}).resolved(
      num_parts, scattered=True, scale=cursor.WORK_SCALE)
  return Settings(
      thresholds=alignment.Thresholds.of(task),
      cursor=cursor_lib.CursorSettings(
          move_speed=cursor.move_speed, rotate_speed=cursor.rotate_speed,
          grasp_margin=cursor.grasp_margin, workspace_low=tuple(cursor.workspace[0]),
          workspace_high=tuple(cursor.workspace[1])),
      control_timestep=task.control_timestep, substeps=task.substeps,
      max_steps=task.max_steps,
      connection_reward=task.connection_reward, completion_bonus=task.completion_bonus,
      spread=task.spread, yaw_range=task.yaw_range, task=task, cursor_config=cursor)
