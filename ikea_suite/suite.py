"""ikea_suite.load: furniture x robot x options -> a composer environment."""

import dataclasses
import os
from typing import Any

from ikea_suite import environment
from ikea_suite import errors
from ikea_suite import options as ranges
from ikea_suite import physics_settings
from ikea_suite.arenas import presets
from ikea_suite.arenas import work_table
from ikea_suite.props import catalog
from ikea_suite.props import furniture as furniture_lib
from ikea_suite.props import scaling
from ikea_suite.robots import registry
from ikea_suite.tasks import alignment
from ikea_suite.tasks import arm_placement
from ikea_suite.tasks import assembly
from ikea_suite.tasks import camera_observables
from ikea_suite.tasks import placement
from ikea_suite.tasks import randomization

DEFAULT_FURNITURE = "table_four_leg_lack"
DEFAULT_ROBOT = "cursor"

# Option name -> (where it goes, default). Thresholds are flattened for convenience.
TASK_OPTIONS = ("control_timestep", "physics_timestep", "connection_reward", "completion_bonus",
                "reward")
THRESHOLD_OPTIONS = {"distance_threshold": "distance", "up_threshold": "up_cos",
                     "forward_threshold": "forward_cos"}
ENVIRONMENT_OPTIONS = ("time_limit",)
# Furniture size factor (props/scaling.py): lengths x scale, masses x scale^3, inertias x scale^5.
FURNITURE_OPTIONS = ("scale",)
# Scene preset, placement, randomization and cameras: see the README, "Observations, scenes and domain randomization".
SCENE_OPTIONS = (("scene", "arena") + placement.OPTIONS + randomization.OPTIONS
                 + camera_observables.OPTIONS)
# Default episode length in simulated seconds: a start-up allowance plus a
# fixed budget per part (500 control steps at 20 Hz), so larger furniture gets
# proportionally longer episodes.
TIME_LIMIT_BASE = 30.0
TIME_LIMIT_PER_PART = 25.0


def default_time_limit(num_parts):
  return TIME_LIMIT_BASE + TIME_LIMIT_PER_PART * num_parts


def load(furniture: str | os.PathLike = DEFAULT_FURNITURE, robot: str = DEFAULT_ROBOT,
         seed: int | None = None, **options: Any) -> environment.Environment:
  """Builds the assembly environment of `furniture` with `robot`.

  `furniture` is a catalog name (see furniture_names() and register_models()) or
  the path of a model file.

  Options: time_limit (s; default 30 + 25 per part); control_timestep, physics_timestep (s);
  connection_reward, completion_bonus; reward ("sparse" or "dense", tasks/rewards.py); distance_threshold (m), up_threshold
  and forward_threshold (cosines); and the robot's own options (for the
  cursor: move_speed, rotate_speed, grasp_margin, workspace, radius).
  scale: the furniture's size factor (0.2 to 2, default 1): the same design built
  that much smaller or larger from the same materials, lengths x scale, masses
  x scale^3, inertias x scale^5, connectors with the parts; the default
  distance_threshold scales with it (a given distance_threshold is in metres).
  Arena: arena ("floor", or "work_table" for arms: a 0.75 m table in front of the robot,
  which stands on a pedestal as high; base_pos's z is then measured from the table top).
  Scene: scene (preset name), spread, preassembled, yaw_range, randomize;
  images: cameras, camera_outputs, image_size, goal_image (README: "Observations, scenes and domain randomization").
  Unknown names raise UnknownNameError listing the valid ones.

  Args:
    furniture: catalog name or model file path.
    robot: robot name (robot_names()).
    seed: seed of the environment's random state; None draws a fresh one.
    **options: the options above.
  Returns:
    The composer environment (dm_env API); `env.task` is the tasks.assembly.Assembly.
  Raises:
    UnknownNameError: an unknown furniture, robot or option name.
    OptionValueError: an option value out of range or of the wrong kind.
    ModelFormatError: a model file that breaks the format.
  """
  spec = catalog.spec(furniture)
  robot_entry = registry.get(robot)
  robot_keys = list(robot_entry.factory.option_defaults())
  valid = (set(TASK_OPTIONS) | set(THRESHOLD_OPTIONS) | set(ENVIRONMENT_OPTIONS) | set(robot_keys)
           | set(SCENE_OPTIONS) | set(FURNITURE_OPTIONS))
  for key in options:
    if key not in valid:
      raise errors.UnknownNameError("option", key, valid)
  _check_options(options)
  scale = scaling.check_scale(options.get("scale", 1.0))
  spec = scaling.scaled(spec, scale)
  thresholds = alignment.Thresholds(**{field: options[key] for key, field in THRESHOLD_OPTIONS.items()
                                       if key in options})
  if "distance_threshold" not in options and scale != 1.0:
    thresholds = dataclasses.replace(thresholds, distance=thresholds.distance * scale)
  def picked(names):
    return {k: options[k] for k in names if k in options}
  furniture_prop = furniture_lib.Furniture(spec)
  robot_options = picked(robot_keys)
  arena_kind = _arena_kind(options, robot_entry, robot_options)
  robot_entity = robot_entry.factory(**robot_options)
  arena = presets.make_arena(options.get("scene", "default"), arena_kind,
                             base_pose=getattr(robot_entity, "base_pose", None))
  if robot_entity.reach_zone is not None:   # an arm: the same options, within its reach
    initializer = arm_placement.reachable_parts(furniture_prop, robot_entity.reach_zone,
                                                support=arena.support, **picked(placement.OPTIONS))
  else:
    initializer = placement.scattered_parts(furniture_prop, **picked(placement.OPTIONS))
  task = assembly.Assembly(
      arena=arena,
      furniture=furniture_prop,
      initializer=initializer,
      robot=robot_entity,
      thresholds=thresholds,
      **{k: options[k] for k in TASK_OPTIONS if k in options})
  randomization.attach(task, **picked(randomization.OPTIONS))
  camera_observables.attach(task, **picked(camera_observables.OPTIONS))
  time_limit = options.get("time_limit", default_time_limit(len(furniture_prop.parts)))
  return environment.Environment(task, time_limit=time_limit, random_state=seed)


