"""The observation vocabulary: one set of keys for every furniture and robot, finite bounds."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import observations


@pytest.mark.parametrize("furniture", ["table_four_leg_lack", "chair_back_ivar"])
def test_keys_name_no_furniture_or_robot(furniture):
  env = ikea_suite.load(furniture, "cursor", seed=0)
  keys = set(env.observation_spec())
  assert keys == {"furniture/part_positions", "furniture/part_quaternions", "task/connections",
                  "task/connectors_used", "task/next_pair", "robot/tcp_positions",
                  "robot/tcp_quaternions", "robot/held_parts"}
  assert not any(furniture in key for key in keys)


def test_every_spec_is_bounded_finite_and_holds_the_observations():
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0)
  spec = env.observation_spec()
  timestep = env.reset()
  assert {k.split("/")[0] for k in spec} == {"furniture", "task", "robot"}
  for name, s in spec.items():
    assert np.isfinite(s.minimum).all() and np.isfinite(s.maximum).all(), name
    s.validate(timestep.observation[name])
  parts = len(env.task.furniture.parts)
  assert spec["task/next_pair"].maximum.max() == parts - 1
  assert spec["furniture/part_quaternions"].minimum.min() == -1.0


def test_wrist_camera_is_filed_under_cameras():
  env = ikea_suite.load("table_four_leg_lack", "sawyer", wrist_camera=True, camera_size=(8, 8))
  spec = env.observation_spec()["cameras/wrist_rgb"]
  assert spec.dtype == np.uint8 and spec.maximum.max() == 255


def test_camera_and_goal_keys_follow_the_pattern():
  assert observations.entry("cameras/front_goal_rgb").dtype == "uint8"
  assert observations.entry("cameras/top_depth").unit == "m"
  with pytest.raises(ikea_suite.UnknownNameError, match="furniture/part_positions"):
    observations.entry("table_four_leg_lack/part_positions")


def test_vocabulary_rows_describe_the_loaded_environment():
  rows = observations.vocabulary_rows("cursor")
  assert [r[0] for r in rows] == list(ikea_suite.load(
      ikea_suite.DEFAULT_FURNITURE, "cursor").observation_spec())
  by_key = {r[0]: r for r in rows}
  assert by_key["furniture/part_positions"][1:4] == ("(5, 3)", "float64", "m")
  assert all(r[4] for r in rows)


def test_camera_rows_name_their_camera():
  rows = observations.vocabulary_rows("cursor", cameras=("top",), image_size=(8, 8))
  by_key = {r[0]: r for r in rows}
  assert "camera top" in by_key["cameras/top_rgb"][4] and "*" not in by_key["cameras/top_rgb"][4]
