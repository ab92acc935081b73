"""Pins the private state of dm_control's composer that ikea_suite reads (composer_internals),
and shows the environment runs composer's own step, with the same episodes, where it differs."""

import logging

import numpy as np
import pytest
from dm_control import composer
from dm_control.composer import environment as composer_environment
from dm_control.composer.observation import updater as updater_lib

import ikea_suite
from ikea_suite import composer_internals

FURNITURE = "table_four_leg_lack"


def _env(robot="cursor", seed=0):
  env = ikea_suite.load(FURNITURE, robot, seed=seed)
  env.reset()
  return env


def _value(owner, path):
  for name in path.split("."):
    owner = getattr(owner, name)
  return owner


@pytest.mark.parametrize("robot", ["cursor", "sawyer"])
def test_every_pinned_attribute_has_its_name_and_type(robot):
  env = _env(robot)
  for path, kinds in composer_internals.PINNED:
    assert kinds is not None, f"{path}: dm_control no longer has the class it should be"
    assert isinstance(_value(env, path), kinds), path
  enabled = list(env._observation_updater._enabled_list)
  assert enabled
  for entry in enabled:
    assert isinstance(entry, updater_lib._EnabledObservable)
    for name, kinds in composer_internals.PINNED_PER_OBSERVABLE:
      assert isinstance(getattr(entry, name), kinds), name
  assert composer_internals.problems(env) == []


def test_the_pinned_attributes_mean_what_the_batched_step_takes_them_to_mean():
  env = _env()
  internals = composer_internals.read(env)
  assert isinstance(internals.hooks, composer_environment._EnvironmentHooks)
  assert internals.physics.data is env.physics.data   # the physics behind the proxy
  assert internals.n_sub_steps == env.task.physics_steps_per_control_step
  updater = internals.updater
  assert updater._is_nested is False
  assert list(updater._enabled_structure) == list(env.observation_spec())
  assert list(updater._enabled_list) == list(updater._enabled_structure.values())
  # The warnings flag: on, and off only within suppress_physics_errors().
  assert composer_internals.warnings_raise(internals.physics) is True
  with env.physics.suppress_physics_errors():
    assert composer_internals.warnings_raise(internals.physics) is False
  # composer's own step counts every substep in the updater's step counter, as skip_updates
  # does for the substeps the batched step runs without updates.
  before = updater._step_counter
  composer.Environment.step(env, np.zeros(env.action_spec().shape))
  assert updater._step_counter == before + internals.n_sub_steps
  # Its substep is one physics step with the substep hooks around it.
  time = env.physics.time()
  internals.substep(np.zeros(env.action_spec().shape))
  assert env.physics.time() == pytest.approx(time + env.physics.timestep())


def test_problems_name_a_missing_and_a_mistyped_attribute():
  env = _env()
  updater = env._observation_updater
  counter = updater._step_counter
  try:
    del updater._step_counter
    updater._is_nested = "no"
    found = composer_internals.problems(env)
  finally:
    updater._step_counter, updater._is_nested = counter, False
  assert any(line.startswith("_observation_updater._step_counter: ") and "no attribute" in line
             for line in found), found
  assert any(line.startswith("_observation_updater._is_nested: str") for line in found), found
  assert composer_internals.read(env) is not None


def _rollout(env, actions):
  steps = [env.reset()]
  steps += [env.step(a) for a in actions]
  return steps


@pytest.mark.parametrize("robot", ["cursor", "sawyer"])
def test_where_composer_differs_the_environment_runs_composers_own_step(
    robot, monkeypatch, caplog):
  fast = ikea_suite.load(FURNITURE, robot, seed=3)
  actions = np.random.default_rng(0).uniform(-1, 1, (12,) + fast.action_spec().shape)
  actions[:, -1] = -1.0
  expected = _rollout(fast, actions)
  monkeypatch.setattr(composer_internals, "PINNED",
                      composer_internals.PINNED + (("_a_name_no_dm_control_has", object),))
  monkeypatch.setattr(composer_internals, "_warned", [])
  fallback = ikea_suite.load(FURNITURE, robot, seed=3)
  with caplog.at_level(logging.WARNING):
    got = _rollout(fallback, actions)
  assert fallback._internals is None
  assert "composer's own step" in caplog.text and "_a_name_no_dm_control_has" in caplog.text
  for ours, theirs in zip(got, expected):
    assert ours.step_type == theirs.step_type and ours.reward == theirs.reward
    assert ours.discount == theirs.discount
    assert ours.observation.keys() == theirs.observation.keys()
    for key in ours.observation:
      np.testing.assert_array_equal(ours.observation[key], theirs.observation[key], err_msg=key)
  # A diverging state still ends the episode, with its reason.
  fallback.physics.data.qvel[0] = np.nan
  timestep = fallback.step(actions[0])
  assert timestep.last() and timestep.discount == 0.0
  assert "Physics state is invalid" in fallback.termination_reason
  assert fallback.step(actions[0]).first()
