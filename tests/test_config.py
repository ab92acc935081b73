"""The one configuration: config.py's dataclasses are load()'s defaults and checks, every bad
option is an IkeaSuiteError naming the value and what is valid, and combinations that cannot
work are refused at load()."""

import dataclasses

import numpy as np
import pytest
from dm_control import composer

import ikea_suite
import ikea_suite.gym
from ikea_suite import config
from ikea_suite.arenas import floor
from ikea_suite.batch import settings
from ikea_suite.environment import Environment
from ikea_suite.props import catalog
from ikea_suite.props import furniture as furniture_lib
from ikea_suite.props import scaling
from ikea_suite.robots import cursor
from ikea_suite.robots import registry
from ikea_suite.tasks import assembly
from ikea_suite.tasks import placement

TABLE = "table_four_leg_lack"
BAD = ikea_suite.OptionValueError

# (load() keywords, error, text the message must hold): one case per invalid input.
INVALID = [
    # A scale range reaching a massless part: MuJoCo's mass matrix would be singular.
    (dict(randomize={"part_mass": (0, 0)}), BAD, "0.01 <= low"),
    (dict(randomize={"part_mass": (0.001, 1.0)}), BAD, "mass matrix singular"),
    (dict(randomize=True), BAD, "randomize must be None, a factor or group name"),
    (dict(randomize=5), BAD, "randomize must be None"),
    (dict(randomize=1.5), BAD, "randomize must be None"),
    (dict(randomize=[5]), BAD, "randomize names must be strings"),
    (dict(randomize={"gravity": (0, 1e9)}), BAD, "<= 19.62 (0 to twice Earth's gravity)"),
    (dict(randomize={"friction": (0.5, np.inf)}), BAD, "friction"),
    (dict(randomize={"light_count": (1.5, 2)}), BAD, "whole numbers"),
    (dict(randomize={"friction": "12"}), BAD, "(low, high) range of numbers"),
    (dict(randomize={"camera_jitter": np.inf}), BAD, "finite amount"),
    (dict(cameras=5), BAD, "cameras must be a name or a sequence of names"),
    (dict(camera_outputs=5), BAD, "camera_outputs must be a name or a sequence of names"),
    (dict(cameras=("front",), camera_outputs=()), BAD, "need camera_outputs"),
    (dict(preassembled=None), BAD, "preassembled must be a count >= 0 or a (low, high)"),
    (dict(preassembled=True), BAD, "preassembled must be a count"),
    (dict(furniture=["table_four_leg_lack"]), BAD, "furniture must be a catalog name"),
    (dict(robot=["cursor"]), BAD, "robot must be a robot name (str), got ['cursor']; valid:"),
    (dict(seed="abc"), BAD, "seed must be None or a whole number from 0 to 4294967295"),
    (dict(seed=1.5), BAD, "seed must be None or a whole number"),
    (dict(seed=-1), BAD, "seed must be None or a whole number"),
    (dict(seed=2**32), BAD, "got 4294967296"),
    (dict(seed=True), BAD, "seed must be None or a whole number"),
    (dict(goal_image="no"), BAD, "goal_image must be a bool (True, False), got 'no'"),
    (dict(goal_image=1), BAD, "goal_image must be a bool"),
    (dict(goal_image="yes"), BAD, "goal_image must be a bool"),
    (dict(robot="sawyer", wrist_camera=1), BAD, "wrist_camera must be a bool"),
    (dict(image_size=True), BAD, "image_size must be an int or (height, width)"),
    (dict(scale="1.0"), BAD, "scale must be a number from 0.2 to 2"),
    (dict(scale=True), BAD, "scale must be a number"),
    (dict(time_limit=True), BAD, "time_limit must be a number"),
    (dict(spread="1"), BAD, "spread must be a number >= 0"),
    (dict(reward=["sparse"]), ikea_suite.UnknownNameError, "valid reward names"),
    (dict(scene=None), ikea_suite.UnknownNameError, "valid scene names"),
    (dict(robot="sawyer", base_pos=(0, 0, -5)), BAD, "base_pos must have |x|, |y| <= 3 m"),
    (dict(robot="sawyer", base_pos=(0, 0, 0.5)), BAD, "to 0.3 m"),
    (dict(robot="panda", base_pos=(10, 0, 0)), BAD, "base_pos must have"),
    (dict(robot="panda", base_pos=(True, 0, 0)), BAD, "base_pos must be numbers"),
    (dict(robot="panda", base_pos=("0", "0", "0")), BAD, "base_pos must be numbers"),
    (dict(robot="jaco", camera_size=(84, True)), BAD, "camera_size must be two whole numbers"),
    (dict(robot="panda", control_mode=3), ikea_suite.UnknownNameError, "task_space"),
    # Time steps too large for the arms' servos (the Cursor has none).
    (dict(robot="sawyer", physics_timestep=0.05), BAD, "too large for the sawyer's servos"),
    (dict(robot="panda", physics_timestep=0.05), BAD, "at most 0.0116 s"),
    (dict(robot="jaco", physics_timestep=0.05), BAD, "too large for the jaco's servos"),
    (dict(robot="baxter", physics_timestep=0.01), BAD, "too large for the baxter's servos"),
    (dict(robot="panda", control_mode="impedance", impedance_stiffness=(1e8, 1e5)), BAD,
     "physics_timestep 0.002 s is too large for the panda's servos"),
    # Furniture that does not fit the work table at that scale.
    (dict(furniture="desk_side_unit_w120_black", robot="panda", arena="work_table", scale=0.5),
     BAD, "does not fit on the work table (1 x 1.6 m)"),
    (dict(furniture="dresser_chest_three_white_oak", robot="panda", arena="work_table",
          scale=0.5), BAD, "does not fit on the work table"),
    (dict(furniture="shelving_posts_steel", robot="panda", arena="work_table", scale=0.5), BAD,
     "does not fit on the work table"),
]


