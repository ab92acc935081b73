"""The scripted Cursor oracle assembles one model of every category from a randomized start.

The whole catalog is swept by benchmarks/oracle_sweep.py; CI runs this subset.
"""

import pytest

import ikea_suite
from ikea_suite import cli
from ikea_suite.oracle import cursor_oracle
from ikea_suite.props import catalog


@pytest.mark.parametrize("name", catalog.representatives())
def test_oracle_assembles_a_model_of_each_category(name):
  env = ikea_suite.load(name, "cursor", seed=1)
  steps = cli.run_episode(env, cursor_oracle.CursorOracle(env))["steps"]
  state = env.task.state
  assert state.complete, f"{len(state.connections)} of {len(env.task.furniture.parts) - 1} connections"
  assert len(state.connections) == len(env.task.furniture.parts) - 1
  assert steps < round(env.time_limit / env.control_timestep())
