"""Connecting parts: the alignment check in before_step, snapping, welds, collision groups, rewards."""

import numpy as np
import pytest
from dm_control import composer

import ikea_suite
from ikea_suite import geometry
from ikea_suite.arenas import floor
from ikea_suite.props import catalog
from ikea_suite.props import furniture as furniture_lib
from ikea_suite.robots import cursor
from ikea_suite.tasks import assembly
from tests import helpers


TABLE = "table_four_leg_lack"


@pytest.fixture
def env():
  environment = ikea_suite.load(TABLE, seed=0)
  environment.reset()
  return environment


def top_and_legs(env):
  return helpers.part_index(env, "top"), [helpers.part_index(env, f"leg{i}") for i in range(4)]


def connector_gap(env, pair_parts):
  """Smallest distance between used connector pairs' frames (0 when snapped exactly)."""
  scores = env.task.alignment(env.physics)
  table = env.task.furniture.connectors
  used = [i for i in range(table.num_pairs)
          if env.task.state.connector_used[table.pair_a[i]] and env.task.state.connector_used[table.pair_b[i]]
          and {table.part[table.pair_a[i]], table.part[table.pair_b[i]]} == set(pair_parts)]
  return min(scores.distance[used])


def test_aligned_pair_connects_welds_and_rewards(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]])
  timestep = env.step(helpers.connect_action(env))
  assert timestep.reward == 1.0
  assert env.task.state.same_group(top, legs[0])
  assert timestep.observation["task/connections"][top, legs[0]] == 1.0
  assert sum(timestep.observation["task/connectors_used"]) == 2
  assert env.task.welded_part_pairs(env.physics) == [tuple(sorted((top, legs[0])))]
  # Joined parts stop colliding with each other, not with the rest.
  physics = env.physics
  assert not helpers.geoms_collide(physics, helpers.first_geom(env, top), helpers.first_geom(env, legs[0]))
  assert helpers.geoms_collide(physics, helpers.first_geom(env, top), helpers.first_geom(env, legs[1]))
  floor = physics.bind(env.task.arena.floor).element_id
  assert helpers.geoms_collide(physics, helpers.first_geom(env, legs[0]), floor)


def test_welded_parts_move_as_one(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]])
  env.step(helpers.connect_action(env))
  positions, rotations = env.task.furniture.part_poses(env.physics)
  before = rotations[top].T @ (positions[legs[0]] - positions[top])
  for _ in range(40):   # two seconds of falling and landing
    env.step(helpers.idle_action(env))
  positions, rotations = env.task.furniture.part_poses(env.physics)
  after = rotations[top].T @ (positions[legs[0]] - positions[top])
  assert np.linalg.norm(after - before) < 2e-3
  assert positions[top][2] < 0.5   # it did fall


def test_no_connection_without_connect_action(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]])
  timestep = env.step(helpers.idle_action(env))
  assert timestep.reward == 0.0 and not env.task.state.connections


def test_misaligned_pair_does_not_connect(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]], extra_pos={legs[0]: np.array([0.05, 0, 0])})
  timestep = env.step(helpers.connect_action(env))
  assert timestep.reward == 0.0 and not env.task.state.connections


@pytest.mark.parametrize("twist_deg, connects", [(90, True), (180, True), (45, False)])
def test_square_leg_twists(env, twist_deg, connects):
  top, legs = top_and_legs(env)
  turn = geometry.rot_z(np.radians(twist_deg))
  helpers.place_assembled(env, [top, legs[0]], extra_rot={legs[0]: turn})
  # Rotating the leg about world z moves it off its corner; turn about its own axis instead.
  spec = env.task.furniture.spec.parts[legs[0]]
  env.task.furniture.parts[legs[0]].set_pose(
      env.physics, position=spec.pos + helpers.LIFT, quaternion=geometry.mat_to_quat(turn @ spec.rot))
  env.physics.forward()
  env.step(helpers.connect_action(env))
  assert bool(env.task.state.connections) is connects


