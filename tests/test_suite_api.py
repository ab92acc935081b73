"""The public face: load, names, ALL, and clear errors for bad input."""

import numpy as np
import pytest

import ikea_suite
import ikea_suite.config


def test_names_and_all():
  furniture, robots = ikea_suite.furniture_names(), ikea_suite.robot_names()
  assert ikea_suite.DEFAULT_FURNITURE in furniture and "cursor" in robots
  assert set(ikea_suite.ALL) == {(f, r) for f in furniture for r in robots}
  assert ikea_suite.furniture_names(tag="table")
  assert all(n.startswith("table") for n in ikea_suite.furniture_names(tag="table"))


def test_default_load_is_the_documented_one():
  env = ikea_suite.load(seed=0)
  assert env.task.furniture.name == ikea_suite.DEFAULT_FURNITURE
  assert type(env.task.robot).__name__ == "Cursor"


@pytest.mark.parametrize("kwargs, kind, bad", [
    ({"furniture": "table_ikea_nope"}, "furniture", "table_ikea_nope"),
    ({"robot": "r2d2"}, "robot", "r2d2"),
    ({"gravity_on_mars": True}, "option", "gravity_on_mars"),
])
def test_unknown_names_list_the_valid_ones(kwargs, kind, bad):
  with pytest.raises(ikea_suite.UnknownNameError) as info:
    ikea_suite.load(**kwargs)
  message = str(info.value)
  assert f"unknown {kind} '{bad}'" in message
  valid = {"furniture": ikea_suite.furniture_names(), "robot": ikea_suite.robot_names(),
           "option": ["time_limit", "distance_threshold"]}[kind]
  assert all(name in message for name in valid)


@pytest.mark.parametrize("kwargs, kind", [
    ({"furniture": ["table_four_leg_lack"]}, "furniture"), ({"furniture": 5}, "furniture"),
    ({"robot": ["cursor"]}, "robot"), ({"robot": None}, "robot")])
def test_a_name_that_is_not_a_string_is_refused_by_its_type(kwargs, kind):
  with pytest.raises(ikea_suite.OptionValueError, match=f"^{kind} must be a .*name"):
    ikea_suite.load(**kwargs)


def test_unknown_name_suggests_close_matches():
  with pytest.raises(ikea_suite.UnknownNameError, match="did you mean table_four_leg_lack"):
    ikea_suite.load("table_four_leg_lak")


@pytest.fixture(scope="module")
def env():
  return ikea_suite.load(seed=0)


@pytest.mark.parametrize("action, message", [
    (np.zeros(14), r"shape \(14,\), expected \(15,\)"),
    (np.zeros((15, 1)), r"shape \(15, 1\)"),
    (np.r_[np.zeros(14), np.nan], "non-finite entries: connect=nan"),
    (np.r_[np.inf, np.zeros(14)], "cursor0_move_x=inf"),
    ("go left", "must be numeric.*got a str"),
    (np.array(["0.5"] * 15), "must be numeric.*dtype <U3"),
    (["0.5"] * 15, "must be numeric.*got a list of <U3 values"),
    (np.full(15, 0.5 + 1e-3j), "must be numeric.*dtype complex128"),
    (np.zeros(15, dtype=bool), "must be numeric.*dtype bool"),
    ([True] + [0.0] * 14, "must be numeric.*got a list holding a bool"),
    (np.zeros(15, dtype=object), "must be numeric.*dtype object"),
    ([[0.0], [0.0, 1.0]], "must be numeric.*got a list"),
    (None, "must be numeric.*got a NoneType"),
])
def test_bad_actions_raise_action_error(env, action, message):
  env.reset()
  with pytest.raises(ikea_suite.ActionError, match=message):
    env.step(action)


@pytest.mark.parametrize("action", [np.zeros(15, dtype=np.float32), np.zeros(15, dtype=np.int64),
                                    [0.0] * 15, [0] * 15, tuple(np.zeros(15))])
def test_real_number_actions_of_any_float_or_integer_dtype_are_accepted(env, action):
  env.reset()
  assert env.step(action).mid()


def test_actions_are_checked_on_a_fresh_environment_and_after_the_last_step():
  """composer resets instead of stepping there; the action is checked all the same."""
  fresh = ikea_suite.load(seed=0, time_limit=0.1)
  nan = np.full(15, np.nan)
  with pytest.raises(ikea_suite.ActionError, match="non-finite"):
    fresh.step(nan)
  assert fresh.step(np.zeros(15)).first()
  while not fresh.step(np.zeros(15)).last():
    pass
  with pytest.raises(ikea_suite.ActionError, match="non-finite"):
    fresh.step(nan)
  with pytest.raises(ikea_suite.ActionError, match="shape"):
    fresh.step(np.zeros(3))
  assert fresh.step(np.zeros(15)).first()


