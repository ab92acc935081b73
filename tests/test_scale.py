"""The `scale` load option builds the same furniture physically larger or smaller."""

import numpy as np
import pytest

import ikea_suite


def _furniture(scale):
  env = ikea_suite.load("stool_square_pine", "cursor", seed=0, scale=scale)
  return env, env.task.furniture, env.physics.model


@pytest.mark.parametrize("scale", [0.5, 1.5])
def test_lengths_masses_and_inertias_scale_physically(scale):
  _, full, full_model = _furniture(1.0)
  env, small, model = _furniture(scale)
  np.testing.assert_allclose(model.body_mass[small.body_ids],
                             full_model.body_mass[full.body_ids] * scale ** 3, rtol=1e-6)
  np.testing.assert_allclose(model.body_inertia[small.body_ids],
                             full_model.body_inertia[full.body_ids] * scale ** 5, rtol=1e-6)
  for a, b in zip(small.spec.parts, full.spec.parts):
    np.testing.assert_allclose(a.bounds, b.bounds * scale, atol=1e-9)
    np.testing.assert_allclose(a.pos, b.pos * scale, atol=1e-9)
  np.testing.assert_allclose(small.connectors.local_pos, full.connectors.local_pos * scale,
                             atol=1e-9)
  assert env.task.thresholds.distance == pytest.approx(0.02 * scale)


def test_a_given_distance_threshold_stays_in_metres():
  env = ikea_suite.load("stool_square_pine", "cursor", scale=0.5, distance_threshold=0.03)
  assert env.task.thresholds.distance == pytest.approx(0.03)


def test_scaled_furniture_assembles_in_its_assembled_pose():
  """Parts put at the scaled design pose line up: every designed pair is attachable."""
  env, furniture, _ = _furniture(0.5)
  env.reset()
  physics = env.physics
  for part, spec in zip(furniture.parts, furniture.spec.parts):
    part.set_pose(physics, position=spec.pos + [0, 0, 1.0],
                  quaternion=ikea_suite.geometry.mat_to_quat(spec.rot))
  physics.forward()
  scores = env.task.alignment(physics)
  pairs = furniture.spec.assembled_connector_pairs()
  assert pairs
  table = furniture.connectors
  for a, b in pairs:
    index = np.flatnonzero((table.pair_a == min(a, b)) & (table.pair_b == max(a, b)))[0]
    assert scores.distance[index] < 1e-6


@pytest.mark.parametrize("bad", [0, 0.1, 5, "big", True, None])
def test_bad_scale_raises_option_value_error_naming_the_range(bad):
  with pytest.raises(ikea_suite.OptionValueError, match=r"scale must be a number from 0.2 to 2"):
    ikea_suite.load("stool_square_pine", "cursor", scale=bad)
