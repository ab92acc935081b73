"""The panel rack: thin panels that stand upright in the furniture wait upright for an arm."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import experts
from ikea_suite import geometry
from ikea_suite.experts import gripper_fit
from ikea_suite.experts import mating
from ikea_suite.experts import part_geometry
from ikea_suite.experts import single_arm
from ikea_suite.experts import top_down_grasp
from ikea_suite.props import panel_rack
from ikea_suite.robots import grippers
from ikea_suite.tasks import panel_placement
from tests import helpers

WALLS = ["long_wall0", "long_wall1", "short_wall0", "short_wall1"]


def _env(furniture="box_open_small_white", robot="panda", seed=0):
  env = ikea_suite.load(furniture, robot, scale=0.5, seed=seed)
  env.reset()
  return env


def _racked_names(env):
  spec = env.task.furniture.spec
  return sorted(spec.parts[i].name for i in env.task.initializer.racked_parts)


def _rack_body(env):
  return env.physics.bind(env.task.initializer.fixtures[0].mjcf_model.worldbody)


def _tilt_degrees(rot):
  """Angle (deg) between a standing panel's plane and the vertical: its normal's rise."""
  return [np.degrees(np.arcsin(min(1.0, np.min(np.abs(r[2]))))) for r in rot]


def test_box_walls_stand_upright_in_their_slots_within_reach():
  env = _env()
  assert _racked_names(env) == WALLS
  rack = env.task.initializer.fixtures[0]
  positions, rotations = env.task.furniture.part_poses(env.physics)
  racked = env.task.initializer.racked_parts
  rack_pos = _rack_body(env).xpos
  rack_rot = _rack_body(env).xmat.reshape(3, 3)
  for slot, part in enumerate(racked):
    rot = rotations[part]
    spec = env.task.furniture.spec.parts[part]
    thin = int(np.argmin(spec.bounds[1] - spec.bounds[0]))
    assert abs(rot[2, thin]) < 1e-6   # the thickness lies horizontal: the panel stands
    assert abs(abs(rot[:, thin] @ rack_rot[:, 0]) - 1.0) < 1e-6   # across the slot
    corners = geometry.box_corners(*spec.bounds) @ rot.T + positions[part]
    assert corners[:, 2].min() == pytest.approx(rack_pos[2] + panel_rack.PLATE, abs=2e-3)
    slot_centre = rack_pos + rack_rot @ rack.slot_centre(slot)
    assert np.linalg.norm(corners[:, :2].mean(0) - slot_centre[:2]) < 1e-3
  zone = env.task.robot.reach_zone
  distance = np.linalg.norm(rack_pos[:2] - zone.base_xy)
  assert zone.min_distance <= distance <= zone.reach


@pytest.mark.parametrize("robot", ["panda", "jaco"])
def test_the_farthest_slot_stands_well_within_reach(robot):
  # Fingers that must close within 1.5 mm of a panel's edge miss it at full stretch.
  env = ikea_suite.load("box_open_small_white", robot, scale=0.5, seed=4)
  zone = env.task.robot.reach_zone
  for _ in range(6):
    env.reset()
    rack = env.task.initializer.fixtures[0]
    body = _rack_body(env)
    for slot in (0, rack.num_slots - 1):
      centre = body.xpos + body.xmat.reshape(3, 3) @ rack.slot_centre(slot)
      assert np.linalg.norm(centre[:2] - zone.base_xy) <= (
          zone.reach - panel_placement.RACK_SPARE + 1e-6)


def test_racked_panels_stand_still_until_taken():
  env = _env(seed=3)
  racked = env.task.initializer.racked_parts
  before, _ = env.task.furniture.part_poses(env.physics)
  before = before[racked].copy()
  for _ in range(40):   # 2 s, the arm holding still
    env.step(np.zeros(env.action_spec().shape))
  after, rotations = env.task.furniture.part_poses(env.physics)
  assert np.abs(after[racked] - before).max() < 0.002   # the 1 mm drop onto the plate
  assert max(_tilt_degrees(rotations[racked])) < 0.5


def test_only_panels_that_stand_in_the_furniture_are_racked(monkeypatch):
  # A lid lies flat on the box: no wider than FLAT_WIDE it stays lying on the floor, like
  # every stool's and four-leg table's legs, whose placement is unchanged (no rack in
  # their scene).
  spec = _env("box_lidded_white_flat").task.furniture.spec
  lid = next(i for i, part in enumerate(spec.parts) if part.name == "lid")
  monkeypatch.setattr(panel_placement, "FLAT_WIDE", 0.2)   # the lid is 180 mm across
  assert lid not in [i for i, _ in panel_placement.upright_panels(spec, 0, np.eye(3))]
  monkeypatch.undo()
  for furniture in ("table_four_leg_lack", "stool_round_frosta"):
    env = _env(furniture)
    assert env.task.initializer.racked_parts == []
    assert env.task.initializer.fixtures == []
  # The Cursor's scattered placement has no rack either.
  cursor = ikea_suite.load("box_open_small_white", "cursor", seed=0)
  assert cursor.task.initializer.fixtures == []


@pytest.mark.parametrize("furniture,part", [("box_lidded_white_flat", "lid"),
                                            ("bookcase_shelf_unit_billy", "side1")])
def test_a_wide_panel_that_lies_flat_in_the_furniture_stands_on_its_long_edge(furniture, part):
  # Lying flat it is wider than the Sawyer's open fingers; on its long edge it is taken
  # across its thickness by that edge (experts/top_down_grasp.py) and turned flat.
  env = _env(furniture)
  spec = env.task.furniture.spec
  index = next(i for i, p in enumerate(spec.parts) if p.name == part)
  assert index in env.task.initializer.racked_parts
  _, rotations = env.task.furniture.part_poses(env.physics)
  extents = spec.parts[index].bounds[1] - spec.parts[index].bounds[0]
  thin, middle, long = np.argsort(extents)
  assert extents[middle] > panel_placement.FLAT_WIDE
  assert abs(rotations[index][2, middle]) > 0.99   # its width stands up
  assert abs(rotations[index][2, thin]) < 0.1 and abs(rotations[index][2, long]) < 0.1
  _, assembled = part_geometry.assembled_pose(env.physics, env.task.furniture,
                                              env.task.root_part, index)
  assert abs(assembled[2, thin]) > 0.99   # and lies flat once assembled


def test_only_a_part_of_bars_is_a_frame():
  spec = _env("shelving_posts_white_low").task.furniture.spec
  frames = [p.name for p in spec.parts if panel_placement.is_frame(p)]
  assert frames == ["ladder0", "ladder1"]   # two posts and two crossbars; not the shelves
  for furniture in ("box_open_small_white", "table_four_leg_lack"):   # plates, single legs
    assert not any(panel_placement.is_frame(p) for p in _env(furniture).task.furniture.spec.parts)


def test_a_wide_frame_that_lies_flat_in_the_furniture_lies_on_the_floor_as_it_lies_there():
  # A shelving ladder, stood on its long edge in the rack, had to be turned flat on its
  # way in, which the Panda's wrist could not do over the shelves; lying on the floor as
  # it will lie on them, its post is taken from above and it goes in turned only about
  # the vertical.
  env = _env("shelving_posts_white_low", seed=1000)
  spec, task = env.task.furniture.spec, env.task
  far = spec.part_index("ladder1")
  assert far not in task.initializer.racked_parts
  assert _racked_names(env) == ["shelf0", "shelf1", "shelf2"]
  assert [i for i, _ in panel_placement.flat_frames(spec, task.root_part,
                                                    task.initializer._root_rest)] == [far]
  positions, rotations = task.furniture.part_poses(env.physics)
  _, assembled = part_geometry.assembled_pose(env.physics, task.furniture, task.root_part, far)
  thin = int(np.argmin(np.ptp(spec.parts[far].bounds, axis=0)))
  assert rotations[far][2, thin] == pytest.approx(assembled[2, thin], abs=0.02)   # same face up
  assert abs(rotations[far][2, thin]) > 0.99
  corners = geometry.box_corners(*spec.parts[far].bounds) @ rotations[far].T + positions[far]
  assert corners[:, 2].min() == pytest.approx(0.0, abs=3e-3)   # lying on the floor


def test_a_frame_is_taken_by_its_longest_bar_clear_of_its_connectors():
  env = _env("shelving_posts_white_low", seed=1000)
  expert = experts.make_expert(env, require_supported=False)
  furniture, physics = env.task.furniture, env.physics
  far = furniture.spec.part_index("ladder1")
  point, rot = expert._grasps.pose(far, 1.0)
  position, part_rot = part_geometry.part_pose(physics, furniture, far)
  local = part_rot.T @ (point - position)
  bounds = furniture.spec.parts[far].bounds
  thin, across, along = np.argsort(bounds[1] - bounds[0])
  post = abs(bounds[1][across]) - 0.0125 * furniture.spec.scale   # a post's axis (radius 12.5 mm)
  assert abs(abs(local[across]) - post) < 0.005   # over a post, not the open middle
  connectors = furniture.connectors.local_pos[furniture.connectors.part == far][:, along]
  assert np.abs(connectors - local[along]).min() >= top_down_grasp.FLAT_EDGE_CLEAR - 1e-3
  closing = rot @ expert.closing_local()
  assert abs(closing @ part_rot[:, along]) < 1e-6   # the fingers close across the post


def test_walls_in_the_rack_fit_fingers_that_close_fully_and_are_too_thin_for_slot_2(
    monkeypatch):
  assert gripper_fit.grasp_problems(_env()) == []
  for robot in ("sawyer", "baxter"):   # their fingers one slot in
    assert gripper_fit.grasp_problems(_env(robot=robot)) == []
  # In the descriptions' default slot the closed fingertips stay 14 mm apart.
  monkeypatch.setattr(grippers, "RETHINK_SLOT_1", grippers.RETHINK)
  problems = gripper_fit.grasp_problems(_env(robot="baxter"))
  assert sorted(p.part for p in problems) == WALLS
  assert all("narrower than the closed" in str(p) for p in problems)


@pytest.mark.parametrize("furniture", ["box_open_small_white", "bench_plank_pine"])
def test_a_two_arm_robot_gets_a_rack_each_side_holding_that_sides_panels(furniture):
  # One rack on one side of the Baxter's torso was out of the other arm's reach.
  env = _env(furniture, robot="baxter")
  initializer = env.task.initializer
  groups = initializer.rack_groups
  assert len(initializer.fixtures) == len(groups) == 2
  assert sorted(i for group in groups for i in group) == sorted(initializer.racked_parts)
  positions, _ = env.task.furniture.part_poses(env.physics)
  base_pos, base_rot = env.task.robot.base_pose

  def across(point):   # metres left of the torso's heading
    return (base_rot.T @ (point - base_pos))[1]

  root = positions[initializer.root_part]
  placed = {i: across(part_geometry.assembled_pose(
      env.physics, env.task.furniture, initializer.root_part, i)[0]) - across(root)
            for i in initializer.racked_parts}
  middle = 0.25 * max(abs(y) for y in placed.values())
  sides = []
  for group, rack in zip(groups, initializer.fixtures):
    side = np.sign(across(env.physics.bind(rack.mjcf_model.worldbody).xpos))
    assert all(np.sign(across(positions[i])) == side for i in group)
    # Each panel's place in the furniture is on its rack's side, or across the middle.
    assert all(placed[i] * side >= -middle for i in group)
    sides.append(side)
  assert sorted(sides) == [-1, 1]
  # A single arm keeps one rack.
  assert len(_env(furniture, robot="sawyer").task.initializer.fixtures) == 1


def test_a_round_seat_standing_in_the_rack_is_taken_across_its_thickness():
  assert gripper_fit.grasp_problems(_env("stool_pedestal_birch_bar")) == []


def test_panda_expert_takes_box_walls_from_the_rack_and_assembles_the_box():
  env = ikea_suite.load("box_open_small_white", "panda", scale=0.5, seed=1)
  helpers.run_expert(env)
  assert env.task.state.complete   # four walls joined through the action vector


def test_the_rack_stands_on_the_work_table_when_there_is_one():
  env = ikea_suite.load("box_open_small_white", "panda", scale=0.5, seed=2, arena="work_table")
  env.reset()
  rack_pos = _rack_body(env).xpos
  support = env.task.arena.support
  assert rack_pos[2] == pytest.approx(support.height)
  assert support.contains(rack_pos[:2], np.linalg.norm(env.task.initializer.fixtures[0].half_size))
  positions, _ = env.task.furniture.part_poses(env.physics)
  assert (positions[env.task.initializer.racked_parts, 2] > support.height + panel_rack.PLATE).all()


def _pair_between(env, part_a, part_b):
  table = env.task.furniture.connectors
  names = [p.name for p in env.task.furniture.spec.parts]
  a, b = names.index(part_a), names.index(part_b)
  for pair in range(table.num_pairs):
    if {int(table.part[table.pair_a[pair]]), int(table.part[table.pair_b[pair]])} == {a, b}:
      return pair, b


def test_a_bench_end_mated_the_wrong_way_round_is_off_design():
  # Both twists attach an end to the seat, but one turns its stretcher slot outwards.
  env = _env("bench_plank_pine")
  pair, end = _pair_between(env, "seat", "end0")
  off = []
  for twist in (0.0, np.pi):
    pos, rot, _ = part_geometry.mated_part_pose(env.physics, env.task.furniture, pair, end, twist)
    off.append(mating.off_design(env, end, pos, rot, pair))
  assert min(off) < 1e-6
  assert max(off) > env.task.thresholds.distance   # 15 mm: the far face of a 15 mm end


def test_a_stretcher_between_the_standing_ends_goes_in_from_above():
  env = ikea_suite.load("bench_plank_pine", "panda", scale=0.5, seed=1)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  while len(env.task.state.connections) < 2 and not timestep.last():   # both ends on
    timestep = env.step(expert(timestep))
  pair, stretcher = _pair_between(env, "end0", "stretcher")
  _, _, alone = part_geometry.mated_part_pose(env.physics, env.task.furniture, pair, stretcher, 0.0)
  _, _, side = mating.mate_pose(env, pair, stretcher, 0.0)
  assert abs(alone[2]) < 0.1   # along its own axis: through the far end
  np.testing.assert_allclose(side, [0.0, 0.0, 1.0])


def test_panda_expert_assembles_a_plank_bench_from_the_rack():
  env = ikea_suite.load("bench_plank_white_short", "panda", scale=0.5, seed=0)
  assert _racked_names(env) == ["end0", "end1", "stretcher"]
  helpers.run_expert(env)
  assert env.task.state.complete


def test_jaco_keeps_squeezing_a_wall_it_holds_by_the_edge():
  # Its usual hold, 0.05 rad short of closed (for 18 mm legs), opened its fingers off a
  # 6 mm wall as the lift began, and the wall fell back into its slot.
  env = ikea_suite.load("box_open_small_white", "jaco", scale=0.5, seed=0)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  grip = []
  while expert.phase != single_arm.Phase.ALIGN and not timestep.last():
    action = expert(timestep)
    if expert.phase == single_arm.Phase.LIFT:
      grip.append(action[env.task.robot.actions_per_arm - 1])
    timestep = env.step(action)
  assert grip and min(grip) == 1.0
  part = expert.job[1]
  assert expert._holding(part)
  position, _ = env.task.furniture.part_poses(env.physics)
  assert position[part][2] > 0.08   # lifted out of the rack


def test_jaco_carries_a_far_wall_as_high_as_it_reaches_and_completes_the_box():
  # Half a metre over the table the far wall's goal lay 0.77 m out, beyond the Jaco's
  # reach: the carry stalled there, the wall was put back, and time ran out.
  env = ikea_suite.load("box_open_shoe_dark", "jaco", scale=0.5, seed=0)
  robot = env.task.robot
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  lowered = []
  route = expert._clearance
  original = route.reachable_carry

  def watched(goal, rot, top, floor):
    height = original(goal, rot, top, floor)
    lowered.append((robot.reach_check(env.physics, 0, np.array([*goal[:2], top]), rot)[0],
                    robot.reach_check(env.physics, 0, np.array([*goal[:2], height]), rot)[0],
                    height - top, height - floor))
    return height

  route.reachable_carry = watched
  while not timestep.last() and not env.task.state.complete:
    timestep = env.step(expert(timestep))
  assert env.task.state.complete
  assert lowered
  for miss_high, miss_lowered, drop, above_floor in lowered:
    assert miss_high > 0.01 and miss_lowered < 0.01 and drop < 0   # reached, lower down
    assert above_floor >= 0.0   # the held wall still passes clear over the box


def test_panda_stands_both_trestles_before_the_stretcher_and_assembles_the_desk():
  # The stretcher, joined to the first trestle before the second stood, left the second
  # to go in over it: held by its foot, it struck the first and was dropped.
  env = ikea_suite.load("desk_trestle_w100_birch", "panda", scale=0.5, seed=0)
  names = [part.name for part in env.task.furniture.spec.parts]
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  order, joined = [], 0
  while not timestep.last() and not env.task.state.complete:
    timestep = env.step(expert(timestep))
    if len(env.task.state.connections) > joined:
      joined = len(env.task.state.connections)
      order.append(names[expert.job[1]])
  assert env.task.state.complete
  assert order[-1] == "stretcher" and sorted(order[:2]) == ["trestle0", "trestle1"]


def test_a_raised_carry_out_of_reach_goes_back_to_the_usual_height_and_the_desk_completes():
  # The second trestle, held by its foot, is carried high enough to clear the first one
  # standing; where that height is out of the Panda's reach it is carried at the usual
  # height (its path need not cross the first trestle), instead of stalling, being put
  # back and taken again until time ran out.
  env = ikea_suite.load("desk_trestle_w120_white", "panda", scale=0.5, seed=0)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  usual = env.task.arena.support.height + 0.5   # ArmAssemblyController's default carry
  heights = []
  while not timestep.last() and not env.task.state.complete:
    timestep = env.step(expert(timestep))
    top = expert._carry_height.top   # chosen at the first step of each carry
    if expert.phase == single_arm.Phase.ALIGN and top is not None:
      heights.append(top)
  assert env.task.state.complete
  raised = [i for i, h in enumerate(heights) if h > usual + 0.01]
  assert raised and any(abs(h - usual) < 1e-9 for h in heights[raised[0]:])


def _first_rack_exit(furniture):
  """(env, expert, part, pair, slide) for the panda expert's first job on `furniture`, as
  its lift would judge it: the tool at the grasp, every other panel still racked."""
  env = ikea_suite.load(furniture, "panda", scale=0.5, seed=1000)
  expert = experts.make_expert(env, require_supported=False)
  timestep = env.reset()
  expert.reset()
  expert(timestep)   # chooses the first part and its grasp
  pair, part = expert.job
  point, rot = expert._grasp_pose(part)
  slide = expert._clearance.rack_exit(part, pair, point, rot @ expert.closing_local(),
                                      expert._carry_height.nominal)
  return env, expert, part, pair, point, rot, slide


def test_a_panel_hanging_below_its_neighbours_tops_slides_out_of_the_rack_along_its_plane():
  # A dresser's panels stand 0.38 m tall in the rack (scale 0.5): held by the top edge,
  # one hangs below its neighbours' tops even at the carry's height, and carried round
  # the base along the row of slots it was swept into them and fell out of the fingers.
  env, expert, part, pair, point, rot, slide = _first_rack_exit("dresser_chest_three_white")
  assert slide is not None
  closing = rot @ expert.closing_local()
  assert abs(slide[2]) < 1e-9 and abs(slide @ closing) < 1e-6   # in the panel's plane
  base = env.task.robot.base_pose[0]
  assert slide[:2] @ (base - point)[:2] > 0.0   # towards the base
  furniture, table = env.task.furniture, env.task.furniture.connectors
  positions, rotations = furniture.part_poses(env.physics)
  held = part_geometry.part_corners(furniture, part, positions[part] + slide, rotations[part])
  along = slide / np.linalg.norm(slide)
  ends = table.pair_a[pair], table.pair_b[pair]
  mate = table.world_frames(positions, rotations)[0][ends[1] if table.part[ends[0]] == part
                                                      else ends[0]]
  rack = next(g for g in env.task.initializer.rack_groups if part in g)
  between = []   # the tall neighbours on its mate's side, along the row of slots
  for other in set(rack) - {part}:
    corners = part_geometry.part_corners(furniture, other, positions[other], rotations[other])
    if ((corners.mean(0) - held.mean(0)) @ closing * ((mate - held.mean(0)) @ closing) > 0.0
        and corners[:, 2].max() > held[:, 2].min() + 0.1):
      between.append(corners)
  assert between
  for corners in between:   # slid past them
    assert (held @ along).min() >= (corners @ along).max() + 0.02
  # The carry keeps out of that row: a waypoint back over one of them is held at the
  # slide's end, for this part only.
  route = expert._clearance
  over = np.array([*between[0].mean(0)[:2], point[2]])
  assert route.outside_rack(over, part) @ along == pytest.approx((point + slide) @ along)
  assert np.array_equal(route.outside_rack(over, part + 1), over)


def test_box_walls_low_enough_to_pass_over_their_neighbours_lift_straight_out():
  *_, slide = _first_rack_exit("box_open_small_white")
  assert slide is None
