"""The arm experts' motion planning helpers (experts/arm_motion.py, experts/mating.py)."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import mating


@pytest.mark.parametrize("robot,winds", [("sawyer", True), ("panda", False), ("jaco", False),
                                         ("baxter", False)])
def test_only_the_sawyers_wrist_turns_more_than_a_full_turn_between_its_limits(robot, winds):
  # The experts judge such an arm's reaches along the servo's path, not by a converged IK.
  env = ikea_suite.load("stool_square_pine", robot, seed=0, scale=0.5)
  assert mating.winds_past_a_turn(env.task.robot, 0) is winds


@pytest.mark.parametrize("move,turn", [((0.1, 0.35, -0.1), 2.0), ((-0.1, -0.3, 0.05), -2.5)])
def test_servo_path_end_stops_where_the_arm_servoed_there_stops(move, turn):
  """The replay ends near the joints the Sawyer itself reaches with PoseServo from home, its
  wrist turned 2-2.5 rad the same way round."""
  env = ikea_suite.load("stool_square_pine", "sawyer", seed=0, scale=0.5)
  env.reset()
  robot, physics = env.task.robot, env.physics
  pos, rot = robot.tcp_pose(physics)
  goal_pos, goal_rot = pos + move, geometry.rot_z(turn) @ rot
  replayed, distance, angle = arm_motion.servo_path_end(
      robot, 0, robot.arm_qpos(physics), goal_pos, goal_rot, env.control_timestep())
  assert distance < 0.02 and angle < 0.05
  servo, action = arm_motion.PoseServo(), np.zeros(env.action_spec().shape)
  action[6] = -1.0
  for _ in range(200):
    action[:6] = servo(robot, physics, 0, goal_pos, goal_rot)
    env.step(action)
  reached = robot.arm_qpos(physics)
  # Within a few tenths of a radian (the real arm lags, and its redundant joints drift
  # their own way); the wrist the other way round would end a full turn (6.3 rad) away.
  assert np.abs(replayed - reached).max() < 0.3
  assert abs(replayed[6] - reached[6]) < 0.2