@pytest.mark.parametrize("kwargs, error, text", INVALID,
                         ids=[str(kwargs) for kwargs, _, _ in INVALID])
def test_an_invalid_option_raises_naming_it(kwargs, error, text):
  kwargs = dict(kwargs)
  furniture, robot = kwargs.pop("furniture", TABLE), kwargs.pop("robot", "cursor")
  with pytest.raises(error) as info:
    ikea_suite.load(furniture, robot, **kwargs).reset()
  assert text in str(info.value)


@pytest.mark.parametrize("kwargs, error, text", [
    (dict(render_camera=["front"]), ikea_suite.UnknownNameError, "valid camera names: front"),
    (dict(render_size="big"), BAD, "render_size must be (height, width) of ints in 1..2048"),
    (dict(render_size=(0, 0)), BAD, "got (0, 0)"),
    (dict(render_size=84), BAD, "render_size must be (height, width)"),
    (dict(render_mode=True), ikea_suite.UnknownNameError, "render mode"),
])
def test_an_invalid_gym_option_raises_naming_it(kwargs, error, text):
  with pytest.raises(error, match=None) as info:
    ikea_suite.gym.AssemblyEnv(**kwargs)
  assert text in str(info.value)


@pytest.mark.parametrize("seed", ["x", 1.5, -1, 2**32, True])
def test_an_invalid_gym_seed_raises_naming_it(seed):
  env = ikea_suite.gym.AssemblyEnv()
  with pytest.raises(BAD, match="seed must be None or a whole number"):
    env.reset(seed=seed)
  env.close()


def test_a_large_render_size_is_given_its_frame(gl):
  env = ikea_suite.gym.AssemblyEnv(render_mode="rgb_array", render_size=(500, 700))
  env.reset(seed=0)
  assert env.render().shape == (500, 700, 3)
  env.close()


def test_the_refused_combinations_work_just_inside_their_bounds():
  ikea_suite.load(TABLE, "panda", physics_timestep=0.01)          # bound 0.0116 s
  ikea_suite.load(TABLE, "sawyer", base_pos=(-0.55, 0.0, 0.3))
  env = ikea_suite.load(TABLE, "cursor", seed=0,
                        randomize={"part_mass": (0.01, 0.01), "gravity": (19.62, 19.62)})
  env.reset()
  assert env.step(np.zeros(env.action_spec().shape)).mid()
  masses = env.physics.model.body_mass[env.task.furniture.body_ids]
  assert np.all(masses > 0)


