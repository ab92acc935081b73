"""Turning the assembly over: a chair's legs go into its upside-down seat, then an arm
rolls the chair onto its legs and its back goes in from above (oracle/turn_over.py)."""

import numpy as np

import ikea_suite
from ikea_suite import geometry
from ikea_suite import experts
from ikea_suite.oracle import arm_controller
from ikea_suite.oracle import arm_motion
from ikea_suite.oracle import mating
from ikea_suite.oracle import targets
from ikea_suite.oracle import turn_over
from ikea_suite.tasks import planner

CHAIR = "chair_back_pine_high"


def _env(seed=0):
  env = ikea_suite.load(CHAIR, "panda", scale=0.5, seed=seed)
  env.reset()
  return env


def _part(env, name):
  return [p.name for p in env.task.furniture.spec.parts].index(name)


def _connector(env, part_name):
  table = env.task.furniture.connectors
  return int(np.flatnonzero(table.part == _part(env, part_name))[0])


def test_only_the_back_waits_for_the_seat_to_be_turned_over():
  env = _env()
  task, physics = env.task, env.physics
  surface = task.arena.support.height
  assert task.furniture.spec.parts[task.root_part].name == "seat"
  table = task.furniture.connectors
  waiting = []
  for pair in range(len(table.pair_a)):
    a, b = table.pair_a[pair], table.pair_b[pair]
    moving = b if table.part[a] == task.root_part else a
    if turn_over.under_support(physics, task.furniture, pair, table.part[moving], surface):
      waiting.append(task.furniture.spec.parts[table.part[moving]].name)
  assert waiting == ["back"]
  assert [task.furniture.connectors.types[c] for c in turn_over.waiting(task, physics, surface)] == [
      "seat_back_slot"]


def test_the_back_stands_in_the_rack_the_way_up_it_goes_in_after_the_turn_over():
  env = _env()
  back = _part(env, "back")
  assert back in env.task.initializer.racked_parts
  positions, _ = env.task.furniture.part_poses(env.physics)
  cpos, _ = env.task.furniture.connectors.world_frames(*env.task.furniture.part_poses(env.physics))
  # Its bottom connector (where it meets the seat) is at its foot, not at its top edge.
  assert cpos[_connector(env, "back")][2] < positions[back][2] - 0.05


def test_panda_turns_the_chair_over_and_completes_it():
  env = ikea_suite.load(CHAIR, "panda", scale=0.5, seed=1)   # expert_sweep's seed 1
  expert = experts.make_expert(env)
  timestep, phases = env.reset(), set()
  expert.reset()
  seat = env.task.root_part
  while not timestep.last():
    timestep = env.step(expert(timestep))
    phases.add(expert.phase)
  assert env.task.state.complete
  assert arm_controller.Phase.TURN_OVER in phases
  _, rotations = env.task.furniture.part_poses(env.physics)
  assert rotations[seat][2, 2] > 0.99   # the seat lies right way up, on its legs


def test_a_part_put_back_from_the_assembly_is_lifted_off_it_first():
  # Dragged sideways off the seat, a chair's back knocked the turned chair over.
  env = _env(seed=1)
  expert = experts.make_expert(env)
  physics, furniture = env.physics, env.task.furniture
  leg = _part(env, "leg0")
  seat_pos, _ = targets.part_pose(physics, furniture, env.task.root_part)
  expert._job, expert._grasp = (0, leg), expert._grasp_pose(leg)
  lengths = []
  for on_seat in (False, True):
    if on_seat:   # lying across the upturned seat
      _, rot = targets.part_pose(physics, furniture, leg)
      furniture.set_part_pose(physics, leg, [seat_pos[0], seat_pos[1], seat_pos[2] + 0.03],
                              geometry.mat_to_quat(rot))
      for _ in range(200):
        physics.step()
    expert._put_back()
    lengths.append(len(expert._put_back_path))
  tcp, _ = env.task.robot.tcp_pose(physics, 0)
  assert lengths == [3, 4]
  np.testing.assert_allclose(expert._put_back_path[0], tcp + [0.0, 0.0, 0.05])


def _legs_joined(env, count):
  """Joins the first `count` legs to the upturned seat (connect_in_place); returns the
  seat's connector left open for the next leg, its world position."""
  task, physics = env.task, env.physics
  table = task.furniture.connectors
  joined, free = 0, None
  for pair in range(len(table.pair_a)):
    if not planner.open_pairs(table, task.state)[pair]:
      continue   # its leg or its slot is taken
    a, b = table.pair_a[pair], table.pair_b[pair]
    names = {task.furniture.spec.parts[table.part[c]].name for c in (a, b)}
    if "seat" not in names or not any(n.startswith("leg") for n in names):
      continue
    seat_side = a if table.part[a] == task.root_part else b
    if joined < count:
      leg = int(table.part[b if seat_side == a else a])
      pos, rot, _ = targets.mated_part_pose(physics, task.furniture, pair, leg, 0.0)
      task.furniture.set_part_pose(physics, leg, pos, geometry.mat_to_quat(rot))
      task.connect_in_place(physics, pair)
      joined += 1
    elif free is None:
      free = seat_side
  cpos, _ = table.world_frames(*task.furniture.part_poses(physics))
  return cpos[free]


def test_a_hand_reaching_in_across_the_standing_legs_is_in_their_way():
  # A Panda taking a chair's near corner with its tool pointing back at its base crossed
  # the seat, and its forearm pushed the far legs 0.4 m (tuning seed 2): plan_mating now
  # counts the whole hand, back to the wrist, against the parts already joined.
  env = _env()
  corner = _legs_joined(env, 3)
  seat, _ = targets.part_pose(env.physics, env.task.furniture, env.task.root_part)
  tool = corner + [0.0, 0.0, 0.1]   # about where the fourth leg is held, going in
  inward = np.array([*(seat[:2] - corner[:2]), 0.0]) / np.linalg.norm(seat[:2] - corner[:2])
  closing_local = experts.make_expert(env).closing_local()

  def pointing(axis):   # the fingers closing across a standing leg, horizontally
    return arm_motion.tool_rotation(axis, np.cross([0.0, 0.0, 1.0], axis), closing_local)

  across = mating.hand_in_the_way(env, 0, tool, pointing(-inward))
  outside = mating.hand_in_the_way(env, 0, tool, pointing(inward))
  down = mating.hand_in_the_way(env, 0, tool, geometry.HALF_TURN_X)
  assert across > 0.05   # the hand over the seat runs into the legs standing there
  assert outside == 0.0 and down == 0.0
