"""gymnasium adapter: check_env, spaces mirror the dm_env specs, termination, vector envs."""

import subprocess
import sys
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import ikea_suite
import ikea_suite.gym
from ikea_suite.props import catalog

# Every observation is bounded (ikea_suite.observations), so check_env warns of nothing but
# the render modes it cannot try without a render_mode.
_EXPECTED_WARNINGS = ("Not able to test alternative render modes",)
REPRESENTATIVES = catalog.representatives()
ARMS = [r for r in ikea_suite.robot_names() if r != "cursor"]
# Every robot is checked: the Cursor on every category's representative, each arm on a
# different representative (all 13 x 5 took 194 s on the busy two-core machine; see the README).
CASES = ([(f, "cursor") for f in REPRESENTATIVES]
         + [(REPRESENTATIVES[(3 * i + 1) % len(REPRESENTATIVES)], arm) for i, arm in enumerate(ARMS)])


@pytest.mark.parametrize("furniture, robot", CASES, ids=[f"{f}-{r}" for f, r in CASES])
def test_check_env_passes(furniture, robot):
  env = ikea_suite.gym.AssemblyEnv(furniture, robot)
  with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    check_env(env)
  unexpected = [str(w.message) for w in caught
                if not any(text in str(w.message) for text in _EXPECTED_WARNINGS)]
  assert not unexpected
  env.close()


def test_make_gives_spaces_mirroring_specs_and_seeded_episodes(gl):
  env = gymnasium.make(ikea_suite.gym.ENV_ID, furniture="table_four_leg_lack", robot="cursor",
                       cameras=("front",), image_size=16)
  dm = env.unwrapped.suite_env
  for name, spec in dm.observation_spec().items():
    space = env.observation_space[name]
    assert space.shape == spec.shape and space.dtype == spec.dtype
  image = env.observation_space["cameras/front_rgb"]
  assert image.dtype == np.uint8 and image.low.min() == 0 and image.high.max() == 255
  assert env.action_space.shape == dm.action_spec().shape
  first, info = env.reset(seed=3)
  assert info == {"connections": 0, "success": False, "blocked_connections": ()}
  same = ikea_suite.load("table_four_leg_lack", "cursor", seed=3).reset().observation
  np.testing.assert_array_equal(first["furniture/part_positions"],
                                same["furniture/part_positions"])
  env.close()


def test_time_limit_truncates_and_render_gives_rgb(gl):
  env = ikea_suite.gym.AssemblyEnv(time_limit=0.1, render_mode="rgb_array", render_size=(24, 32))
  env.reset(seed=0)
  zero = np.zeros(env.action_space.shape)
  assert env.step(zero)[2:4] == (False, False)
  _, _, terminated, truncated, _ = env.step(zero)
  assert (terminated, truncated) == (False, True)
  with pytest.raises(ikea_suite.gym.ResetNeeded):
    env.step(zero)
  frame = env.render()
  assert frame.shape == (24, 32, 3) and frame.dtype == np.uint8
  env.close()
  env.close()


def test_bad_arguments_raise_suite_errors():
  with pytest.raises(ikea_suite.UnknownNameError):
    ikea_suite.gym.AssemblyEnv(render_mode="human")
  env = ikea_suite.gym.AssemblyEnv()
  with pytest.raises(ikea_suite.IkeaSuiteError):
    env.reset(seed=-1)
  with pytest.raises(ikea_suite.UnknownNameError):
    env.reset(options={"preassembled": 1})
  env.close()


def test_spaces_are_finite_with_float32_actions_and_a_step_limit():
  env = gymnasium.make(ikea_suite.gym.ENV_ID, furniture="table_four_leg_lack", robot="cursor",
                       time_limit=2.0)
  assert env.action_space.dtype == np.float32
  assert env.spec.max_episode_steps == env.unwrapped.suite_env.task.config.max_steps
  for name, space in env.observation_space.items():
    assert np.isfinite(space.low).all() and np.isfinite(space.high).all(), name
  np.testing.assert_array_equal(env.observation_space["furniture/part_quaternions"].high, 1.0)
  np.testing.assert_array_equal(env.observation_space["task/connections"].low, 0.0)
  env.reset(seed=0)
  steps, done = 0, False
  while not done:
    *_, terminated, truncated, _ = env.step(np.zeros(env.action_space.shape, np.float32))
    steps, done = steps + 1, terminated or truncated
  assert truncated and steps == env.spec.max_episode_steps
  env.close()


_FORK_SCRIPT = """
import gymnasium, ikea_suite.gym, ikea_suite.errors
if {render_first}:
  env = gymnasium.make("ikea_suite/Assembly-v0", cameras=("front",), image_size=16)
  env.reset(seed=0)
envs = gymnasium.make_vec("ikea_suite/Assembly-v0", num_envs=2, vectorization_mode="async",
                          vector_kwargs={{"context": "fork"}}, time_limit=1.0,
                          cameras=("front",), image_size=16)
try:
  observations, _ = envs.reset(seed=0)
except ikea_suite.errors.RenderAfterForkError as e:
  print("RenderAfterForkError", e)
else:
  assert observations["cameras/front_rgb"].shape == (2, 16, 16, 3)
  assert observations["cameras/front_rgb"].any()
  print("rendered")
envs.close()
"""


@pytest.mark.parametrize("render_first, expected", [(False, "rendered"),
                                                    (True, "RenderAfterForkError")])
def test_async_vector_env_with_cameras_under_fork(gl, render_first, expected):
  # Fork, Linux's default start method, from a fresh interpreter (this one has rendered):
  # the parent builds one env to read the spaces, which must not make a GL context. A parent
  # that rendered itself gets an error naming the fix rather than workers that hang.
  result = subprocess.run([sys.executable, "-c", _FORK_SCRIPT.format(render_first=render_first)],
                          capture_output=True, text=True, timeout=300)
  assert expected in result.stdout, result.stdout + result.stderr
  if render_first:
    assert "forkserver" in result.stdout


def test_async_vector_env_steps_two_processes():
  envs = gymnasium.make_vec(ikea_suite.gym.ENV_ID, num_envs=2, vectorization_mode="async",
                            vector_kwargs={"context": "spawn"}, time_limit=1.0)
  observations, infos = envs.reset(seed=0)
  assert observations["task/connections"].shape == (2, 5, 5)
  assert not np.array_equal(observations["furniture/part_positions"][0],
                            observations["furniture/part_positions"][1])
  _, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
  assert rewards.shape == (2,) and not terminated.any() and not truncated.any()
  assert list(infos["connections"]) == [0, 0]
  envs.close()


def test_spec_to_space_mapping_keeps_bounds_and_dtype_limits():
  from dm_env import specs
  from ikea_suite.gym import spaces
  seg = spaces.box_from_spec(specs.Array((4, 5), np.int32))
  assert seg.dtype == np.int32 and seg.low.min() == np.iinfo(np.int32).min
  depth = spaces.box_from_spec(specs.Array((4, 5), np.float32))
  assert depth.dtype == np.float32 and np.isinf(depth.high).all()
  bounded = spaces.box_from_spec(specs.BoundedArray((3,), np.float64, -1.0, [1.0, 2.0, 3.0]))
  assert list(bounded.high) == [1.0, 2.0, 3.0] and list(bounded.low) == [-1.0] * 3
  assert not bounded.contains(np.array([0.0, 2.5, 0.0]))