def test_furniture_that_fits_the_work_table_in_most_layouts_is_accepted_and_resets():
  # Its parts fit on the table in 18 of 20 layouts: a reset tries again when they do not.
  env = ikea_suite.load("table_four_leg_w140_dark", "panda", seed=0, scale=0.5,
                        arena="work_table")
  for _ in range(6):
    assert env.reset().first()
  with pytest.raises(BAD, match=r"could not be laid out in 5 of 5 tries"):
    ikea_suite.load("dresser_chest_three_white_oak", "panda", scale=0.5, arena="work_table")


def test_a_reset_that_cannot_start_raises_a_suite_error():
  class Failing(placement.PartInitializer):
    preassembled_pairs = ()

    def __call__(self, physics, random_state):
      raise composer.EpisodeInitializationError("no room")

  class Massless(Failing):   # what a part_mass factor of 0 did
    def __call__(self, physics, random_state):
      physics.model.body_mass[1:] = 0.0
      physics.model.body_inertia[1:] = 0.0

  for initializer, reason in ((Failing(), "no room"), (Massless(), "mjWARN_INERTIA")):
    furniture = furniture_lib.Furniture(catalog.spec(TABLE))
    task = assembly.Assembly(arena=floor.FloorArena(), furniture=furniture,
                             robot=cursor.Cursor(), initializer=initializer)
    env = Environment(task, time_limit=1.0, random_state=0)
    with pytest.raises(ikea_suite.EpisodeStartError, match=reason):
      env.reset()


# -- the config is the one source of defaults -------------------------------------------


def test_load_takes_exactly_the_configs_options():
  for robot in ikea_suite.robot_names():
    with pytest.raises(ikea_suite.UnknownNameError) as info:
      ikea_suite.load(TABLE, robot, no_such_option=1)
    valid = set(info.value.valid)
    assert valid == (set(config.TaskConfig.option_names())
                     | set(registry.get(robot).factory.CONFIG.option_names()))


def test_the_environment_keeps_the_resolved_config():
  env = ikea_suite.load(TABLE, "sawyer", seed=0, scale=0.5, preassembled=1, time_limit=7,
                        cameras="front", goal_image=False)
  task_config, robot_config = env.task.config, env.task.robot.config
  assert isinstance(task_config, config.TaskConfig)
  assert task_config.time_limit == 7.0 == env.time_limit
  assert task_config.distance_threshold == config.DISTANCE_THRESHOLD * 0.5
  assert env.task.thresholds.distance == task_config.distance_threshold
  assert task_config.preassembled == (1, 1) and task_config.cameras == ("front",)
  assert task_config.spread is None   # an arm: its whole reach band
  assert isinstance(robot_config, config.SawyerConfig)
  assert robot_config.base_pos == (-0.55, 0.0, 0.0)
  with pytest.raises(dataclasses.FrozenInstanceError):
    task_config.scale = 1.0
  cursor_env = ikea_suite.load(TABLE, "cursor", seed=0)
  parts = len(cursor_env.task.furniture.parts)
  assert cursor_env.task.config == config.TaskConfig().resolved(parts, scattered=True, scale=1.0)
  assert cursor_env.task.config.spread == config.SCATTER_SPREAD
  assert cursor_env.time_limit == config.default_time_limit(parts)


def test_each_robot_points_at_its_config_and_the_arm_base_defaults_are_its_own():
  for name in ikea_suite.robot_names():
    factory = registry.get(name).factory
    assert issubclass(factory.CONFIG, config.RobotConfig)
    env = ikea_suite.load(TABLE, name, seed=0, scale=0.5 if name != "cursor" else 1.0)
    assert env.task.robot.config == factory.CONFIG()
  assert config.ARM_CONFIGS == {name: registry.get(name).factory.CONFIG
                                for name in registry.names("arm")}


def test_each_robot_loads_at_its_work_scale_unless_given_one():
  assert config.TaskConfig().scale is None
  assert config.CursorConfig.WORK_SCALE == 1.0
  for name in ikea_suite.robot_names():
    work_scale = registry.get(name).factory.CONFIG.WORK_SCALE
    assert work_scale == (1.0 if name == "cursor" else 0.5)
    env = ikea_suite.load(TABLE, name, seed=0)
    assert env.task.furniture.scale == env.task.config.scale == work_scale
    assert env.task.config.distance_threshold == config.DISTANCE_THRESHOLD * work_scale
  full = ikea_suite.load(TABLE, "sawyer", seed=0, scale=1.0)
  assert full.task.furniture.scale == full.task.config.scale == 1.0
  row = {(r.scope, r.name): r for r in config.option_rows()}["task", "scale"]
  assert row.default == "None" and "0.5 for the arms" in row.meaning