def test_near_alignment_snaps_exactly(env):
  top, legs = top_and_legs(env)
  tilt = geometry.axis_angle_to_mat(np.radians([3.0, -2.0, 4.0]))
  helpers.place_assembled(env, [top, legs[0]], extra_rot={legs[0]: tilt},
                          extra_pos={legs[0]: np.array([0.006, -0.004, 0.003])})
  env.step(helpers.connect_action(env))
  assert env.task.state.connections
  # The weld holds the snapped relative pose: the legs' connector sits on the slot.
  assert connector_gap(env, (top, legs[0])) < 2e-3


def test_identical_legs_are_interchangeable(env):
  top, legs = top_and_legs(env)
  spec = env.task.furniture.spec.parts
  # Put leg1 where leg0 belongs.
  env.task.furniture.parts[legs[1]].set_pose(
      env.physics, position=spec[legs[0]].pos + helpers.LIFT, quaternion=[1, 0, 0, 0])
  helpers.place_assembled(env, [top])
  env.step(helpers.connect_action(env))
  assert env.task.state.same_group(top, legs[1])


def test_a_connector_is_used_once(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]])
  env.step(helpers.connect_action(env))
  # leg1 into the slot leg0 already uses: nothing may connect.
  spec = env.task.furniture.spec.parts
  positions, rotations = env.task.furniture.part_poses(env.physics)
  slot_offset = spec[legs[0]].pos - spec[top].pos
  env.task.furniture.parts[legs[1]].set_pose(
      env.physics, position=positions[top] + rotations[top] @ slot_offset,
      quaternion=geometry.mat_to_quat(rotations[top]))
  env.physics.forward()
  timestep = env.step(helpers.connect_action(env))
  assert timestep.reward == 0.0 and len(env.task.state.connections) == 1


def test_completion_pays_bonus_and_ends_episode(env):
  parts = range(len(env.task.furniture.parts))
  rewards = []
  for _ in parts:
    helpers.place_assembled(env, parts)
    timestep = env.step(helpers.connect_action(env))
    rewards.append(timestep.reward)
    if timestep.last():
      break
  assert env.task.state.complete
  assert timestep.last() and timestep.discount == 0.0
  assert rewards == [1.0, 1.0, 1.0, 11.0]
  assert (timestep.observation["task/next_pair"] == -1).all()


def test_next_pair_suggests_joining_the_root_group(env):
  observation = env.step(helpers.idle_action(env)).observation
  moving, target = observation["task/next_pair"].astype(int)
  assert target == env.task.root_part == helpers.part_index(env, "top")
  assert env.task.furniture.spec.parts[moving].name.startswith("leg")


def test_physics_blow_up_ends_episode_without_raising(env):
  env.physics.data.qvel[:] = 1e30
  timestep = env.step(helpers.idle_action(env))
  assert timestep.last() and timestep.discount == 0.0 and timestep.reward == 0.0
  assert env.step(helpers.idle_action(env)).first()   # the next step resets


def test_time_limit_truncates_with_discount_one():
  env = ikea_suite.load(TABLE, seed=0, time_limit=0.5)
  env.reset()
  steps = 0
  while True:
    timestep = env.step(helpers.idle_action(env))
    steps += 1
    if timestep.last():
      break
  assert steps == 10 and timestep.discount == 1.0


def test_a_connect_that_would_push_a_part_into_the_floor_is_refused(env):
  top, legs = top_and_legs(env)
  physics, task = env.physics, env.task
  helpers.place_assembled(env, [top, legs[1]])
  assert task.try_connect(physics)
  # The top and leg 1 sit 1 cm lower than standing on the floor; leg 0 hovers 1.5 cm
  # above its slot, its foot 5 mm above the floor: snapping it home would sink it 10 mm.
  lowered = np.array([0.0, 0.0, -0.010])
  helpers.place_assembled(env, [top, legs[1]], offset=lowered)
  helpers.place_assembled(env, [legs[0]], offset=lowered + [0.0, 0.0, 0.015])
  before = physics.data.qpos.copy()
  assert not task.try_connect(physics)
  assert not task.state.same_group(top, legs[0])
  np.testing.assert_array_equal(physics.data.qpos, before)   # nothing teleported
  (reason,) = task.blocked_connections
  assert "leg0" in reason and "into the floor" in reason and "10 mm" in reason
  # With the table standing on the floor instead, the same snap keeps clear of it.
  standing = np.array([0.0, 0.0, 0.001])
  helpers.place_assembled(env, [top, legs[1]], offset=standing)
  helpers.place_assembled(env, [legs[0]], offset=standing + [0.0, 0.0, 0.015])
  assert task.try_connect(physics) and task.state.same_group(top, legs[0])


