"""The IK step's own QP assembly (robots/ik_qp.py) against mink's build_ik + qpsolvers."""

import mink
import numpy as np
import pytest

from ikea_suite.robots import ik_qp
from ikea_suite.robots import registry

ARMS = ("sawyer", "baxter", "panda", "jaco")


def _random_rotation(rng):
  quat = rng.normal(size=4)
  return mink.SO3(wxyz=quat / np.linalg.norm(quat)).as_matrix()


@pytest.mark.parametrize("angle", [0.0, 1e-7, 1e-3, 0.3, 2.0, 3.1])
def test_frame_residual_is_minks_error_and_jlog(angle):
  rng = np.random.default_rng(int(angle * 1000))
  for _ in range(20):
    rot, pos = _random_rotation(rng), rng.normal(size=3)
    axis = rng.normal(size=3)
    target_rot = rot @ mink.SO3.exp(angle * axis / np.linalg.norm(axis)).as_matrix()
    target_pos = pos + rng.normal(scale=0.3, size=3)
    frame = mink.SE3.from_rotation_and_translation(mink.SO3.from_matrix(rot), pos)
    target = mink.SE3.from_rotation_and_translation(mink.SO3.from_matrix(target_rot), target_pos)
    error, block, corner = ik_qp.frame_residual(pos.tolist(), rot.ravel().tolist(),
                                                target_pos.tolist(), target_rot.ravel().tolist())
    factor = np.zeros((6, 6))
    factor[:3, :3] = factor[3:, 3:] = np.reshape(block, (3, 3))
    if corner is not None:
      factor[:3, 3:] = -np.reshape(corner, (3, 3))
    np.testing.assert_allclose(error, target.minus(frame), atol=1e-12)
    np.testing.assert_allclose(factor, (target.inverse() @ frame).jlog(), atol=1e-10)


@pytest.mark.parametrize("robot", ARMS)
def test_step_gives_minks_joint_vector(robot):
  """Random states (some beyond the joint limits) and targets near and far, with and
  without the velocity limit: the step's joints equal build_ik + qpsolvers' ones."""
  ik = registry.get(robot).factory().ik
  model = ik.model
  low = np.where(model.jnt_limited, model.jnt_range[:, 0], -np.pi)
  high = np.where(model.jnt_limited, model.jnt_range[:, 1], np.pi)
  rng = np.random.default_rng(0)
  for trial in range(40):
    q = rng.uniform(low - 0.05, high + 0.05)
    other = rng.uniform(low, high) if trial % 4 == 0 else q + rng.normal(scale=0.1, size=len(q))
    targets = ik.tcp_poses(other)
    if trial % 5 == 1:   # a target turned half a turn about a random axis
      pos, rot = targets[0]
      targets[0] = (pos, rot @ _random_rotation(rng))
    for velocity_limited in (True, False):
      dt = (0.05, 0.1)[trial % 2]
      fast = ik.step(q, targets, dt, velocity_limited)
      reference = ik.step_mink(q, targets, dt, velocity_limited)
      np.testing.assert_allclose(fast, reference, atol=1e-6)
    flat = [(list(pos), np.ravel(rot).tolist()) for pos, rot in targets]   # as in_frame gives
    np.testing.assert_array_equal(ik.step(q, flat, 0.05), ik.step(q, targets, 0.05))
    np.testing.assert_allclose(ik.step_mink(q, flat, 0.05), ik.step(q, flat, 0.05), atol=1e-6)
  assert ik.failures == 0


def test_an_endless_joint_wound_whole_turns_steps_as_it_does_unwound():
  """The posture target of an endless joint follows it round by whole turns (the Jaco's
  wrist wound to 16 rad): wound two turns, a joint steps exactly as it does from the same
  angle unwound, and back again after, however often the winding changes."""
  ik = registry.get("jaco").factory().ik
  ik.set_posture(ik.clip_to_limits(np.zeros(ik.model.nq)))
  endless = np.flatnonzero(~ik.model.jnt_limited.astype(bool)
                           & (ik.model.jnt_type == 3))   # hinges
  assert endless.size
  rng = np.random.default_rng(0)
  q = ik.clip_to_limits(rng.uniform(-0.5, 0.5, ik.model.nq))
  targets = ik.tcp_poses(q + rng.normal(scale=0.05, size=len(q)))
  unwound = ik.step(q.copy(), targets, 0.05) - q
  for turns in (2, -1, 2, 0):
    wound = q.copy()
    wound[ik.model.jnt_qposadr[endless[0]]] += 2 * np.pi * turns
    np.testing.assert_allclose(ik.step(wound.copy(), targets, 0.05) - wound, unwound, atol=1e-9)

