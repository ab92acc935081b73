"""Dense reward: staged, potential-based, rising along an oracle episode, never above sparse."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.experts import cursor_oracle
from ikea_suite.experts import part_geometry
from ikea_suite.tasks import rewards
from tests import helpers


def oracle_episode(furniture, seed=0):
  env = ikea_suite.load(furniture, "cursor", seed=seed, reward="dense")
  oracle = cursor_oracle.CursorOracle(env)
  timestep = env.reset()
  returns, stages, connection_steps = [0.0], [], []
  while not timestep.last():
    made = len(env.task.state.connections)
    timestep = env.step(oracle(timestep))
    returns.append(returns[-1] + timestep.reward)
    stage = oracle.subtask + (len(env.task.state.connections),)
    if not stages or stages[-1][1] != stage:
      stages.append((len(returns) - 1, stage))
    if len(env.task.state.connections) > made:
      connection_steps.append((timestep.reward, env.task.state.complete))
  return env, np.array(returns), stages, connection_steps


@pytest.fixture(scope="module")
def table_episode():
  return oracle_episode("table_four_leg_lack")


def test_dense_return_rises_at_every_oracle_stage(table_episode):
  env, returns, stages, _ = table_episode
  assert env.task.state.complete
  # Per part: reaching, then inserting, then connected. (Raise and travel are left
  # out: meanwhile the oracle's other cursor lifts the root part to its holding
  # height, which can carry the target connector away from a part just grasped,
  # and the potential rightly says so.)
  checkpoints = [step for step, (phase, _, _) in stages if phase in ("reach", "insert")]
  checkpoints.append(len(returns) - 1)
  at_checkpoints = returns[checkpoints]
  assert len(checkpoints) >= 2 * 4 + 1
  assert np.all(np.diff(at_checkpoints) >= -1e-3), at_checkpoints
  assert returns[-1] > at_checkpoints[len(at_checkpoints) // 2] > returns[0]


def test_dense_never_pays_more_for_a_connection_than_sparse(table_episode):
  env, _, _, connection_steps = table_episode
  needed = len(env.task.furniture.parts) - 1
  assert len(connection_steps) == needed
  # The stage terms earn at most weights.total of a connection; connecting pays the rest.
  least = (1.0 - rewards.StageWeights().total) / needed
  for reward, complete in connection_steps:
    sparse = 1.0 + (10.0 if complete else 0.0)   # connection_reward, completion_bonus defaults
    bonus = 1.0 if complete else 0.0             # dense pays min(bonus, connection_reward)
    assert least + bonus - 1e-9 <= reward <= sparse


def test_complete_episode_returns_about_two_for_any_furniture(table_episode):
  # Potential-based: the return telescopes to Phi(end) - Phi(start) plus the completion term.
  _, table_returns, _, _ = table_episode
  env, stool_returns, _, _ = oracle_episode("stool_step_tall_oak")
  assert env.task.state.complete
  assert len(env.task.furniture.parts) != 5
  for total in (table_returns[-1], stool_returns[-1]):
    assert 1.8 < total <= 2.0 + 1e-9


def test_stage_terms_of_a_held_and_lifted_part_match_their_definitions():
  env = ikea_suite.load("table_four_leg_lack", "cursor", seed=0, reward="dense")
  env.reset()
  task, physics, robot = env.task, env.physics, env.task.robot
  dense = task.dense_reward
  leg, top = helpers.part_index(env, "leg0"), task.root_part
  body = task.furniture.body_ids[leg]
  start_z = physics.data.xipos[body][2]
  terms = dense.pair_terms(physics)
  assert set(terms) == {"reach", "grasp", "lift", "distance", "angle"}
  assert not terms["grasp"].any() and not terms["lift"].any()   # nothing held yet
  # Cursor 0 selects leg0 at its grasp point, then raises it 5 cm (two steps at full speed).
  robot.set_cursor_pose(physics, 0, part_geometry.grasp_point(physics, task.furniture, leg),
                        np.eye(3))
  action = helpers.idle_action(env)
  action[6] = 1.0    # cursor0_select
  returns = 0.0
  for move_z in (0.0, 1.0, 1.0, 0.0, 0.0, 0.0):
    action[2] = move_z
    returns += env.step(action).reward
  assert robot.held_parts[0] == leg
  assert returns > 0   # holding and lifting the next part raised the potential
  terms = dense.pair_terms(physics)
  held = terms["grasp"] == 1.0   # the rows whose moving part is leg0
  assert held.any() and not held.all()
  rise = physics.data.xipos[body][2] - start_z
  assert 0.03 < rise < 0.07
  np.testing.assert_allclose(terms["reach"][held], 1.0)
  np.testing.assert_allclose(terms["lift"][held], rise / rewards.LIFT_HEIGHT, rtol=1e-9)
  # Distance terms of leg0's open pairs with the top, from the task's own alignment scores.
  table, scores = task.furniture.connectors, task.alignment(physics)
  a, b = table.part[table.pair_a], table.part[table.pair_b]
  mine = ((a == leg) & (b == top)) | ((a == top) & (b == leg))
  np.testing.assert_allclose(np.sort(terms["distance"][held]),
                             np.sort(np.exp(-scores.distance[mine] / rewards.DISTANCE_SCALE)))
  others = ~held   # parts not held earn reach only
  assert np.all(terms["reach"][others] < 1.0)
  for name in ("lift", "distance", "angle"):
    assert not terms[name][others].any()
  env.close()


def test_sparse_is_default_and_unknown_reward_is_rejected():
  env = ikea_suite.load("table_four_leg_lack", "cursor", seed=0)
  assert env.task.dense_reward is None
  with pytest.raises(ikea_suite.UnknownNameError, match="dense"):
    ikea_suite.load("table_four_leg_lack", "cursor", reward="shaped")


def test_arm_grasp_is_detected_and_return_rises_from_grasp_to_connection():
  from ikea_suite.experts import single_arm
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0, reward="dense")
  controller = single_arm.ArmAssemblyController(env)
  timestep, total, samples, grasped = env.reset(), 0.0, {}, False
  for _ in range(500):
    timestep = env.step(controller(timestep))
    total += timestep.reward
    grasped |= env.task.dense_reward.terms["grasp"] == 1.0
    key = (controller.phase.value, len(env.task.state.connections))
    samples.setdefault(key, total)
    if env.task.state.connections:
      break
  assert grasped and env.task.state.connections
  rising = [samples[(phase, 0)] for phase in ("close", "lift", "align", "insert")]
  rising.append(samples[("insert", 1)])
  assert np.all(np.diff(rising) > 0), rising
  env.close()
