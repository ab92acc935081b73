"""The paper's alignment test (distance, up, forward over allowed twists), without a simulator."""

import types

import numpy as np
import pytest

from ikea_suite import geometry
from ikea_suite.tasks import alignment

THRESHOLDS = alignment.Thresholds(distance=0.02, up_cos=0.99, forward_cos=0.99)


def one_pair_table(twists_deg):
  """A ConnectorTable-shaped object with connectors 0 and 1 as the only candidate pair."""
  angles = np.radians(np.array(twists_deg, dtype=float)).reshape(1, -1) if twists_deg else np.zeros((1, 1))
  valid = np.ones_like(angles, dtype=bool) if twists_deg else np.zeros((1, 1), dtype=bool)
  return types.SimpleNamespace(
      pair_a=np.array([0]), pair_b=np.array([1]), twist_angles=angles,
      twist_cos=np.cos(angles), twist_sin=np.sin(angles), twist_valid=valid,
      any_twist=np.array([not twists_deg]))


def frames(offset=(0, 0, 0), rot_b=np.eye(3), rot_a=np.eye(3)):
  pos = np.array([[0.0, 0, 0], offset], dtype=float)
  return pos, np.stack([rot_a, rot_b])


def check(table, pos, rot):
  return bool(alignment.align_pairs(pos, rot, table).attachable(THRESHOLDS)[0])


def test_coincident_frames_attach():
  assert check(one_pair_table([0]), *frames())


@pytest.mark.parametrize("gap, expected", [(0.019, True), (0.021, False)])
def test_distance_threshold(gap, expected):
  assert check(one_pair_table([0]), *frames(offset=(gap, 0, 0))) is expected


@pytest.mark.parametrize("tilt_deg, expected", [(7.0, True), (9.0, False)])
def test_up_threshold(tilt_deg, expected):
  # cos(8.1 deg) = 0.99: tilting up about x by 7 passes, by 9 fails.
  tilt = geometry.axis_angle_to_mat(np.radians(tilt_deg) * np.array([1.0, 0, 0]))
  assert check(one_pair_table([]), *frames(rot_b=tilt)) is expected


@pytest.mark.parametrize("twist_deg, expected", [(0, True), (7, True), (9, False), (45, False),
                                                 (90, True), (180, True), (270, True), (263, True)])
def test_forward_threshold_over_square_twists(twist_deg, expected):
  rot_b = geometry.rot_z(np.radians(twist_deg))
  assert check(one_pair_table([0, 90, 180, 270]), *frames(rot_b=rot_b)) is expected


def test_twist_not_allowed_is_rejected():
  assert not check(one_pair_table([0, 180]), *frames(rot_b=geometry.rot_z(np.pi / 2)))
  assert check(one_pair_table([0, 180]), *frames(rot_b=geometry.rot_z(np.pi)))


def test_any_twist_ignores_forward_but_not_up():
  table = one_pair_table([])
  assert check(table, *frames(rot_b=geometry.rot_z(1.234)))
  flipped = geometry.axis_angle_to_mat(np.array([np.pi, 0, 0]))
  assert not check(table, *frames(rot_b=flipped))


def test_reported_twist_is_the_matching_one():
  scores = alignment.align_pairs(*frames(rot_b=geometry.rot_z(np.radians(92))),
                                 one_pair_table([0, 90, 180, 270]))
  assert np.isclose(scores.twist[0], np.pi / 2)
  any_scores = alignment.align_pairs(*frames(rot_b=geometry.rot_z(0.7)), one_pair_table([]))
  assert np.isclose(any_scores.twist[0], 0.7)


def test_symmetric_in_the_two_connectors():
  rng = np.random.default_rng(0)
  table = one_pair_table([0, 90, 180, 270])
  for _ in range(200):
    base = geometry.axis_angle_to_mat(rng.normal(size=3))
    twist = geometry.rot_z(rng.choice([0, np.pi / 2, np.pi, 1.5 * np.pi]) + rng.normal(scale=0.1))
    tilt = geometry.axis_angle_to_mat(rng.normal(scale=0.1, size=3))
    rot_a, rot_b = base, tilt @ base @ twist
    offset = rng.normal(scale=0.015, size=3)
    forward = check(table, np.array([[0, 0, 0], offset]), np.stack([rot_a, rot_b]))
    backward = check(table, np.array([offset, [0, 0, 0]]), np.stack([rot_b, rot_a]))
    assert forward == backward


def test_all_pairs_scored_at_once():
  table = types.SimpleNamespace(
      pair_a=np.array([0, 0]), pair_b=np.array([1, 2]), twist_angles=np.zeros((2, 1)),
      twist_cos=np.ones((2, 1)), twist_sin=np.zeros((2, 1)), twist_valid=np.ones((2, 1), bool),
      any_twist=np.array([False, False]))
  pos = np.array([[0, 0, 0], [0.01, 0, 0], [0.5, 0, 0]], dtype=float)
  rot = np.stack([np.eye(3)] * 3)
  assert alignment.align_pairs(pos, rot, table).attachable(THRESHOLDS).tolist() == [True, False]
