"""The batched alignment test agrees with tasks/alignment.py on thousands of pose pairs."""

import jax
import numpy as np
import pytest

from ikea_suite import config
from ikea_suite import geometry
from ikea_suite.batch import align
from ikea_suite.batch import model as model_lib
from ikea_suite.tasks import alignment

THRESHOLDS = alignment.Thresholds.of(config.TaskConfig().resolved(5, scattered=True, scale=1.0))


def random_frames(rng, num_connectors):
  """Connector frames scattered about one common frame: within a few cm, degrees and one of
  the quarter twists, so many pairs sit near each threshold."""
  base = geometry.axis_angle_to_mat(rng.normal(size=3))
  pos = rng.normal(size=3) + rng.normal(scale=0.012, size=(num_connectors, 3))
  rot = []
  for _ in range(num_connectors):
    tilt = geometry.axis_angle_to_mat(rng.normal(size=3) * rng.uniform(0, 0.12))
    twist = geometry.rot_z(rng.integers(4) * np.pi / 2 + rng.normal(scale=0.1))
    rot.append(tilt @ base @ twist)
  return pos, np.array(rot)


# A table (quarter twists) and a chair with any-twist connectors.
@pytest.mark.parametrize("furniture", ["table_four_leg_lack", "chair_back_dark_bar"])
def test_batched_alignment_matches_cpu(furniture):
  bm = model_lib.build(furniture)
  table = bm.table
  rng = np.random.default_rng(0)
  configs = [random_frames(rng, len(table)) for _ in range(4000 // table.num_pairs + 1)]
  with jax.enable_x64(True):
    tables = align.pair_tables(table, bm.welds)
    batched = jax.jit(jax.vmap(lambda p, r: align.align_pairs(tables, p, r)))(
        np.array([c[0] for c in configs]), np.array([c[1] for c in configs]))
    got_attach = np.asarray(batched.attachable(THRESHOLDS))
  cpu = [alignment.align_pairs(p, r, table) for p, r in configs]
  want_attach = np.array([c.attachable(THRESHOLDS) for c in cpu])
  assert want_attach.size >= 4000
  assert 0.05 < want_attach.mean() < 0.95   # both outcomes are well represented
  np.testing.assert_array_equal(got_attach, want_attach)
  for field in ("distance", "up_cos", "forward_cos"):
    np.testing.assert_allclose(np.asarray(getattr(batched, field)),
                               np.array([getattr(c, field) for c in cpu]), atol=1e-9)
  gap = np.asarray(batched.twist) - np.array([c.twist for c in cpu])
  np.testing.assert_allclose(np.angle(np.exp(1j * gap)), 0.0, atol=1e-9)


def test_slot_is_the_nearest_declared_twist():
  bm = model_lib.build("chair_back_dark_bar")
  rng = np.random.default_rng(1)
  pos, rot = random_frames(rng, len(bm.table))
  with jax.enable_x64(True):
    scores = align.align_pairs(align.pair_tables(bm.table, bm.welds), pos, rot)
    slot, twist = np.asarray(scores.slot), np.asarray(scores.twist)
  welds = bm.welds
  for k in range(bm.table.num_pairs):
    angles = welds.twist_angles[k][welds.twist_valid[k]]
    error = np.abs(np.angle(np.exp(1j * (angles - twist[k]))))
    assert slot[k] == np.argmin(error)
    if bm.table.any_twist[k]:
      assert error.min() <= np.pi / len(angles) + 1e-9
