"""Every part starts an episode at rest: with zero actions no part moves more than 2 mm or
turns more than 1 degree between the first step and 2 s later (tasks/resting.py).

Every catalog model is checked with the Cursor on the floor at scale 1, and one model of
every family (the one with the most parts) with the Sawyer at its work scale (0.5): the
arms share one placement (tasks/arm_placement.py), and the Sawyer's covers both of its
paths, parts lying within reach and panels standing in the rack. A few models each cover
the work table (round legs lying on its box top, a pedestal tipped onto its foot's rim,
panels in a rack standing on it) and the Baxter (its arms hanging at home over the band
where parts lie). The whole catalog with every arm and arena would take minutes:
benchmarks/rest_sweep.py runs that sweep (any robots, seeds, arena and duration).
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


# (model, seed) on the work table with the Sawyer: round legs that rolled on the box top
# (MuJoCo's convex collider at its default tolerance; physics_settings), a pedestal lying
# tipped onto its foot's rim, a round seat and back, and box walls in a rack on the table.
WORK_TABLE_SAMPLE = [("stool_round_four_leg", 2), ("table_four_leg_w75_black", 2),
                     ("stool_pedestal_birch_bar", 2), ("chair_back_white_round", 2),
                     ("box_open_kuggis", 0)]
# (model, seed) with the Baxter: a TV unit's panels standing in the rack (0.78 m tall built
# on its side, where its forearms hang at home and touched them at seeds 1 and 5; 0.2 m
# built on its front, tasks/arm_placement.root_rest), a dresser's 0.44 m panels, and a
# table (parts lying low).
BAXTER_SAMPLE = [("tv_unit_open_dark_long", 1), ("tv_unit_open_dark_long", 5),
                 ("dresser_chest_four_wide_dark", 1), ("table_four_leg_lack", 0)]


def _check_at_rest(name, robot, seed, **options):
  scale = registry.get(robot).factory.CONFIG.WORK_SCALE
  env = ikea_suite.load(name, robot, seed=seed, scale=scale, **options)
  motion = resting.start_motion(env, seconds=2.0)
  env.close()
  assert motion.drift <= DRIFT_LIMIT and motion.turn <= TURN_LIMIT, (
      f"{name} with the {robot} {options}: {motion.worst_part} moved "
      f"{motion.drift * 1000:.2f} mm and turned {np.degrees(motion.turn):.2f} degrees")


@pytest.mark.parametrize("name", MODELS)
def test_every_part_starts_at_rest_on_the_floor_with_the_cursor(name):
  _check_at_rest(name, "cursor", seed=MODELS.index(name))   # a different yaw draw per model


@pytest.mark.parametrize("name", FAMILY_SAMPLE)
def test_every_part_starts_at_rest_in_an_arms_work_area(name):
  _check_at_rest(name, "sawyer", seed=MODELS.index(name))


@pytest.mark.parametrize("name,seed", WORK_TABLE_SAMPLE)
def test_every_part_starts_at_rest_on_the_work_table(name, seed):
  _check_at_rest(name, "sawyer", seed, arena="work_table")


@pytest.mark.parametrize("name,seed", BAXTER_SAMPLE)
def test_every_part_starts_at_rest_in_the_baxters_work_area(name, seed):
  _check_at_rest(name, "baxter", seed)


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


def _touching_the_robot(env, robot):
  """(body, body) pairs of a part and the robot in contact after one zero-action step."""
  env.reset()
  env.step(np.zeros(env.action_spec().shape))
  model, data = env.physics.model, env.physics.data
  parts = set(env.task.furniture.body_ids.tolist())
  touching = {(model.id2name(model.geom_bodyid[c.geom1], "body"),
               model.id2name(model.geom_bodyid[c.geom2], "body"))
              for c in data.contact[:data.ncon]
              if {model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]} & parts}
  return [pair for pair in touching if any(n.startswith(f"{robot}/") for n in pair)]


@pytest.mark.parametrize("name,seeds", [
    # The torso is 0.67 m wide: a 0.8 m bed rail drawn beside it lay against it and was pushed.
    ("bed_slatted_kids_dark_open", (1, 2)),
    # The arms hang at home over the band: the forearms touched 0.78 m panels in the rack
    # (a TV unit built on its side); a dresser racks 0.44 m panels.
    ("tv_unit_open_dark_long", (1, 5, 8)),
    ("dresser_chest_four_wide_dark", (1, 5, 8))])
def test_no_part_starts_against_the_baxter(name, seeds):
  env = ikea_suite.load(name, "baxter", seed=seeds[0], scale=0.5)
  for seed in seeds:
    env.random_state.seed(seed)
    assert not _touching_the_robot(env, "baxter"), (name, seed)


@pytest.mark.parametrize("robot", registry.names("arm"))
def test_an_arms_home_footprint_holds_its_body_and_its_hanging_tools(robot):
  """The placement keeps parts clear of the robot where it stands at home: its footprint
  has a box over each tool's home position, as low as the tool (within the fingers'
  length), and one round the base that reaches the floor."""
  env = ikea_suite.load("table_four_leg_lack", robot, seed=0)
  env.reset()
  arm = env.task.robot
  footprint = arm.reach_zone.home_footprint
  base_pos, base_rot = arm.base_pose
  assert footprint.ndim == 2 and footprint.shape[1] == 5
  for tool in arm.tool_positions(env.physics):
    local = base_rot[:2, :2].T @ (tool[:2] - base_pos[:2])
    over = ((footprint[:, 0] <= local[0]) & (local[0] <= footprint[:, 2])
            & (footprint[:, 1] <= local[1]) & (local[1] <= footprint[:, 3]))
    assert over.any() and abs(footprint[over, 4].min() - tool[2]) < 0.06, (robot, tool)
  at_base = (footprint[:, 0] <= 0) & (0 <= footprint[:, 2]) & (footprint[:, 1] <= 0) & (
      0 <= footprint[:, 3])
  assert footprint[at_base, 4].min() <= base_pos[2] + 1e-6
