"""experts.work_scale: the scale each furniture is assembled at, from the gripper fit; and
experts.below_work_scale: what the arm expert does differently below the work scale."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.experts import below_work_scale
from ikea_suite.experts import gripper_fit
from ikea_suite.experts import work_scale
from ikea_suite.robots import grippers


def test_stools_and_bookcases_stay_at_the_work_scale_and_beds_get_their_fit():
  assert work_scale.work_scale("panda", "stool_round_frosta") == 0.5
  # The bookcase's sides stand in the panel rack, the far one on its long edge.
  assert work_scale.work_scale("panda", "bookcase_shelf_unit_billy") == 0.5
  assert work_scale.work_scale("panda", "bed_slatted_toddler_white") == work_scale.SMALL_SCALES[
      "panda"]["bed_slatted_toddler_white"] < 0.5


def test_furniture_measured_smaller_for_reach_or_grip_gets_that_scale():
  # The tall post shelving's far mates lie beyond the Panda's reach at 0.5; the low one
  # it assembles there, and the Sawyer only at 0.35.
  assert work_scale.work_scale("panda", "shelving_posts_white_low") == 0.5
  assert work_scale.work_scale("panda", "shelving_posts_black_six") == 0.4
  assert work_scale.work_scale("sawyer", "shelving_posts_white_low") == 0.35
  assert work_scale.work_scale("baxter", "shelving_posts_white_low") == 0.35   # same fingers
  for robot, scales in work_scale.REACH_SCALES.items():
    for furniture, scale in scales.items():
      assert 0.2 <= scale < 0.5
      assert work_scale.fit_scale(robot, furniture) == 0.5   # their parts fit at 0.5


def test_fit_scale_is_the_largest_at_which_every_loose_part_fits():
  # The bed's side rails lie flat, wider than the open fingers at 0.5.
  scale = work_scale.fit_scale("panda", "bed_slatted_toddler_white")
  assert scale == work_scale.SMALL_SCALES["panda"]["bed_slatted_toddler_white"]
  for s, fits in ((scale, True), (scale + 0.02, False)):
    env = ikea_suite.load("bed_slatted_toddler_white", "panda", scale=s, seed=0)
    env.reset()
    assert (gripper_fit.grasp_problems(env) == []) == fits
  assert work_scale.fit_scale("panda", "bookcase_shelf_unit_billy") == 0.5


def test_a_racked_plank_bench_fits_fingers_that_close_fully_and_never_slot_2(monkeypatch):
  # Lying flat, its 300-330 mm ends fitted the open fingers only at about 0.2. Racked,
  # its ends and its 10 mm stretcher are taken across their thickness: the Panda's
  # fingers close fully, and so do the Sawyer's and the Baxter's one slot in; in the
  # sheet's slot they stop 14 mm apart.
  for robot in ("panda", "sawyer", "baxter"):
    assert work_scale.fit_scale(robot, "bench_plank_pine") == 0.5
    assert work_scale.work_scale(robot, "bench_plank_pine") == 0.5
  monkeypatch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)
  assert work_scale.fit_scale("baxter", "bench_plank_pine") is None


def test_no_scale_fits_a_chair_in_slot_2_and_a_fitting_model_keeps_the_work_scale(
    monkeypatch):
  # The chair's thin parts slip between fingers stopped 14 mm apart at every scale; one
  # slot in, the fingers meet and the chair fits at the work scale.
  assert work_scale.fit_scale("baxter", "chair_back_ivar") == 0.5
  assert work_scale.fit_scale("baxter", "stool_round_frosta") == 0.5
  monkeypatch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)
  assert work_scale.fit_scale("baxter", "chair_back_ivar") is None


def test_a_bench_end_is_held_away_from_its_connectors_below_the_work_scale():
  env = ikea_suite.load("bench_plank_pine", "sawyer", scale=0.22, seed=0)
  assert below_work_scale.active(env)
  furniture = env.task.furniture
  names = [p.name for p in furniture.spec.parts]
  table = furniture.connectors
  end = names.index("end0")
  shift = below_work_scale.grip_shift(furniture, end)
  connectors = table.local_pos[table.part == end].mean(axis=0)
  assert shift[2] * connectors[2] < 0 and abs(shift[2]) > 0.02   # the far end, along its length
  assert np.count_nonzero(shift) == 1
  # The stretcher, joined at both ends, is held at its middle.
  assert not below_work_scale.grip_shift(furniture, names.index("stretcher")).any()
  assert not below_work_scale.active(
      ikea_suite.load("bench_plank_pine", "sawyer", scale=0.5, seed=0))


def _grasp_height_over_part(scale):
  """Tool height over the underside of a lying Lack leg at the expert's grasp pose, less
  the fingertips' reach: the fingertips' height over the part's underside."""
  from ikea_suite import experts
  from ikea_suite import geometry
  from ikea_suite.experts import arm_motion
  from ikea_suite.experts import part_geometry
  env = ikea_suite.load("table_four_leg_lack", "sawyer", scale=scale, seed=0)
  env.reset()
  expert = experts.make_expert(env, require_supported=False)   # below its measured scale
  part = 1 if env.task.root_part != 1 else 2
  point, _ = expert._grasp_pose(part, 1.0)
  pos, rot = part_geometry.part_pose(env.physics, env.task.furniture, part)
  bounds = env.task.furniture.spec.parts[part].bounds
  bottom = (geometry.box_corners(*bounds) @ rot.T + pos)[:, 2].min()
  return point[2] - bottom - arm_motion.fingertip_reach(env.task.robot, env.physics, 0)


def test_fingertips_close_lower_on_parts_below_the_work_scale():
  assert _grasp_height_over_part(0.5) == pytest.approx(0.003, abs=1e-6)
  assert _grasp_height_over_part(0.22) == pytest.approx(below_work_scale.TIP_CLEARANCE, abs=1e-6)
  assert below_work_scale.TIP_CLEARANCE < 0.003
