"""Every part starts an episode at rest: with zero actions no part moves more than 2 mm or
turns more than 1 degree between the first step and 2 s later (tasks/resting.py).

Every catalog model is checked with the Cursor on the floor at scale 1, and one model of
every family (the one with the most parts) with the Sawyer at its work scale (0.5): the
arms share one placement (tasks/arm_placement.py), and the Sawyer's covers both of its
paths, parts lying within reach and panels standing in the rack. The whole catalog with
every arm would take minutes: benchmarks/rest_sweep.py runs that sweep (any robots, seeds,
arena and duration).
"""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import geometry
from ikea_suite.props import catalog
from ikea_suite.props import model_format
from ikea_suite.robots import registry
from ikea_suite.tasks import panel_placement
from ikea_suite.tasks import placement
from ikea_suite.tasks import resting

DRIFT_LIMIT = 0.002            # m
TURN_LIMIT = np.radians(1.0)
MODELS = catalog.names()
# One model per family, the one with the most parts (the most panels in the rack).
FAMILY_SAMPLE = [max(sorted(n for n in catalog.names(category=c) if catalog.entries()[n].family == f),
                     key=lambda n: catalog.entries()[n].num_parts)
                 for c, f in catalog.families()]


def _check_at_rest(name, robot, seed):
  scale = registry.get(robot).factory.CONFIG.WORK_SCALE
  env = ikea_suite.load(name, robot, seed=seed, scale=scale)
  motion = resting.start_motion(env, seconds=2.0)
  env.close()
  assert motion.drift <= DRIFT_LIMIT and motion.turn <= TURN_LIMIT, (
      f"{name} with the {robot}: {motion.worst_part} moved {motion.drift * 1000:.2f} mm and "
      f"turned {np.degrees(motion.turn):.2f} degrees")


@pytest.mark.parametrize("name", MODELS)
def test_every_part_starts_at_rest_on_the_floor_with_the_cursor(name):
  _check_at_rest(name, "cursor", seed=MODELS.index(name))   # a different yaw draw per model


@pytest.mark.parametrize("name", FAMILY_SAMPLE)
def test_every_part_starts_at_rest_in_an_arms_work_area(name):
  _check_at_rest(name, "sawyer", seed=MODELS.index(name))


def _turn_degrees(a, b):
  return np.degrees(np.linalg.norm(geometry.mat_to_axis_angle(a @ b.T)))


def test_a_part_at_rest_where_it_is_laid_keeps_its_placement():
  spec = model_format.load_spec(catalog.path_of("table_four_leg_lack"))
  rests = placement.lying_rests(spec)
  for index, part in enumerate(spec.parts):
    assert rests[index].position is None
    assert np.array_equal(rests[index].rotation, placement.resting_rotation(part.bounds))


def test_a_pedestal_starts_on_its_side_as_it_would_fall():
  """Laid with its thinnest extent up, the pedestal's heavy foot and long column tip it
  14.6 degrees onto the line from the foot's rim to the column's end."""
  spec = model_format.load_spec(catalog.path_of("stool_pedestal_birch_bar"))
  index = spec.part_index("pedestal")
  rest = placement.lying_rests(spec)[index]
  lying = placement.resting_rotation(spec.parts[index].bounds)
  assert 13.0 < _turn_degrees(rest.rotation, lying) < 16.0
  assert 0.15 < rest.position[2] < 0.25   # its origin, at the foot, is held up by the rim


def test_a_round_seat_starts_at_its_rest_height_instead_of_landing():
  """A cylinder lying on its flat end loses MuJoCo's plane contacts for part of a landing
  at some yaws: it starts at rest instead, sunk into the floor as far as at rest."""
  spec = model_format.load_spec(catalog.path_of("stool_round_frosta"))
  index = spec.part_index("seat")
  rest = placement.lying_rests(spec)[index]
  half_height = 0.015
  assert rest.position is not None and 0 < half_height - rest.position[2] < 2e-4


def test_tall_thin_panels_lean_in_their_rack_slots_all_the_same_way():
  """A dresser's back balances upright only in a rack square to the axes: it starts leaning
  on a fin as it would come to rest (4 degrees), and, whichever way round it stands, every
  leaning panel leans towards the rack's +x, so none leans onto its neighbour."""
  env = ikea_suite.load("dresser_chest_three_white", "sawyer", seed=0, scale=0.5)
  task = env.task
  rack, racked = task.initializer.fixtures[0], task.initializer.racked_parts
  leans = []
  for seed in range(4):
    env.random_state.seed(seed)
    env.reset()
    rack_pos, rack_quat = rack.get_pose(env.physics)
    rack_rot = geometry.quat_to_mat(rack_quat)
    pos, rot = task.furniture.part_poses(env.physics)
    for index in racked:
      corners = geometry.box_corners(*task.furniture.spec.parts[index].bounds) @ rot[index].T
      order = np.argsort(corners[:, 2])
      rise = rack_rot.T @ (corners[order[4:]].mean(0) - corners[order[:4]].mean(0))
      leans.append((task.furniture.spec.parts[index].name, np.degrees(np.arctan2(rise[0], rise[2]))))
  back = [angle for name, angle in leans if name == "back"]
  assert all(2.0 < angle < 6.0 for angle in back), back
  assert all(angle > -0.5 for _, angle in leans), leans


def test_a_round_panel_stands_between_chocks_and_neither_rolls_nor_spins():
  """Stood on its rim in a plain slot a disc is a wheel (a round table top rolled 29-289 mm
  in 20 s), and cradled by box edges it spun in place: its slot's chocks touch the rim
  with their faces."""
  spec = model_format.load_spec(catalog.path_of("table_round_post_d90_dark"))
  top = spec.part_index("top")
  assert panel_placement.is_disc(spec.parts[top], int(np.argmin(np.ptp(spec.parts[top].bounds, 0))))
  env = ikea_suite.load("table_round_post_d90_dark", "sawyer", seed=0, scale=0.5)
  assert top in env.task.initializer.racked_parts
  rack = env.task.initializer.fixtures[0]
  assert sum(g.name.startswith("chock") for g in rack.geoms) == 2 * sum(
      panel_placement.is_disc(spec.parts[i], int(np.argmin(np.ptp(spec.parts[i].bounds, 0))))
      for i in env.task.initializer.racked_parts)
  env.random_state.seed(111)   # a yaw at which a round top spun 2 degrees a second
  motion = resting.start_motion(env, seconds=10.0)
  assert motion.drift < DRIFT_LIMIT and motion.turn < TURN_LIMIT, motion


def test_no_part_starts_against_the_baxters_torso():
  """The torso is 0.67 m wide: a 0.8 m bed rail drawn beside it lay against it and was pushed."""
  env = ikea_suite.load("bed_slatted_kids_dark_open", "baxter", seed=1, scale=0.5)
  model = env.physics.model
  for seed in (1, 2):
    env.random_state.seed(seed)
    env.reset()
    env.step(np.zeros(env.action_spec().shape))
    parts = set(env.task.furniture.body_ids.tolist())
    data = env.physics.data
    touching = {(model.id2name(model.geom_bodyid[c.geom1], "body"),
                 model.id2name(model.geom_bodyid[c.geom2], "body"))
                for c in data.contact[:data.ncon]
                if {model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]} & parts}
    assert not [pair for pair in touching if any(n.startswith("baxter/") for n in pair)], touching
