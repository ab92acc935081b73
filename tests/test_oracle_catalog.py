"""The scripted Cursor oracle assembles one model of every category from a randomized start.

The whole catalog is swept by benchmarks/oracle_sweep.py; CI runs this subset.
"""

import pytest

import ikea_suite
from ikea_suite import cli
from ikea_suite.experts import cursor_oracle
from ikea_suite.props import catalog
from tests import helpers


@pytest.mark.parametrize("name", catalog.representatives())
def test_oracle_assembles_a_model_of_each_category(name):
  env = ikea_suite.load(name, "cursor", seed=1)
  cli.run_episode(env, cursor_oracle.CursorOracle(env))
  state = env.task.state
  assert state.complete, f"{len(state.connections)} of {len(env.task.furniture.parts) - 1} connections"
  assert helpers.assembled_shape_error(env) < 2e-3   # the design's shape, not just one group
