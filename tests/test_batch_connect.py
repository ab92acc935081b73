"""Connecting in a batched world gives the CPU task's weld, group and pose state."""

import jax
import numpy as np
import pytest

import ikea_suite
from ikea_suite import geometry
from ikea_suite.batch import connect as connect_lib
from ikea_suite.batch import env as env_lib

FURNITURE = "table_four_leg_lack"
LIFT = np.array([0.0, 0.0, 0.6])


@pytest.fixture(scope="module")
def envs():
  cpu = ikea_suite.load(FURNITURE, "cursor", seed=0)
  cpu.reset()
  batch = env_lib.load(FURNITURE)
  with batch.precision():
    reset = jax.jit(batch.reset)
    connect = jax.jit(lambda st: connect_lib.connect(
        batch.tables, batch.settings.thresholds, st.task, st.data.qpos, st.data.qvel,
        st.data.eq_active, True))
    pose = jax.jit(batch.with_part_poses)
  return cpu, batch, reset, connect, pose


def scene(rng, spec, near):
  """Part poses: the design lifted and turned by a random yaw; parts in `near` are moved a
  little (<= 8 mm, <= 2.5 degrees) and turned by a random quarter twist about their axis;
  every other leg is 0.4 m away from its slot."""
  yaw = geometry.rot_z(rng.uniform(-np.pi, np.pi))
  pos, rot = [], []
  for i, part in enumerate(spec.parts):
    p, r = yaw @ part.pos + LIFT, yaw @ part.rot
    if i in near:
      r = (geometry.axis_angle_to_mat(rng.normal(size=3) / np.sqrt(3) * rng.uniform(0, 0.04))
           @ r @ geometry.rot_z(rng.integers(4) * np.pi / 2))
      p = p + rng.normal(size=3) / np.sqrt(3) * rng.uniform(0, 0.008)
    elif i != 0:
      p = p + np.array([0.0, 0.0, -0.4]) + yaw @ np.array([0.4, 0.0, 0.0])
    pos.append(p)
    rot.append(r)
  return np.array(pos), np.array(rot)


def partition(labels):
  return sorted(sorted(np.flatnonzero(labels == g).tolist()) for g in np.unique(labels))


def cpu_connect(cpu, pos, rot):
  physics, furniture = cpu.physics, cpu.task.furniture
  for i, part in enumerate(furniture.parts):
    part.set_pose(physics, position=pos[i], quaternion=geometry.mat_to_quat(rot[i]))
  physics.forward()
  connected = cpu.task.try_connect(physics)
  physics.forward()
  state = cpu.task.state
  return {
      "connected": connected, "groups": partition(state.group_labels()),
      "used": state.connector_used.copy(), "adjacency": state.adjacency > 0,
      "welds": cpu.task.weld_relative_poses(physics),
      "pos": physics.data.xpos[furniture.body_ids].copy(),
      "rot": physics.data.xmat[furniture.body_ids].reshape(-1, 3, 3).copy()}


def batch_connect(batch, state, connect, pose, pos, rot):
  with batch.precision():
    state = pose(state, pos, rot)
    task, qpos, qvel, eq_active, connected = connect(state)
  bm = batch.batch_model
  on = np.asarray(eq_active)[bm.weld_eq]
  q = np.asarray(qpos)[bm.part_qpos[:, None] + np.arange(7)]
  return state._replace(task=task, data=state.data.replace(
      qpos=qpos, qvel=qvel, eq_active=eq_active)), {
      "connected": bool(connected), "groups": partition(np.asarray(task.group)),
      "used": np.asarray(task.connector_used), "adjacency": np.asarray(task.adjacency),
      "welds": {(int(bm.welds.body1[w]), int(bm.welds.body2[w])):
                np.concatenate([bm.welds.relpos[w], bm.welds.relquat[w]])
                for w in np.flatnonzero(on)},
      "pos": q[:, :3], "rot": geometry.quats_to_mats(q[:, 3:])}


def same_quat(a, b):
  return min(np.abs(a - b).max(), np.abs(a + b).max())


@pytest.mark.parametrize("trial", range(6))
def test_two_connections_match_cpu(envs, trial):
  cpu, batch, reset, connect, pose = envs
  spec = cpu.task.furniture.spec
  rng = np.random.default_rng(trial)
  cpu.reset()
  with batch.precision():
    state = reset(jax.random.PRNGKey(trial))
  legs = rng.permutation(np.arange(1, len(spec.parts)))[:2]
  want = None   # the CPU's result of the previous connection
  for step in range(2):
    pos, rot = scene(rng, spec, near=legs[:step + 1])
    if step == 1:   # the first leg stays where the first connection put it
      pos[legs[0]], rot[legs[0]] = want["pos"][legs[0]], want["rot"][legs[0]]
    want = cpu_connect(cpu, pos, rot)
    state, got = batch_connect(batch, state, connect, pose, pos, rot)
    assert want["connected"] and got["connected"]
    assert got["groups"] == want["groups"]
    np.testing.assert_array_equal(got["used"], want["used"])
    np.testing.assert_array_equal(got["adjacency"], want["adjacency"])
    assert got["welds"].keys() == want["welds"].keys()
    for pair, relpose in want["welds"].items():
      np.testing.assert_allclose(got["welds"][pair][:3], relpose[:3], atol=1e-6)
      assert same_quat(got["welds"][pair][3:], relpose[3:]) < 1e-6
    np.testing.assert_allclose(got["pos"], want["pos"], atol=1e-6)
    np.testing.assert_allclose(got["rot"], want["rot"], atol=1e-6)


def test_misaligned_pair_does_not_connect(envs):
  cpu, batch, reset, connect, pose = envs
  spec = cpu.task.furniture.spec
  rng = np.random.default_rng(99)
  pos, rot = scene(rng, spec, near=[1])
  pos[1] = pos[1] + np.array([0.0, 0.0, -0.03])   # 3 cm below its slot: beyond 2 cm
  cpu.reset()
  with batch.precision():
    state = reset(jax.random.PRNGKey(0))
  want = cpu_connect(cpu, pos, rot)
  _, got = batch_connect(batch, state, connect, pose, pos, rot)
  assert not want["connected"] and not got["connected"]
  assert got["welds"] == {} and got["groups"] == want["groups"]
