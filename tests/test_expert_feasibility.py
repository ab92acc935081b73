"""experts.gripper_fit: which loose parts a gripper can take from above, as they lie."""

import pytest

import ikea_suite
from ikea_suite.experts import gripper_fit
from ikea_suite.robots import grippers


def _env(furniture, robot):
  env = ikea_suite.load(furniture, robot, scale=0.5, seed=0)
  env.reset()
  return env


def _gaps(robot):
  env = _env("stool_round_frosta", robot)
  return tuple(gripper_fit.finger_gap(env.physics, env.task.robot, 0, f) for f in (1.0, 0.0))


@pytest.fixture
def slot_2(monkeypatch):
  """The Baxter with its fingers in the Rethink sheet's slot (grippers.RETHINK), not slot 1."""
  monkeypatch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)


def test_rethink_tips_open_wider_than_they_close(slot_2):
  closed, opened = _gaps("baxter")   # fingers in the sheet's slot
  # Rethink's fact sheet: 2 x 32.3 mm of finger travel between the joint limits.
  assert opened - closed == pytest.approx(2 * (0.020833 + 0.0115), abs=0.002)
  assert 0.010 < closed < 0.020   # the fingertips stop short of touching


def test_rethink_fingers_one_slot_in_meet_when_closed(monkeypatch):
  # grippers.RETHINK_SLOT_1: each finger 9.5 mm nearer the centre; travel ends where they meet.
  for robot in ("sawyer", "baxter"):
    closed, opened = _gaps(robot)
    assert 0.0 <= closed < 0.001
    with monkeypatch.context() as patch:
      patch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)
      assert opened == pytest.approx(_gaps("baxter")[1] - 2 * 0.0095, abs=0.0005)


def test_slender_legs_fit_and_a_drawer_fits_by_its_front():
  assert gripper_fit.grasp_problems(_env("stool_round_frosta", "sawyer")) == []
  # A panel wider than the open fingers that lies flat in the furniture stands in the panel
  # rack on its long edge and is taken by that edge (tests/test_panel_rack.py), so the
  # coffee table's shelf is no problem; a drawer box, wider than any stroke, is taken by
  # its front's top edge (tests/test_hollow_parts.py).
  assert gripper_fit.grasp_problems(_env("table_coffee_shelf_w90_birch", "panda")) == []
  assert gripper_fit.grasp_problems(_env("nightstand_drawer_birch", "panda")) == []


def test_legs_thinner_than_the_closed_rethink_fingers_are_named(monkeypatch):
  for robot in ("panda", "sawyer", "baxter"):
    assert gripper_fit.grasp_problems(_env("stool_round_black_metal", robot)) == []
  monkeypatch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)   # the sheet's slot
  problems = gripper_fit.grasp_problems(_env("stool_round_black_metal", "baxter"))
  assert sorted(p.part for p in problems) == ["leg0", "leg1", "leg2", "leg3"]
  assert "narrower than the closed" in str(problems[0])
