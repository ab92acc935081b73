"""Kept MjData views and compact indices (ikea_suite/mujoco_arrays.py)."""

import numpy as np
from dm_control import mujoco as dm_mujoco

from ikea_suite import mujoco_arrays

_XML = """<mujoco><worldbody>
  <body><joint type="slide"/><geom size="0.1"/></body>
  <body><joint type="hinge"/><geom size="0.1"/></body>
</worldbody></mujoco>"""


def test_compact_index_is_a_slice_only_where_the_ids_run_consecutively_upward():
  values = np.arange(10.0) * 3
  for ids in ([4, 5, 6], [[2, 3], [4, 5]], [7], [5, 4], [1, 3, 4], []):
    index = mujoco_arrays.compact_index(ids)
    consecutive = len(ids) > 0 and np.array_equal(np.ravel(ids), np.arange(
        np.ravel(ids)[0], np.ravel(ids)[0] + np.size(ids)))
    assert isinstance(index, slice) == consecutive, ids
    np.testing.assert_array_equal(values[index], values[np.ravel(ids).astype(int)])


def test_array_views_follow_the_physics_they_are_asked_about():
  views = mujoco_arrays.ArrayViews("qpos", "xpos")
  first, second = (dm_mujoco.Physics.from_xml_string(_XML) for _ in range(2))
  first.data.qpos[:] = [0.1, 0.2]
  kept = views(first)
  assert views(first) is kept   # fetched once per MjData
  assert np.shares_memory(kept.qpos, first.data.qpos) and list(kept.qpos) == [0.1, 0.2]
  assert np.shares_memory(views(second).qpos, second.data.qpos)   # another physics: fetched again
  first.data.qpos[0] = 0.5   # writes through the kept view's buffer
  assert views(first).qpos[0] == 0.5
