"""The scripted Cursor oracle assembles one model of every category from a randomized start.

The whole catalog is swept by benchmarks/oracle_sweep.py; CI runs this subset.
"""

import pytest

import ikea_suite
from ikea_suite.oracle import cursor_oracle
from ikea_suite.props import catalog


def _run(name, seed):
  env = ikea_suite.load(name, "cursor", seed=seed, **cursor_oracle.episode_options(name))
  timestep = env.reset()
  oracle = cursor_oracle.CursorOracle(env)
  steps = 0
  while not timestep.last():
    timestep = env.step(oracle(timestep))
    steps += 1
  return env, steps


@pytest.mark.parametrize("name", catalog.representatives())
def test_oracle_assembles_a_model_of_each_category(name):
  env, steps = _run(name, seed=1)
  state = env.task.state
  assert state.complete, f"{len(state.connections)} of {len(env.task.furniture.parts) - 1} connections"
  assert len(state.connections) == len(env.task.furniture.parts) - 1
  limit = round(cursor_oracle.episode_options(name)["time_limit"] / env.control_timestep())
  assert steps < limit


def test_episode_options_scale_with_the_furniture():
  small = cursor_oracle.episode_options("stool_pedestal_white")
  large = cursor_oracle.episode_options("bookcase_shelf_unit_cd_tower")
  assert small["time_limit"] < large["time_limit"]