def test_huge_finite_actions_are_clipped_not_refused(env):
  """Entries whose sum overflows are still finite: clipped to the spec like any other."""
  env.reset()
  action = np.zeros(15)
  action[:2] = 1e308, 1e308
  assert env.step(action).mid()


def test_thresholds_are_options():
  env = ikea_suite.load(seed=0, distance_threshold=0.05, up_threshold=0.9, forward_threshold=0.8)
  thresholds = env.task.thresholds
  assert (thresholds.distance, thresholds.up_cos, thresholds.forward_cos) == (0.05, 0.9, 0.8)


def test_robot_options_reach_the_robot():
  env = ikea_suite.load(seed=0, move_speed=0.25)
  assert env.task.robot.move_speed == 0.25


def test_time_limit_scales_with_the_part_count():
  small = ikea_suite.load("stool_round_frosta", seed=0)
  large = ikea_suite.load("bookcase_shelf_unit_billy", seed=0)
  assert small.time_limit == ikea_suite.config.default_time_limit(len(small.task.furniture.parts))
  assert small.time_limit < large.time_limit
  assert ikea_suite.load("stool_round_frosta", seed=0, time_limit=3.0).time_limit == 3.0


@pytest.mark.parametrize("robot, option, value, valid", [
    ("cursor", "up_threshold", 2, "[-1, 1)"),
    ("cursor", "forward_threshold", -1.5, "[-1, 1)"),
    ("cursor", "distance_threshold", 0.0, "(0, inf)"),
    ("cursor", "time_limit", -3, "(0, inf)"),
    ("cursor", "control_timestep", float("inf"), "(0, 1]"),
    ("cursor", "physics_timestep", 0, "(0, inf)"),
    ("cursor", "connection_reward", float("nan"), "(-inf, inf)"),
    ("cursor", "completion_bonus", "ten", "a number"),
    ("cursor", "move_speed", -0.5, "(0, inf)"),
    ("cursor", "rotate_speed", 0, "(0, inf)"),
    ("cursor", "grasp_margin", -0.01, "[0, inf)"),
    ("cursor", "radius", 0, "(0, inf)"),
    ("cursor", "workspace", ((0, 0, 0), (1, 1)), "shape (2, 3)"),
    ("cursor", "workspace", ((0, 0, 1), (1, 1, 1)), "low < high"),
    ("cursor", "spread", -1, ">= 0"),
    ("sawyer", "max_translation", 0, "(0, inf)"),
    ("sawyer", "max_rotation", -1, "(0, inf)"),
    ("sawyer", "base_pos", (0, 0), "shape (3,)"),
    ("sawyer", "base_yaw", "north", "a number"),
    ("sawyer", "camera_size", (0, 84), "whole numbers of pixels"),
    ("sawyer", "wrist_camera", "yes", "True, False"),
])
def test_every_option_is_range_checked(robot, option, value, valid):
  with pytest.raises(ikea_suite.OptionValueError) as info:
    ikea_suite.load("table_four_leg_lack", robot, **{option: value})
  assert option in str(info.value) and valid in str(info.value)


def test_control_timestep_must_be_a_multiple_of_the_physics_timestep():
  with pytest.raises(ikea_suite.OptionValueError, match="whole multiple"):
    ikea_suite.load(control_timestep=0.005, physics_timestep=0.002)
  assert ikea_suite.load(control_timestep=0.03, physics_timestep=0.002).control_timestep() == 0.03


def test_an_ik_failure_holds_the_arm_still(monkeypatch):
  from ikea_suite.robots import ik_qp
  env = ikea_suite.load("table_four_leg_lack", "panda", seed=0)
  env.reset()
  robot = env.task.robot
  for _ in range(3):
    env.step(np.zeros(env.action_spec().shape))
  # The step's QP solver reports the problem infeasible (DAQP's exit flag -1).
  monkeypatch.setattr(ik_qp.daqp, "solve", lambda *args, **kwargs: (None, None, -1, {}))
  before = robot.arm_qpos(env.physics)
  action = np.zeros(env.action_spec().shape)
  action[:3] = 1.0   # a move the IK now cannot solve
  env.step(action)
  assert robot.ik_failures == 1
  np.testing.assert_allclose(robot.arm_qpos(env.physics), before, atol=2e-3)


def test_doctor_reports_versions_and_rendering(capsys):
  from ikea_suite import cli
  from ikea_suite import doctor
  problems = doctor.main()
  out = capsys.readouterr().out
  for name in ("python", "mujoco", "dm_control", "numpy", "MUJOCO_GL", "offscreen GL"):
    assert name in out
  assert f"{problems} problem(s) found" in out
  assert cli.main(["--doctor"]) == (1 if problems else 0)


def test_doctor_flags_an_unsupported_python(monkeypatch):
  from ikea_suite import doctor
  monkeypatch.setattr(doctor.sys, "version_info", (3, 13, 0, "final", 0))
  (python,) = [c for c in doctor.checks() if c[0] == "python"]
  assert python[2] == "Python 3.13 is not supported" and "3.12" in python[3]
