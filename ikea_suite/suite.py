"""ikea_suite.load: furniture x robot x options (config.py) -> a composer environment."""

import os
from typing import Any

import numpy as np
from dm_control import composer

from ikea_suite import config
from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.arenas import presets
from ikea_suite.arenas import work_table
from ikea_suite.props import catalog
from ikea_suite.props import furniture as furniture_lib
from ikea_suite.props import scaling
from ikea_suite.robots import registry
from ikea_suite.tasks import assembly
from ikea_suite.tasks import camera_observables
from ikea_suite.tasks import randomization

DEFAULT_FURNITURE = "table_four_leg_lack"
DEFAULT_ROBOT = "cursor"
# load() lays a furniture out on the work table this many times and refuses it when more
# than half the layouts fail. The layout is random: at scale 0.5 with the Panda, 45 of the
# catalog's 129 models failed in all of 20 layouts (and 4 have a root part wider than the
# table) while 13 failed in some (2 to 19 of 20); the environment's reset retries those
# (environment.RESET_ATTEMPTS).
LAYOUT_DRAWS = 8


def load(furniture: str | os.PathLike = DEFAULT_FURNITURE, robot: str = DEFAULT_ROBOT,
         seed: int | None = None, **options: Any) -> environment.Environment:
  """Builds the assembly environment of `furniture` with `robot`.

  `furniture` is a catalog name (see furniture_names() and register_models()) or
  the path of a model file.

  The options are the fields of config.TaskConfig (the task's: time_limit,
  control_timestep, physics_timestep, reward, connection_reward, completion_bonus,
  distance_threshold, up_threshold, forward_threshold, scale, arena, scene, spread,
  preassembled, yaw_range, randomize, cameras, camera_outputs, image_size, goal_image)
  and of the robot's config (config.CursorConfig for the Cursor, config.ArmConfig for
  an arm); config.option_rows() lists each with its default and meaning. The resolved
  configs are `env.task.config` and `env.task.robot.config`.

  Args:
    furniture: catalog name or model file path.
    robot: robot name (robot_names()).
    seed: seed of the environment's random state (0 to 2**32 - 1); None draws a fresh one.
    **options: the options above.
  Returns:
    The composer environment (dm_env API); `env.task` is the tasks.assembly.Assembly.
  Raises:
    UnknownNameError: an unknown furniture, robot or option name.
    OptionValueError: an option value out of range or of the wrong kind, or options that
      cannot work together (a time step too large for the arm's servos, furniture that
      does not fit the work table at that scale).
    ModelFormatError: a model file that breaks the format.
  """
  config.furniture_argument(furniture)
  seed = config.seed_argument(seed)
  spec = catalog.spec(furniture)
  robot_entry = registry.get(robot)
  task_config, robot_config = _configs(robot_entry, options)
  scale = task_config.furniture_scale(robot_config)
  spec = scaling.scaled(spec, scale)
  furniture_prop = furniture_lib.Furniture(spec)
  robot_entity = robot_entry.factory(config=robot_config, **_mount(task_config, robot_entry))
  arena = presets.make_arena(task_config.scene, task_config.arena,
                             base_pose=getattr(robot_entity, "base_pose", None))
  task = assembly.Assembly(arena=arena, furniture=furniture_prop, robot=robot_entity,
                           config=task_config)
  randomization.attach(task, task.config.randomize)
  camera_observables.attach(task, task.config)
  env = environment.Environment(task, time_limit=task.config.time_limit, random_state=seed)
  _check_physics_timestep(env, robot)
  _check_layout_fits(env, furniture_prop.name, scale)
  return env


def _configs(robot_entry, options):
  """(config.TaskConfig, the robot's config) of load()'s options."""
  task_names = config.TaskConfig.option_names()
  robot_class = robot_entry.factory.CONFIG
  robot_names = robot_class.option_names()
  for key in options:
    if key not in task_names and key not in robot_names:
      raise errors.UnknownNameError("option", key, task_names + robot_names)
  return (config.TaskConfig(**{k: v for k, v in options.items() if k in task_names}),
          robot_class(**{k: v for k, v in options.items() if k in robot_names}))


def _mount(task_config, robot_entry):
  """The robot factory's keywords for the arena: on the work table an arm's base is raised
  onto its pedestal, so the arm meets the table top as it meets the floor."""
  if task_config.arena != "work_table":
    return {}
  if "arm" not in robot_entry.tags:
    raise errors.OptionValueError(
        f"arena='work_table' is for the fixed-base arms ({', '.join(registry.names('arm'))}); "
        f"the {robot_entry.name} scatters full-size furniture metres out, so use arena='floor'")
  return {"mount_height": work_table.TABLE_HEIGHT}


def _check_physics_timestep(env, robot):
  """Refuses a physics time step too large for the robot's servos (it would diverge)."""
  dt = env.task.config.physics_timestep
  limit, why = env.task.robot.max_physics_timestep(env.physics)
  if dt > limit:
    raise errors.OptionValueError(
        f"physics_timestep {dt!r} s is too large for the {robot}'s servos: at most "
        f"{limit:.4f} s ({why}); MuJoCo integrates a servo's stiffness explicitly, and larger "
        f"steps make the arm oscillate or diverge")


def _check_layout_fits(env, name, scale):
  """Refuses furniture whose parts do not fit on a bounded support (the work table) in
  most of LAYOUT_DRAWS layouts, drawn from random states of its own; puts back what the
  layouts move (the parts' state, and a static rack's pose in the model)."""
  task = env.task
  if not task.arena.support.bounded:
    return
  physics = env.physics
  model, data = physics.model, physics.data
  saved = (model.body_pos.copy(), model.body_quat.copy(), data.qpos.copy(), data.qvel.copy())
  failures = []
  try:
    for draw in range(LAYOUT_DRAWS):
      try:
        task.initializer(physics, np.random.RandomState(draw))
      except composer.EpisodeInitializationError as e:
        failures.append(str(e))
      if len(failures) > LAYOUT_DRAWS // 2:
        depth, width = work_table.TABLE_SIZE
        raise errors.OptionValueError(
            f"{name} at scale {scale:g} does not fit on the work table ({depth:g} x {width:g} "
            f"m): {failures[-1]} (its parts could not be laid out in {len(failures)} of "
            f"{draw + 1} tries)")
  finally:
    model.body_pos[:], model.body_quat[:], data.qpos[:], data.qvel[:] = saved
    physics.forward()


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
