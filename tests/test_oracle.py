"""The scripted Cursor oracle assembles each starter furniture from randomized starts."""

import pytest

import ikea_suite
from ikea_suite import cli
from tests import helpers

STARTERS = ["table_four_leg_lack", "stool_round_frosta", "chair_back_ivar",
            "bookcase_shelf_unit_billy", "box_open_kuggis"]


@pytest.mark.parametrize("furniture", STARTERS)
@pytest.mark.parametrize("seed", [11, 12])
def test_oracle_assembles_within_time_limit(furniture, seed):
  env = ikea_suite.load(furniture, seed=seed)
  summary = cli.run_episode(env, cli.make_policy("oracle", env, seed))
  assert summary["success"], summary
  assert helpers.assembled_shape_error(env) < 2e-3   # the design's shape, not just one group
  assert summary["return"] == summary["connections"] + env.task.completion_bonus


def test_cli_rollout_prints_a_summary(capsys):
  assert cli.main(["--episodes", "1", "--seed", "2"]) == 0
  out = capsys.readouterr().out
  assert "connections 4/4, success True" in out and "success rate 1/1" in out


def test_cli_random_policy_and_bad_names(capsys):
  assert cli.main(["--policy", "random", "--time-limit", "1"]) == 0
  assert "success rate 0/1" in capsys.readouterr().out
  assert cli.main(["--furniture", "sofa_nope"]) == 2
  assert "unknown furniture 'sofa_nope'" in capsys.readouterr().err
