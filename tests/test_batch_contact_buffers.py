"""Warp's contact and constraint buffers (ikea_suite/batch/contact_buffers.py): the sizing rule
against CPU MuJoCo's counts on the batched model, the overflow plumbing on MJX's JAX
implementation (always zero: it has no fixed buffers), and, where warp-lang is installed,
a deliberately small buffer reported as an overflow by MJX-Warp on the CPU device."""

import importlib.util
import warnings

import jax
import mujoco
import numpy as np
import pytest

from ikea_suite import errors
from ikea_suite.batch import contact_buffers
from ikea_suite.batch import env as env_lib
from ikea_suite.batch import model as model_lib
from ikea_suite.batch import placement
from ikea_suite.batch import scripted

# Boxes (condim 3), a chair with round legs (cylinders, condim 6) and a bench of mesh slats.
MODELS = ("table_four_leg_lack", "chair_back_dark_bar", "bench_slatted_oak")
STARTS = 3          # scattered starts settled per model
HAS_WARP = importlib.util.find_spec("warp") is not None


def _scattered_starts(bm, num):
  """qpos of `num` starts of the batched env's reset (placement.place), parts at rest."""
  scatter = placement.scatter(bm.spec, spread=0.3, yaw_range=np.pi)
  out = []
  for key in jax.random.split(jax.random.PRNGKey(0), num):
    pos, rot = placement.place(scatter, key)
    qpos = bm.model.qpos0.copy()
    for i, adr in enumerate(bm.part_qpos):
      quat = np.empty(4)
      mujoco.mju_mat2Quat(quat, np.asarray(rot[i], dtype=float).ravel())
      qpos[adr:adr + 3], qpos[adr + 3:adr + 7] = np.asarray(pos[i]), quat
    out.append(qpos)
  return out


@pytest.mark.parametrize("furniture", MODELS)
def test_face_bound_covers_settled_scattered_starts_and_the_assembly(furniture):
  bm = model_lib.build(furniture)
  bound = contact_buffers.part_faces(bm)
  scattered = contact_buffers.settle(bm.model, _scattered_starts(bm, STARTS))
  design = bm.model.qpos0.copy()
  for i, (adr, part) in enumerate(zip(bm.part_qpos, bm.spec.parts)):
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.asarray(part.rot, dtype=float).ravel())
    design[adr:adr + 3], design[adr + 3:adr + 7] = part.pos, quat
  assembled = contact_buffers.settle(bm.model, [design], seconds=0.05)
  for counts in (scattered, assembled):
    assert counts.contacts > 0
    assert counts.contacts <= bound.contacts
    assert counts.candidates <= bound.candidates
    assert counts.contact_rows <= bound.contact_rows
  # Parts lie flat in the scattered starts: every part touches with its worst face's
  # contacts or close to it, so the bound is measured, not padded.
  assert scattered.contacts >= bound.contacts // 2
  sizing = contact_buffers.sizing(bm, num_grips=2)
  assert sizing.nconmax == int(np.ceil(contact_buffers.MARGIN * max(bound.contacts,
                                                                     bound.candidates)))
  assert sizing.njmax == (int(np.ceil(contact_buffers.MARGIN
                                      * (bound.contact_rows + bound.other_rows)))
                          + contact_buffers.equality_rows(2, bm.welds.num_welds, bm.num_parts))
  assert sizing.naconmax(1024) == 1024 * sizing.nconmax


def test_rows_per_contact_follow_condim_and_cone():
  bm = model_lib.build("chair_back_dark_bar")
  data = mujoco.MjData(bm.model)
  data.qpos[:] = _scattered_starts(bm, 1)[0]
  for _ in range(25):   # at rest height the parts touch at 0 distance: let them settle in
    mujoco.mj_step(bm.model, data)
  pairs = contact_buffers.collidable_pairs(bm.model)
  per, other = contact_buffers.counts_by_owner(
      bm.model, data, pairs, np.zeros(bm.model.ngeom, dtype=int), 1)
  # Elliptic cones: one row per contact dimension; the round legs touch with condim 6.
  assert per[0, 2] == int(data.contact.dim[:data.ncon].sum())
  assert 6 in set(data.contact.dim[:data.ncon])
  assert per[0, 0] == data.ncon and other == 0