def test_a_task_config_scale_must_be_the_furniture_s():
  furniture = furniture_lib.Furniture(scaling.scaled(catalog.spec(TABLE), 0.5))
  with pytest.raises(BAD, match="scale 1.0 differs from the furniture's, which is built at 0.5"):
    assembly.Assembly(arena=floor.FloorArena(), furniture=furniture, robot=cursor.Cursor(),
                      config=config.TaskConfig(scale=1.0))
  task = assembly.Assembly(arena=floor.FloorArena(), furniture=furniture, robot=cursor.Cursor())
  assert task.config.scale == 0.5


def test_the_work_table_raises_the_arm_but_keeps_its_config():
  env = ikea_suite.load(TABLE, "panda", seed=0, scale=0.5, arena="work_table")
  assert env.task.robot.config.base_pos == (-0.5, 0.0, 0.0)
  assert env.task.robot.base_pose[0][2] == pytest.approx(0.75)


def test_the_batched_task_takes_its_subset_of_the_same_configs():
  resolved = settings.resolve(5)
  assert resolved.task == config.TaskConfig().resolved(5, scattered=True, scale=1.0)
  assert resolved.cursor_config == config.CursorConfig()
  assert resolved.spread == config.SCATTER_SPREAD
  assert resolved.thresholds.distance == config.DISTANCE_THRESHOLD
  assert resolved.substeps == 25
  assert set(settings.OPTIONS) <= (set(config.TaskConfig.option_names())
                                   | set(config.CursorConfig.option_names()))
  with pytest.raises(BAD, match="whole multiple"):
    settings.resolve(5, control_timestep=0.051)


def test_the_layout_is_chosen_in_one_place():
  for robot, kind in (("cursor", "ScatteredParts"), ("sawyer", "ReachableParts")):
    env = ikea_suite.load(TABLE, robot, seed=0, scale=0.5 if robot != "cursor" else 1.0)
    assert type(env.task.initializer).__name__ == kind
    furniture = furniture_lib.Furniture(catalog.spec(TABLE))
    entity = registry.get(robot).factory()
    task = assembly.Assembly(arena=floor.FloorArena(), furniture=furniture, robot=entity)
    assert type(task.initializer).__name__ == kind


def test_option_rows_cover_every_option_with_its_meaning():
  rows = config.option_rows()
  names = {(row.scope, row.name) for row in rows}
  assert names == ({("task", n) for n in config.TaskConfig.option_names()}
                   | {("cursor", n) for n in config.CursorConfig.option_names()}
                   | {("arm", n) for n in config.ArmConfig.option_names()}
                   | {("gym", n) for n in config.GymConfig.option_names()})
  assert all(row.meaning and "\n" not in row.meaning for row in rows)
  by_name = {(row.scope, row.name): row for row in rows}
  assert by_name["task", "control_timestep"].default == "0.05"
  assert by_name["task", "control_timestep"].meaning.endswith("[s]")
  assert by_name["task", "yaw_range"].default == "pi"
  assert "panda (-0.5, 0.0, 0.0)" in by_name["arm", "base_pos"].default


def test_a_config_can_be_given_whole():
  task_config = config.TaskConfig(reward="dense", up_threshold=0.95)
  robot_config = config.CursorConfig(move_speed=0.25)
  entity = cursor.Cursor(config=robot_config, rotate_speed=1.0)
  assert entity.config == dataclasses.replace(robot_config, rotate_speed=1.0)
  furniture = furniture_lib.Furniture(catalog.spec(TABLE))
  task = assembly.Assembly(arena=floor.FloorArena(), furniture=furniture, robot=entity,
                           config=task_config)
  assert task.config.reward == "dense" and task.thresholds.up_cos == 0.95
  with pytest.raises(BAD, match="config must be a CursorConfig"):
    cursor.Cursor(config=task_config)
