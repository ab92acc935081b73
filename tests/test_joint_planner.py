"""The joint-space planner for stalled carries (experts/joint_planner.py)."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.experts import arm_motion
from ikea_suite.experts import joint_planner

# The planner needs OMPL (the `planning` extra, in `test` too).
needs_ompl = pytest.mark.skipif(not joint_planner.AVAILABLE, reason="OMPL is not installed")


def _scene_with_a_wall():
  """A Panda at home, a tool goal 0.47 m to its side, and the stool's seat moved to stand
  where the straight joint move to that goal takes the hand."""
  env = ikea_suite.load("stool_square_pine", "panda", seed=0, scale=0.5)
  env.reset()
  robot, physics = env.task.robot, env.physics
  pos, rot = robot.tcp_pose(physics)
  goal_pos = pos + np.array([0.0, 0.45, -0.15])
  scene = joint_planner.ArmScene(robot, physics, 0)
  goal_q = joint_planner.ik_goals(robot, scene, goal_pos, rot, seeds=1)[0][0]
  halfway = scene.full((scene.q0[scene.index] + goal_q) / 2)
  base_pos, base_rot = robot.base_pose
  hand = base_rot @ robot.ik.tcp_poses(halfway)[0][0] + base_pos
  _move_part(env, 0, hand)
  return env, goal_pos, rot


def _move_part(env, part, pos):
  model, physics = env.physics.model, env.physics
  free = joint_planner._free_body(model, env.task.furniture.body_ids[part])
  adr = model.jnt_qposadr[model.body_jntadr[free]]
  physics.data.qpos[adr:adr + 3] = pos
  physics.forward()


def _check_path(env, path, goal_pos, goal_rot, held_body=None):
  robot, physics = env.task.robot, env.physics
  scene = joint_planner.ArmScene(robot, physics, 0, held_body)
  arm_q = path.q[:, scene.index]
  np.testing.assert_array_equal(path.q[0], robot.arm_qpos(physics))   # from where it is
  low, high = robot.ik.limits
  assert (arm_q >= low[scene.index]).all() and (arm_q <= high[scene.index]).all()
  assert np.abs(np.diff(arm_q, axis=0)).max() <= 0.05 + 1e-9
  for a, b in zip(arm_q[:-1], arm_q[1:]):   # every move, checked 1 cm of joint apart
    assert scene.motion_valid(a, b, step=0.01)
  base_pos, base_rot = robot.base_pose
  pos, rot = robot.ik.tcp_poses(path.q[-1])[0]
  assert np.linalg.norm(base_rot @ pos + base_pos - goal_pos) < 0.005
  assert path.goal_miss < 0.01
  return scene


@needs_ompl
def test_the_path_goes_round_a_part_in_the_straight_moves_way():
  env, goal_pos, goal_rot = _scene_with_a_wall()
  robot, physics = env.task.robot, env.physics
  # One IK goal, the one whose straight move the wall blocks: the search must go round.
  path = joint_planner.plan_to_pose(robot, physics, 0, goal_pos, goal_rot, ik_seeds=1)
  assert path is not None
  scene = _check_path(env, path, goal_pos, goal_rot)
  start = scene.q0[scene.index]
  assert not scene.motion_valid(start, path.q[-1, scene.index])   # the wall is in the way
  # Deterministic: the same state plans the same path.
  again = joint_planner.plan_to_pose(robot, physics, 0, goal_pos, goal_rot, ik_seeds=1)
  np.testing.assert_array_equal(again.q, path.q)


@needs_ompl
def test_the_held_part_moves_with_the_hand_and_is_kept_clear():
  env, goal_pos, goal_rot = _scene_with_a_wall()
  robot, physics = env.task.robot, env.physics
  tcp, rot = robot.tcp_pose(physics)
  # With the tool 12 cm over the surface the parts lie on, the arm is clear ...
  surface = env.task.arena.support.height
  low_goal = joint_planner.ik_goals(robot, joint_planner.ArmScene(robot, physics, 0),
                                    np.array([tcp[0], tcp[1], surface + 0.12]), rot)
  assert low_goal
  # ... but a leg hanging 12 cm below the tool centre, as if held, would reach into it.
  _move_part(env, 1, tcp + 0.12 * rot[:, 2])
  held = env.task.furniture.body_ids[1]
  assert not joint_planner.ArmScene(robot, physics, 0, held).valid(low_goal[0][0])
  path = joint_planner.plan_to_pose(robot, physics, 0, goal_pos, goal_rot, held_body=held)
  assert path is not None
  _check_path(env, path, goal_pos, goal_rot, held)


def test_without_ompl_there_is_no_plan(monkeypatch):
  env = ikea_suite.load("stool_square_pine", "panda", seed=0, scale=0.5)
  env.reset()
  robot, physics = env.task.robot, env.physics
  pos, rot = robot.tcp_pose(physics)
  monkeypatch.setattr(joint_planner, "AVAILABLE", False)
  assert joint_planner.plan_to_pose(robot, physics, 0, pos + [0.0, 0.1, 0.0], rot) is None


@needs_ompl
def test_the_arm_follows_a_planned_path_through_task_space_actions():
  env, goal_pos, goal_rot = _scene_with_a_wall()
  robot, physics = env.task.robot, env.physics
  path = joint_planner.plan_to_pose(robot, physics, 0, goal_pos, goal_rot)
  follower, action = arm_motion.Unwinder(), np.zeros(env.action_spec().shape)
  follower.follow(robot, 0, path.q)
  for _ in range(6 * len(path.q) + 24):
    if follower.done:
      break
    action[:6] = follower(robot, physics, 0)
    env.step(action)
  assert follower.done
  assert arm_motion.pose_error(robot, physics, 0, goal_pos, goal_rot)[0] < 0.03