def test_candidates_are_the_collidable_pairs_near_the_floor():
  bm = model_lib.build("table_four_leg_lack")
  g1, g2 = contact_buffers.collidable_pairs(bm.model)
  floor = [g for g in range(bm.model.ngeom) if bm.model.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE]
  # Parts collide with the floor only: one pair per part collision geom.
  assert len(g1) == len(bm.geom_part)
  assert set(g1) | set(g2) >= set(floor)


def test_given_sizes_are_checked():
  assert contact_buffers.given((4, 30)).nconmax == 4
  for bad in [(0, 30), (4,), (4.0, 30), (True, 30), "4,30", None]:
    with pytest.raises(errors.OptionValueError, match="buffer_sizes"):
      contact_buffers.given(bad)


def test_overflow_words_name_their_buffers():
  assert contact_buffers.describe(0) == []
  assert contact_buffers.describe((1 << 2) | (1 << 3)) == ["naconmax"]
  assert contact_buffers.describe(1 | (1 << 9)) == ["njmax"]     # 1 << 9: solver iterations
  sizing = contact_buffers.size(contact_buffers.Counts(20, 5, 60, 0), equality_rows=72)
  watch = contact_buffers.OverflowWatch(sizing, num_worlds=4)
  watch.watch(np.zeros(4, dtype=np.int32), np.zeros((4, 2), dtype=np.int32))
  with pytest.warns(RuntimeWarning, match=r"naconmax = 120 \(30 per world x 4 worlds\).*"
                                          r"nconmax >= 38"):
    watch.watch(np.array([0, 8, 8, 0], dtype=np.int32), np.tile([100, 50], (4, 1)))
    watch.flush()
  assert watch.world_steps == {"naconmax": 2} and watch.total == 2


def test_jax_implementation_reports_no_overflow():
  env = env_lib.load("table_four_leg_lack", impl="jax")
  worlds = 4
  state = env.reset_batch(jax.random.PRNGKey(0), worlds)
  assert np.asarray(state.info["contact_overflow"]).shape == (worlds,)
  with warnings.catch_warnings():
    warnings.simplefilter("error", RuntimeWarning)
    for _ in range(2):
      state = env.step_batch(state, np.zeros((worlds, env.action_size)))
    assert env.overflow_watch.flush() == {}
  assert not np.asarray(state.info["contact_overflow"]).any()
  assert not np.asarray(state.info["buffer_peak"]).any()


@pytest.mark.skipif(not HAS_WARP, reason="warp-lang is not installed (the gpu extra)")
def test_overflow_bits_and_pairs_are_mujoco_warps():
  from mujoco.mjx.third_party.mujoco_warp._src import io as mjw_io
  from mujoco.mjx.third_party.mujoco_warp._src import types as mjw_types
  t = mjw_types.OverflowType
  assert contact_buffers.OVERFLOW_BUFFERS == {
      t.NEFC: "njmax", t.NJMAX_NNZ: "njmax_nnz", t.BROADPHASE: "naconmax",
      t.NARROWPHASE: "naconmax", t.CCD: "naccdmax", t.NVMAX: "nvmax"}
  bm = model_lib.build("chair_back_dark_bar")
  import warp as wp
  with wp.ScopedDevice("cpu"):
    mw = mjw_io.put_model(bm.model)
  g1, g2 = contact_buffers.collidable_pairs(bm.model)
  assert sorted(zip(g1, g2)) == sorted(map(tuple, mw.nxn_geom_pair_filtered.numpy()))


@pytest.mark.skipif(not HAS_WARP, reason="warp-lang is not installed (the gpu extra)")
def test_warp_on_cpu_reports_a_too_small_buffer_and_not_the_measured_one():
  # MJX's Warp implementation runs on warp's CPU device: slow (minutes of kernel compiles
  # the first time, cached after), so two worlds and two steps.
  worlds = 2
  small = env_lib.load("table_four_leg_lack", impl="warp", num_worlds=worlds,
                       buffer_sizes=(2, 6))
  with pytest.warns(RuntimeWarning, match="naconmax = 4 .*overflowed"):
    steps = scripted.completion_steps(small, worlds, 2)
    assert small.overflow_watch.flush().get("naconmax", 0) > 0
  assert steps.shape == (worlds,)
  measured = env_lib.load("table_four_leg_lack", impl="warp", num_worlds=worlds)
  with warnings.catch_warnings():
    warnings.simplefilter("error", RuntimeWarning)
    scripted.completion_steps(measured, worlds, 2)
    assert measured.overflow_watch.flush() == {}
  assert 0 < measured.overflow_watch.peak[0] <= measured.buffer_sizing.naconmax(worlds)