def test_blocked_connections_are_reported_for_the_step_only(env):
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[1]])
  env.step(helpers.connect_action(env))
  lowered = np.array([0.0, 0.0, -0.010])
  helpers.place_assembled(env, [top, legs[1]], offset=lowered)
  helpers.place_assembled(env, [legs[0]], offset=lowered + [0.0, 0.0, 0.015])
  timestep = env.step(helpers.connect_action(env))
  assert timestep.reward == 0.0 and len(env.task.blocked_connections) == 1
  env.step(helpers.idle_action(env))
  assert env.task.blocked_connections == ()


def test_next_pair_follows_the_buildable_sequence_in_any_order():
  # The bookcase's sequence puts the shelves in before the closing side panel; table
  # order would suggest back, side and plinth first, which cannot be built.
  env = ikea_suite.load("bookcase_shelf_unit_w80_h106_white", seed=0)
  env.reset()
  task = env.task
  spec = task.furniture.spec
  order = [spec.parts[i].name for i in task.assembly_order]
  suggested = []
  for _ in spec.parts[1:]:
    moving, target = task.suggested_parts()
    assert task.state.same_group(target, task.root_part)
    suggested.append(spec.parts[moving].name)
    helpers.place_assembled(env, range(len(spec.parts)))
    pair = next(k for k in task.design_pairs
                if {task.furniture.connectors.part[task.furniture.connectors.pair_a[k]],
                    task.furniture.connectors.part[task.furniture.connectors.pair_b[k]]}
                == {moving, target})
    task.connect_in_place(env.physics, pair)
    if task.state.complete:
      break
  assert suggested == order[1:len(suggested) + 1]
  assert order.index("side1") > max(order.index("shelf0"), order.index("shelf1"))


def test_next_pair_adapts_when_parts_are_joined_out_of_order(env):
  top, _ = top_and_legs(env)
  task = env.task
  order = task.assembly_order
  last = order[-1]
  assert task.suggested_parts()[0] == order[1] != last
  helpers.place_assembled(env, [top, last])   # the order's last part joins first
  assert task.try_connect(env.physics)
  moving, target = task.suggested_parts()
  assert target in (top, last)
  assert moving == order[1]   # still the first part of the order not yet joined


def test_reset_restores_the_episode_without_recompiling(env):
  physics = env.physics
  model_ptr = physics.model.ptr
  contype = physics.model.geom_contype.copy()
  top, legs = top_and_legs(env)
  helpers.place_assembled(env, [top, legs[0]])
  env.step(helpers.connect_action(env))
  assert env.task.state.same_group(top, legs[0])
  assert not np.array_equal(physics.model.geom_contype, contype)
  env.reset()
  assert env.physics is physics and env.physics.model.ptr is model_ptr   # same compiled model
  np.testing.assert_array_equal(physics.model.geom_contype, contype)
  assert not helpers.welds_on(physics).any() and env.task.state.num_groups == len(env.task.furniture.parts)


def test_an_initializer_that_names_no_preassembled_pairs_is_refused():
  class Plain(composer.Initializer):   # poses parts but says nothing of preassembled pairs
    def __call__(self, physics, random_state):
      pass
  furniture = furniture_lib.Furniture(catalog.spec(TABLE))
  with pytest.raises(ikea_suite.IkeaSuiteError, match="PartInitializer"):
    assembly.Assembly(arena=floor.FloorArena(), furniture=furniture, robot=cursor.Cursor(),
                      initializer=Plain())
