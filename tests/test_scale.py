"""The `scale` load option builds the same furniture physically larger or smaller."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.props import catalog
from ikea_suite.props import model_format
from ikea_suite.props import scaling


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


@pytest.mark.parametrize("bad", [0, 0.1, 5, "big", True])   # None: the robot's work scale
def test_bad_scale_raises_option_value_error_naming_the_range(bad):
  with pytest.raises(ikea_suite.OptionValueError, match=r"scale must be a number from 0.2 to 2"):
    ikea_suite.load("stool_square_pine", "cursor", scale=bad)


@pytest.mark.parametrize("scale", [0.5, 1.5])
def test_scaling_in_memory_gives_the_numbers_of_a_scaled_file(scale, tmp_path):
  """The scaled spec is built from a scaled copy of the document, never a file; written
  out and read back from disk it gives the very same numbers, bit for bit."""
  spec = catalog.spec("stool_square_pine")
  small = scaling.scaled(spec, scale)
  assert small is not spec and small.scale == scale and small.path == spec.path
  assert spec.scale == 1.0 and spec.document is not small.document   # the original untouched
  path = tmp_path / "scaled.xml"
  path.write_text(model_format.to_xml(small.document))
  from_file = model_format.load_spec(str(path))
  for a, b in zip(small.parts, from_file.parts):
    for x, y in ((a.pos, b.pos), (a.rot, b.rot), (a.bounds, b.bounds)):
      assert x.tobytes() == y.tobytes(), a.name
    assert a.mass == b.mass
  assert [c.pos.tobytes() for c in small.connectors] == [c.pos.tobytes() for c in from_file.connectors]
  assert scaling.scaled(spec, 1.0) is spec