def _arena_kind(options, robot_entry, robot_options):
  """The `arena` option, checked; on the work table the arm's base_pos is raised onto its
  pedestal (in `robot_options`), so the arm meets the table top as it meets the floor."""
  kind = ranges.choice("arena", options.get("arena", "floor"), presets.ARENAS)
  if kind == "work_table":
    if "arm" not in robot_entry.tags:
      raise errors.OptionValueError(
          f"arena='work_table' is for the fixed-base arms ({', '.join(registry.names('arm'))}); "
          f"the {robot_entry.name} scatters full-size furniture metres out, so use arena='floor'")
    base = ranges.vector("base_pos", robot_options.get("base_pos", robot_entry.factory.BASE_POS),
                         (3,))
    robot_options["base_pos"] = base + [0.0, 0.0, work_table.TABLE_HEIGHT]
  return kind


def _check_options(options):
  """Range-checks the task and environment options (robots and scene modules check theirs)."""
  given = dict(options)
  if "distance_threshold" in given:
    ranges.positive("distance_threshold", given["distance_threshold"])
  for key in ("up_threshold", "forward_threshold"):
    if key in given:
      ranges.number(key, given[key], -1.0, 1.0, high_open=True)
  for key in ("time_limit", "control_timestep", "physics_timestep"):
    if key in given:
      ranges.positive(key, given[key])
  for key in ("connection_reward", "completion_bonus"):
    if key in given:
      ranges.number(key, given[key])
  control = given.get("control_timestep", assembly.CONTROL_TIMESTEP)
  physics = given.get("physics_timestep", physics_settings.TIMESTEP)
  substeps = control / physics
  if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
    raise errors.OptionValueError(
        f"control_timestep ({control!r}) must be a whole multiple of physics_timestep ({physics!r})")


def furniture_names(tag: str | None = None, min_parts: int | None = None,
                    max_parts: int | None = None) -> list[str]:
  """Names of the catalog's furniture (bundled and register_models()), sorted.

  Args:
    tag: keep only models with this tag: a category ("table"), a family, "parts_N" or
      "concave"; None keeps all.
    min_parts, max_parts: inclusive bounds on the part count; None for no bound.
  Returns:
    Furniture names accepted by load().
  """
  return catalog.names(tag=tag, min_parts=min_parts, max_parts=max_parts)


def robot_names(tag: str | None = None) -> list[str]:
  """Names of the registered robots, sorted.

  Args:
    tag: keep only robots with this tag ("arm", "single_arm", "bimanual", "floating",
      "paper"); None keeps all.
  Returns:
    Robot names accepted by load().
  """
  return registry.names(tag=tag)


def all_environments() -> list[tuple[str, str]]:
  """Every registered (furniture, robot) pair.

  Returns:
    (furniture name, robot name) pairs, furniture-major.
  """
  return [(f, r) for f in furniture_names() for r in robot_names()]
