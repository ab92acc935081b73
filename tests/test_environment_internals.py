"""The batched-substep step gives exactly what composer's own step gives (what it reads of
composer's private state is pinned in tests/test_composer_internals.py)."""

import numpy as np
import pytest
from dm_control import composer
from dm_control.rl import control

import ikea_suite
from ikea_suite import composer_internals
from ikea_suite import environment
from ikea_suite import mujoco_arrays

FURNITURE = "table_four_leg_lack"


def test_default_observables_are_read_directly_and_others_through_the_buffers():
  env = ikea_suite.load(FURNITURE, seed=0)
  env.reset()
  assert env._direct is not None
  assert [name for name, _ in env._direct] == list(env.observation_spec())
  env.task.furniture.observables.part_positions.delay = 2
  env._recompile_physics_and_update_observables()
  env.reset()
  assert env._direct is None


def _pair(configure=None, robot="cursor"):
  """An ikea_suite environment and a plain composer one on an identically built task."""
  ours = ikea_suite.load(FURNITURE, robot, seed=3)
  twin = ikea_suite.load(FURNITURE, robot, seed=3)
  for env in (ours, twin):
    if configure:
      configure(env.task)
  plain = composer.Environment(twin.task, time_limit=ours.time_limit, random_state=3,
                               strip_singleton_obs_buffer_dim=True,
                               recompile_mjcf_every_episode=False,
                               raise_exception_on_physics_error=False)
  if configure:   # observables changed after the first compile: rebuild the updater
    ours._recompile_physics_and_update_observables()
  return ours, plain


def _rollout(env, actions):
  observations = [env.reset().observation]
  observations += [env.step(a).observation for a in actions]
  return observations


def _actions(env, steps=15):
  rng = np.random.default_rng(0)
  actions = rng.uniform(-1, 1, size=(steps,) + env.action_spec().shape)
  actions[:, -1] = -1.0
  return actions


def _assert_same(first, second):
  for a, b in zip(first, second):
    assert a.keys() == b.keys()
    for key in a:
      np.testing.assert_array_equal(a[key], b[key], err_msg=key)
      assert a[key].dtype == b[key].dtype and a[key].shape == b[key].shape, key


def test_batched_substeps_match_composers_step():
  ours, plain = _pair()
  actions = _actions(ours)
  _assert_same(_rollout(ours, actions), _rollout(plain, actions))


def test_batched_substeps_match_composers_step_with_an_arm():
  ours, plain = _pair(robot="sawyer")
  actions = _actions(ours)
  _assert_same(_rollout(ours, actions), _rollout(plain, actions))


def test_the_raw_handles_are_the_physics_own():
  env = ikea_suite.load(FURNITURE, seed=0)
  env.reset()
  physics = env.physics
  assert physics.legacy_step is True
  handles = environment.raw_handles(physics)
  assert handles[0] is physics.model.ptr and handles[1] is physics.data.ptr
  assert handles[2].base is not None   # a view: the counts MuJoCo writes, not a copy


def test_advance_steps_as_physics_step_does_and_raises_on_new_warnings():
  first, second = (ikea_suite.load(FURNITURE, seed=0) for _ in range(2))
  for env in (first, second):
    env.reset()
  environment.advance(first.physics, 7, environment.raw_handles(first.physics))
  second.physics.step(7)
  np.testing.assert_array_equal(first.physics.data.qpos, second.physics.data.qpos)
  np.testing.assert_array_equal(first.physics.data.xpos, second.physics.data.xpos)
  first.physics.data.qvel[0] = np.nan
  with pytest.raises(control.PhysicsError, match=r"Warning\(s\) raised: .*BADQ"):
    environment.advance(first.physics, 2, environment.raw_handles(first.physics))


def test_a_delayed_observable_matches_composers_step():
  def delayed(task):   # buffered and delayed: read through composer's updater
    task.furniture.observables.part_positions.delay = 3
  ours, plain = _pair(delayed)
  actions = _actions(ours, steps=6)
  _assert_same(_rollout(ours, actions), _rollout(plain, actions))


def test_an_observable_sampled_every_substep_gets_every_substep():
  def every_substep(task):   # parts placed 1 mm above the floor settle during the first steps
    positions = task.furniture.observables.part_positions
    positions.update_interval, positions.buffer_size = 1, 25
  ours, plain = _pair(every_substep)
  actions = _actions(ours, steps=2)
  first, second = _rollout(ours, actions), _rollout(plain, actions)
  _assert_same(first, second)
  buffered = first[1]["furniture/part_positions"]
  assert buffered.shape == (25, 5, 3)
  assert len({tuple(row.ravel()) for row in buffered}) == 25   # every substep, none repeated


@pytest.mark.parametrize("robot", ["cursor", "panda", "baxter"])
def test_every_fresh_observable_makes_a_new_array_on_every_read(robot):
  # The direct path hands these out without a copy: a view of the physics or of a stored
  # array would change under the learner's feet, or be changed by it.
  env = ikea_suite.load(FURNITURE, robot, seed=0)
  env.reset()
  physics = env.physics
  internals = composer_internals.read(env)
  fresh = {name: e for name, e in internals.updater._enabled_structure.items()
           if isinstance(e.observable, mujoco_arrays.FreshGeneric)}
  assert len(fresh) >= 6
  state = [physics.data.qpos, physics.data.qvel, physics.data.xpos, physics.data.xquat,
           physics.data.site_xpos, physics.data.site_xmat]
  for name, enabled in fresh.items():
    first, second = enabled.observation_callable(), enabled.observation_callable()
    assert first is not second, name
    assert not np.shares_memory(first, second), name
    assert not any(np.shares_memory(first, array) for array in state), name
    first[...] = 7.0   # a learner writing into its observation changes nothing else
    np.testing.assert_array_equal(enabled.observation_callable(), second, err_msg=name)
