"""The single-arm expert's mate choice (experts/mating.py), checked at moments traced in the
Panda's trestle desks (tuning seeds; episodes are deterministic)."""

import numpy as np

import ikea_suite
from ikea_suite import experts
from ikea_suite.experts import arm_motion
from ikea_suite.experts import mating


def _expert_after(furniture, seed, steps):
  env = ikea_suite.load(furniture, "panda", seed=seed, scale=0.5)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  for _ in range(steps):
    timestep = env.step(expert(timestep))
  return env, expert


def _mate_tool_goal(env, expert, pair, twist):
  moving = expert.job[1]
  part_pos, part_rot, side = mating.mate_pose(env, pair, moving, twist)
  return mating.tool_goal_for_part(env, 0, moving, part_pos + expert._approach * side, part_rot)


def _trestle_mates(env, moving):
  """{connector pair: mate_pose at twist 0} of the held trestle's two slots in the top."""
  table = env.task.furniture.connectors
  out = {}
  for pair in range(len(table.pair_a)):
    parts = {int(table.part[table.pair_a[pair]]), int(table.part[table.pair_b[pair]])}
    if parts == {moving, env.task.root_part}:
      out[pair] = mating.mate_pose(env, pair, moving, 0.0)
  return out


def test_a_trestle_standing_in_the_next_ones_carry_costs_more():
  # desk_trestle_w120_white, tuning seed 2, the first trestle lifted from the rack: at the
  # top's slot nearer the rack it would stand 0.38 m tall on the arc the second takes to
  # the far slot, which it would clear only with the tool at 0.75 m (the Panda reaches
  # 0.70); at the far slot it is in no later carry's way.
  env, expert = _expert_after("desk_trestle_w120_white", 2, 84)
  moving, nominal = expert.job[1], expert._carry_height.nominal
  rack = env.task.furniture.part_poses(env.physics)[0][[
      p for p in env.task.initializer.racked_parts if p != moving]].mean(axis=0)
  mates = _trestle_mates(env, moving)
  near, far = sorted(mates, key=lambda p: np.linalg.norm(mates[p][0][:2] - rack[:2]))
  assert mating.in_a_later_carry(env, moving, near, *mates[near][:2], nominal)
  assert not mating.in_a_later_carry(env, moving, far, *mates[far][:2], nominal)
  # A carry high enough to pass over it: no longer in the way.
  assert not mating.in_a_later_carry(env, moving, near, *mates[near][:2], nominal + 0.4)


def test_a_reach_the_converged_ik_misses_is_judged_along_the_servos_path():
  # desk_trestle_w120_white, tuning seed 10, the first trestle lifted: from the grasp the
  # IK stops 12 cm short of the far slot's pre-insertion pose, four joints at their
  # limits; the servo's own path gets there.
  env, expert = _expert_after("desk_trestle_w120_white", 10, 105)
  robot, physics = env.task.robot, env.physics
  servo = (env.control_timestep(), arm_motion.CARRY_TURN)
  missed = 0
  for pair in _trestle_mates(env, expert.job[1]):
    goal_pos, goal_rot = _mate_tool_goal(env, expert, pair, 0.0)
    if robot.reach_check(physics, 0, goal_pos, goal_rot)[0] > 0.05:
      missed += 1
      _, distance, _ = arm_motion.servo_path_end(robot, 0, robot.arm_qpos(physics),
                                                 goal_pos, goal_rot, *servo)
      assert distance < 0.01
      assert mating.reach_cost(robot, physics, 0, goal_pos, goal_rot, servo=servo) < 0.5
  assert missed == 1
