"""Arm robots: build, action specs per control mode, observables, control tracking."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.robots import control_modes

ARMS = ("sawyer", "baxter", "panda", "jaco")
JOINT_COUNT = {"sawyer": 7, "baxter": 7, "panda": 7, "jaco": 6}


@pytest.mark.parametrize("robot", ARMS)
@pytest.mark.parametrize("mode", control_modes.MODES)
def test_action_spec_per_mode(robot, mode):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=0, control_mode=mode)
  names = env.action_spec().name.split("\t")
  arms = 2 if robot == "baxter" else 1
  per_arm = 7 if mode in ("task_space", "task_space_pose", "impedance") else JOINT_COUNT[robot] + 1
  assert len(names) == arms * per_arm + 1
  assert names[-1] == "connect" and names.count("connect") == 1
  if robot == "baxter":
    assert names[0].startswith("right_") and names[per_arm].startswith("left_")
  env.reset()
  action = np.zeros(len(names))
  action[[i for i, n in enumerate(names) if n.endswith("gripper")]] = -1.0   # keep open
  for _ in range(3):
    timestep = env.step(action)
  positions = timestep.observation["robot/joint_positions"]
  assert positions.shape == (arms * JOINT_COUNT[robot],) and np.all(np.isfinite(positions))
  assert timestep.observation["robot/tcp_positions"].shape == (arms, 3)
  assert timestep.observation["robot/tcp_quaternions"].shape == (arms, 4)
  opening = timestep.observation["robot/gripper_opening"]
  assert opening.shape == (arms,) and np.all(opening > 0.9)   # grippers start open


def test_unknown_control_mode_lists_valid_ones():
  with pytest.raises(ikea_suite.UnknownNameError, match="joint_torque"):
    ikea_suite.load("table_four_leg_lack", "sawyer", control_mode="velocity")


_FULL_SIZE_SPILLS = pytest.mark.xfail(strict=True, reason=(
    "the full-size Lack's 40 cm legs crowd the Jaco's 0.55-0.70 m and the Baxter's "
    "0.62-0.82 m band (their tool-down floor reach): 18% and 10% of parts spill outwards; "
    "they assemble at their work scale, 0.5"))


@pytest.mark.parametrize("robot", [pytest.param(r, marks=_FULL_SIZE_SPILLS)
                                   if r in ("jaco", "baxter") else r for r in ARMS])
def test_home_pose_points_tool_down_and_parts_lie_within_reach(robot):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=1, scale=1.0)   # the full-size layout
  arm = env.task.robot
  base_pos, _ = arm.base_pose
  within = []
  for _ in range(10):
    env.reset()
    for i in range(arm.num_arms):
      pos, rot = arm.tcp_pose(env.physics, i)
      assert rot[2, 2] < -0.99, "tool should point down at home"
      assert 0.2 < pos[2] < 0.5
    parts, _ = env.task.furniture.part_poses(env.physics)
    distance = np.linalg.norm(parts[:, :2] - base_pos[:2], axis=1)
    assert distance[env.task.root_part] < arm.REACH   # the part everything is built onto
    assert np.all(distance > 0.5)                      # nothing under the arm's base
    within.extend(distance < arm.REACH + 0.01)
  assert np.mean(within) > 0.9   # a crowded ring spills a few parts outwards


@pytest.mark.parametrize("robot", ("sawyer", "jaco", "baxter"))
def test_task_space_delta_moves_tool(robot):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=0)
  env.reset()
  arm = env.task.robot
  start = arm.tcp_pose(env.physics, 0)
  action = np.zeros(env.action_spec().shape)
  action[2] = 1.0   # move_z on the first arm
  for _ in range(4):   # 4 x 2.5 cm target steps
    env.step(action)
  action[:] = 0.0
  for _ in range(30):
    env.step(action)
  pos, rot = arm.tcp_pose(env.physics, 0)
  np.testing.assert_allclose(pos - start[0], [0.0, 0.0, 0.10], atol=0.01)
  np.testing.assert_allclose(pos, arm.task_space_target(0)[0], atol=0.005)
  assert np.trace(rot.T @ start[1]) > 3 - 0.01   # orientation held


def test_task_space_rotation_turns_tool_about_world_z():
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0)
  env.reset()
  arm = env.task.robot
  _, start = arm.tcp_pose(env.physics)
  action = np.zeros(env.action_spec().shape)
  action[5] = 1.0
  for _ in range(4):   # 4 x 0.15 rad
    env.step(action)
  action[5] = 0.0
  for _ in range(20):
    env.step(action)
  _, rot = arm.tcp_pose(env.physics)
  turn = rot @ start.T
  assert abs(np.arctan2(turn[1, 0], turn[0, 0]) - 0.6) < 0.03


def test_task_space_targets_move_turn_and_stay_near_the_tool_and_in_the_workspace():
  """A delta target moves max_translation per unit action and turns max_rotation about the
  world axes; it stays within max_lag of the measured tool and inside its workspace box."""
  workspace = [[[-1.0, -1.0, 0.0], [1.0, 1.0, 0.5]]] * 2
  targets = control_modes.TaskSpaceTargets(2, 0.02, 0.1, workspace, max_lag=0.1)
  targets.reset([([0.2, 0.0, 0.3], np.eye(3)), ([0.0, 0.3, 0.3], np.eye(3))])
  tools = targets.pos
  targets.apply_deltas(np.array([[1.0, -0.5, 0.0, 0.0, 0.0, 1.0, -1.0],
                                 [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]]), tools)
  np.testing.assert_allclose(targets.pos, [[0.22, -0.01, 0.3], [0.0, 0.3, 0.3]], atol=1e-15)
  np.testing.assert_allclose(targets.rot[0], ikea_suite.geometry.rot_z(0.1), atol=1e-15)
  np.testing.assert_array_equal(targets.rot[1], np.eye(3))   # no turn: the rotation as it was
  for _ in range(20):   # pushed on while the tools stay put: held 0.1 m ahead of them
    targets.apply_deltas(np.array([[1.0, 0, 0, 0, 0, 0, 0], [0, 0, 1.0, 0, 0, 0, 0]]), tools)
  np.testing.assert_allclose(np.linalg.norm(targets.pos[0] - tools[0]), 0.1, atol=1e-12)
  for _ in range(20):   # the tool follows: the target meets the box's top at 0.5 m
    targets.apply_deltas(np.array([[0, 0, 0, 0, 0, 0, 0], [0, 0, 1.0, 0, 0, 0, 0]]), targets.pos)
  assert targets.pos[1, 2] == 0.5
  kept = targets.pos
  kept[:] = 9.0   # a copy
  assert np.all(targets.pos < 1.0)


def test_task_space_pose_reaches_absolute_target():
  env = ikea_suite.load("table_four_leg_lack", "panda", seed=0, control_mode="task_space_pose")
  env.reset()
  arm = env.task.robot
  action = np.zeros(env.action_spec().shape)
  action[:3] = [0.2, -0.3, -0.2]
  for _ in range(40):
    env.step(action)
  target, _ = arm.task_space_target()
  pos, rot = arm.tcp_pose(env.physics)
  np.testing.assert_allclose(pos, target, atol=0.01)
  assert rot[2, 2] < -0.99


def test_joint_position_mode_tracks_targets():
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0, control_mode="joint_position")
  env.reset()
  action = np.zeros(env.action_spec().shape)
  action[:7] = [0.1, -0.3, 0.0, 0.5, 0.0, 0.3, 0.0]
  for _ in range(40):
    timestep = env.step(action)
  arm = env.task.robot
  low, high = arm.joint_limits(0)
  expected = (low + high) / 2 + action[:7] * (high - low) / 2
  np.testing.assert_allclose(timestep.observation["robot/joint_positions"], expected, atol=0.02)


def test_joint_torque_mode_moves_joint_in_torque_direction():
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0, control_mode="joint_torque")
  env.reset()
  start = env.task.robot.joint_positions(env.physics)
  action = np.zeros(env.action_spec().shape)
  action[0] = 0.2   # base joint: turns about the vertical, no gravity load
  for _ in range(5):
    env.step(action)
  moved = env.task.robot.joint_positions(env.physics) - start
  assert moved[0] > 0.05



def test_wrist_camera_observable_on_request(gl):
  env = ikea_suite.load("table_four_leg_lack", "baxter", seed=0)
  assert not any("camera" in name for name in env.observation_spec())   # off by default
  env = ikea_suite.load("table_four_leg_lack", "baxter", seed=0, wrist_camera=True,
                        camera_size=(32, 40))
  timestep = env.reset()
  for side in ("right", "left"):
    image = timestep.observation[f"cameras/{side}_wrist_rgb"]
    assert image.shape == (32, 40, 3) and image.std() > 0


def test_contacts_at_reports_what_the_arm_would_touch_without_moving_it():
  env = ikea_suite.load("chair_back_dark_bar", "sawyer", scale=0.5, seed=1000)
  env.reset()
  robot, physics = env.task.robot, env.physics
  home = robot.arm_qpos(physics)
  before = physics.data.qpos.copy()
  assert robot.contacts_at(physics, home) == []
  down = home.copy()
  down[1] += 1.5   # the shoulder pitched down: the forearm and the hand into the floor
  floor = physics.model.name2id("world", "body")
  touched = robot.contacts_at(physics, down)
  links = {physics.model.id2name(g, "geom") for g, body, depth in touched
           if body == floor and depth > 0.0}
  assert "sawyer/right_l4_2_col0" in links
  arm_only = {physics.model.id2name(g, "geom") for g, _, _ in robot.contacts_at(
      physics, down, hand=False)}
  assert "sawyer/right_l4_2_col0" in arm_only
  assert not any("finger" in name or "gripper" in name for name in arm_only)
  np.testing.assert_array_equal(physics.data.qpos, before)   # nothing moved
