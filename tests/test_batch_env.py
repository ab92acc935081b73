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
  positions = np.asarray(a.obs["furniture/part_positions"])
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
  np.testing.assert_array_equal(obs["furniture/part_positions"], again["furniture/part_positions"])
  obs, reward, terminated, truncated, info = vec.step(np.zeros(vec.action_space.shape))
  assert vec.observation_space.contains(obs)
  assert reward.shape == terminated.shape == truncated.shape == (WORLDS,)
  with pytest.raises(ikea_suite.ActionError):
    vec.step(np.zeros((WORLDS + 1, vec.single_action_space.shape[0])))


def test_vector_env_has_the_cpu_gym_envs_spaces_and_info_keys():
  import gymnasium
  import ikea_suite.gym  # noqa: F401  (registers the id)
  from ikea_suite import batch
  cpu = gymnasium.make("ikea_suite/Assembly-v0", furniture=FURNITURE, robot="cursor")
  vec = batch.make_vector_env(FURNITURE, num_envs=WORLDS)
  cpu_space, vec_space = cpu.observation_space, vec.single_observation_space
  assert list(vec_space) == sorted(cpu_space)
  for key in cpu_space:
    a, b = cpu_space[key], vec_space[key]
    assert (a.shape, a.dtype) == (b.shape, b.dtype), key
    np.testing.assert_array_equal(a.low, b.low, err_msg=key)
    np.testing.assert_array_equal(a.high, b.high, err_msg=key)
  assert cpu.action_space == vec.single_action_space
  assert vec.single_action_space.dtype == np.float32
  _, cpu_info = cpu.reset(seed=0)
  obs, vec_info = vec.reset(seed=0)
  # The device does not compute the CPU task's reasons for a refused connect.
  assert set(cpu_info) - {"blocked_connections"} <= set(vec_info)
  for key, value in obs.items():
    assert value.dtype == cpu_space[key].dtype and value.shape == (WORLDS,) + cpu_space[key].shape
  assert vec.metadata["autoreset_mode"] == gymnasium.vector.AutoresetMode.NEXT_STEP


def test_make_vec_vector_entry_point_gives_the_batched_env():
  import gymnasium
  import ikea_suite.gym  # noqa: F401
  from ikea_suite.batch import gym_vector
  vec = gymnasium.make_vec("ikea_suite/Assembly-v0", num_envs=WORLDS,
                           vectorization_mode="vector_entry_point", furniture=FURNITURE)
  assert isinstance(vec.unwrapped, gym_vector.AssemblyVectorEnv)
  assert vec.spec.max_episode_steps == vec.unwrapped.batch_env.settings.max_steps


def test_vector_env_resets_on_the_next_step():
  from ikea_suite import batch
  vec = batch.make_vector_env(FURNITURE, num_envs=WORLDS)
  vec.reset(seed=1)
  limit = vec.batch_env.settings.max_steps
  state = vec._state
  vec._state = state._replace(task=state.task._replace(
      steps=np.full(WORLDS, limit - 1, dtype=np.int32)))
  zeros = np.zeros(vec.action_space.shape, dtype=np.float32)
  last, _, terminated, truncated, _ = vec.step(zeros)
  assert truncated.all() and not terminated.any()
  start, reward, terminated, truncated, info = vec.step(zeros)
  assert not (terminated | truncated).any() and (reward == 0).all()
  assert (info["connections"] == 0).all()
  assert not np.allclose(start["furniture/part_positions"], last["furniture/part_positions"])
  np.testing.assert_array_equal(np.asarray(vec._state.task.steps), 0)
  _, _, _, truncated, _ = vec.step(zeros)
  assert not truncated.any()
  np.testing.assert_array_equal(np.asarray(vec._state.task.steps), 1)


def test_make_vec_for_an_arm_names_the_process_vectors():
  import gymnasium
  import ikea_suite.gym  # noqa: F401
  with pytest.raises(ikea_suite.OptionValueError, match="vectorization_mode='async'"):
    gymnasium.make_vec("ikea_suite/Assembly-v0", num_envs=2, robot="baxter")
