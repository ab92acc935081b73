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


def test_the_jacos_wrist_folds_in_to_its_cramped_within():
  """The Jaco's servo brings a level tool to a pose with its wrist CRAMPED_WITHIN (0.3 m)
  from the base, a pose the default (the Sawyer's and Panda's 0.45 m) counts as cramped."""
  env = ikea_suite.load("stool_square_pine", "jaco", seed=0, scale=0.5)
  env.reset()
  robot, physics = env.task.robot, env.physics
  base, _ = robot.base_pose
  bearing, heading = 0.5, -1.0   # the wrist ahead and to the left, the tool pointing right
  approach = np.array([np.cos(heading), np.sin(heading), 0.0])
  wrist = base + robot.CRAMPED_WITHIN * np.array([np.cos(bearing), np.sin(bearing), 0.0])
  goal_pos = wrist + arm_motion.WRIST_BACK * approach + [0.0, 0.0, 0.2]
  goal_rot = np.column_stack([[0.0, 0.0, 1.0], np.cross(approach, [0.0, 0.0, 1.0]), approach])
  _, distance, angle = arm_motion.servo_path_end(
      robot, 0, robot.arm_qpos(physics), goal_pos, goal_rot, env.control_timestep(),
      arm_motion.CARRY_TURN)
  assert distance < 0.01 and angle < 0.05
  assert arm_motion.cramped(robot, goal_pos, approach) == pytest.approx(0.0, abs=1e-9)
  sawyer = ikea_suite.load("stool_square_pine", "sawyer", seed=0, scale=0.5).task.robot
  shift = sawyer.base_pose[0] - base
  assert arm_motion.cramped(sawyer, goal_pos + shift, approach) > 0.1
