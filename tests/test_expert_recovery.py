"""How the arm expert recovers when a carry stalls: it notices, and sets the part back
down where it took it to take it with the other of its two grasps."""

import numpy as np

import ikea_suite
from ikea_suite import experts
from ikea_suite.oracle import arm_controller
from ikea_suite.oracle import arm_motion

Phase = arm_controller.Phase


def test_progress_watch_stalls_only_after_a_window_without_gain():
  watch = arm_motion.ProgressWatch(window=5, min_gain=0.01)
  errors = [0.5, 0.4, 0.3] + [0.295] * 5
  assert not any(watch.stalled(e, 0.0) for e in errors)   # 5 steps without 1 cm
  assert watch.stalled(0.295, 0.0)
  assert not watch.stalled(0.2, 0.0)   # progress again
  watch.reset()
  assert not watch.stalled(1.0, 0.2)


def test_twice_stalled_carry_puts_the_part_back_and_takes_it_the_other_way():
  env = ikea_suite.load("stool_round_frosta", "sawyer", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  furniture = env.task.furniture
  while expert.phase != Phase.CLOSE:
    timestep = env.step(expert(timestep))
  moving, sign = expert.job[1], expert._grasp_sign
  taken_from = furniture.part_poses(env.physics)[0][moving].copy()
  while expert.phase != Phase.ALIGN or expert._plan is None:
    timestep = env.step(expert(timestep))
  for _ in range(5):   # carrying
    timestep = env.step(expert(timestep))
  assert furniture.part_poses(env.physics)[0][moving][2] > taken_from[2] + 0.05
  expert._carry_stalled(moving, *expert._plan)   # first stall: another mate
  assert expert.phase == Phase.ALIGN and expert._plan is None
  timestep = env.step(expert(timestep))
  expert._carry_stalled(moving, *expert._plan)   # second: put it back
  phases = [expert.phase]
  for _ in range(300):
    timestep = env.step(expert(timestep))
    if expert.phase != phases[-1]:
      phases.append(expert.phase)
    if expert.job_just_chosen:
      break
  assert phases == [Phase.PUT_BACK, Phase.RELEASE, Phase.RETREAT, Phase.REACH]
  put_at = furniture.part_poses(env.physics)[0][moving]
  assert np.linalg.norm(put_at - taken_from) < 0.03   # back on the floor where it lay
  assert expert.job[1] == moving and expert._grasp_sign == -sign
