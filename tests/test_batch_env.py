"""The batched environment: scripted assembly completes, same seed same batch, option errors,
and the gymnasium vector entry point. Four worlds of the four-leg table on MJX's JAX
implementation; the scripted carry also on a step stool (the all-categories run is
scripts/batch_scripted_catalog.py)."""

import jax
import numpy as np
import pytest

import ikea_suite
from ikea_suite.batch import env as env_lib
from ikea_suite.batch import scripted

FURNITURE = "table_four_leg_lack"
WORLDS = 4   # one size everywhere: the vmapped step compiles once for the module
# Two categories. The stool is among the cheapest to compile (each extra model costs its own
# step compile, about half a minute on 2 cores) and its last part is a side standing on the
# floor, where the snap's floor check decides. Every category's worlds complete within 4
# steps (scripts/batch_scripted_catalog.py), so 20 leaves room.
CARRY_MODELS = (FURNITURE, "stool_step_tall_oak")
CARRY_STEPS = 20


@pytest.fixture(scope="module")
def env():
  return env_lib.load(FURNITURE)


def test_step_keeps_the_state_layout_so_it_compiles_once(env):
  with env.precision():
    first = jax.eval_shape(env.reset, jax.random.PRNGKey(0))
    after = jax.eval_shape(env.step, first, np.zeros(env.action_size))
  describe = lambda tree: [(jax.tree_util.keystr(p), x.shape, x.dtype, x.weak_type)
                           for p, x in jax.tree_util.tree_leaves_with_path(tree)]
  assert describe(after) == describe(first)


@pytest.mark.parametrize("furniture", CARRY_MODELS)
def test_scripted_cursor_carries_the_last_part_and_completes(furniture):
  steps = scripted.completion_steps(env_lib.load(furniture), WORLDS, CARRY_STEPS, seed=0)
  assert (steps > 0).mean() >= 0.95, steps


def test_scripted_carry_same_seed_same_outcome(env):
  first = scripted.completion_steps(env, WORLDS, CARRY_STEPS, seed=3)
  np.testing.assert_array_equal(first, scripted.completion_steps(env, WORLDS, CARRY_STEPS, seed=3))


def test_same_seed_same_batch(env):
  a = env.reset_batch(jax.random.PRNGKey(7), WORLDS)
  b = env.reset_batch(jax.random.PRNGKey(7), WORLDS)
  c = env.reset_batch(jax.random.PRNGKey(8), WORLDS)
  np.testing.assert_array_equal(np.asarray(a.data.qpos), np.asarray(b.data.qpos))
  assert not np.allclose(np.asarray(a.data.qpos), np.asarray(c.data.qpos))
  # Worlds differ from each other, and every part starts on the floor within the ring.
  positions = np.asarray(a.obs["part_positions"])
  assert not np.allclose(positions[0], positions[1])
  assert (positions[..., 2] > 0).all() and (positions[..., 2] < 0.5).all()
  actions = np.random.default_rng(0).uniform(-1, 1, size=(WORLDS, env.action_size))
  sa, sb = env.step_batch(a, actions), env.step_batch(b, actions)
  for x, y in zip(jax.tree.leaves(sa), jax.tree.leaves(sb)):
    np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def test_time_limit_and_rewards_follow_load(env):
  cpu = ikea_suite.load(FURNITURE, "cursor", seed=0)
  assert env.settings.max_steps == int(round(cpu.time_limit / cpu.control_timestep()))
  assert env.settings.substeps == round(cpu.control_timestep() / cpu.physics.timestep())
  assert (env.settings.connection_reward, env.settings.completion_bonus) == (
      cpu.task.connection_reward, cpu.task.completion_bonus)
  assert env.action_names == list(cpu.action_spec().name.split("\t"))


def test_episode_ends_at_the_time_limit_and_resets(env):
  state = env.reset_batch(jax.random.PRNGKey(0), WORLDS)
  start = np.asarray(state.data.qpos)
  # Two steps before the limit: the first step continues, the second ends and resets.
  steps = np.full(WORLDS, env.settings.max_steps - 2, dtype=np.int32)
  state = state._replace(task=state.task._replace(steps=steps))
  for expected_done in (False, True):
    state = env.step_batch(state, np.zeros((WORLDS, env.action_size)))
    assert np.asarray(state.done).tolist() == [expected_done] * WORLDS
  assert np.asarray(state.info["truncation"]).all()
  assert (np.asarray(state.task.steps) == 0).all()
  assert not np.allclose(np.asarray(state.data.qpos), start)   # a fresh random placement


def test_bad_batch_arguments_raise(env):
  state = env.reset_batch(jax.random.PRNGKey(0), WORLDS)
  with pytest.raises(ikea_suite.ActionError):
    env.step_batch(state, np.zeros((WORLDS, env.action_size - 1)))
  with pytest.raises(ikea_suite.OptionValueError):
    env.reset_batch(jax.random.PRNGKey(0), 0)


@pytest.mark.parametrize("options, error", [
    ({"distance_treshold": 0.02}, ikea_suite.UnknownNameError),
    ({"up_threshold": 1.5}, ikea_suite.OptionValueError),
    ({"control_timestep": 0.051}, ikea_suite.OptionValueError),
    ({"impl": "cuda"}, ikea_suite.OptionValueError),
])
def test_bad_options_raise(options, error):
  with pytest.raises(error):
    env_lib.BatchAssembly(FURNITURE, **options)


def test_gymnasium_vector_env():
  import gymnasium
  from ikea_suite import batch
  vec = batch.make_vector_env(FURNITURE, num_envs=WORLDS)
  assert isinstance(vec, gymnasium.vector.VectorEnv)
  obs, _ = vec.reset(seed=3)
  assert vec.observation_space.contains(obs)
  again, _ = vec.reset(seed=3)
  np.testing.assert_array_equal(obs["part_positions"], again["part_positions"])
  obs, reward, terminated, truncated, info = vec.step(np.zeros(vec.action_space.shape))
  assert vec.observation_space.contains(obs)
  assert reward.shape == terminated.shape == truncated.shape == (WORLDS,)
  with pytest.raises(ikea_suite.ActionError):
    vec.step(np.zeros((WORLDS + 1, vec.single_action_space.shape[0])))
