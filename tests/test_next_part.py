"""The single-arm expert's precedence rule (experts/next_part.py): a part that would stand
in the way of another part coming in waits until that part is in. Planning checks on the
assembled poses at reset; no episode runs."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import geometry
from ikea_suite.experts import next_part
from ikea_suite.experts import part_geometry
from ikea_suite.experts import top_down_grasp


def _reset(furniture):
  env = ikea_suite.load(furniture, "panda", seed=1000, scale=0.5)
  env.reset()
  return env


def _hand(env):
  """The Panda's reach in from a held edge (its flat-panel grip depth)."""
  return top_down_grasp.TopDownGrasp(env, 0, 0.0, None).flat_grip_depth()


def _assembled_connectors(env):
  """World positions of every connector with its part in its assembled place, laid out
  from the root as it lies."""
  task, table = env.task, env.task.furniture.connectors
  parts = task.furniture.spec.parts
  rotation, translation = part_geometry.design_to_world(env.physics, task.furniture,
                                                        task.root_part)
  return np.array([rotation @ (parts[p].rot @ local + parts[p].pos) + translation
                   for p, local in zip(table.part, table.local_pos)])


def _landing_on(env, moving, fixed_parts):
  """Where `moving` lands: the assembled connectors of `fixed_parts` its own connectors
  meet in the design."""
  table = env.task.furniture.connectors
  where = _assembled_connectors(env)
  points = []
  for a, b in zip(table.pair_a, table.pair_b):
    for fixed, loose in ((a, b), (b, a)):
      if (table.part[loose] == moving and table.part[fixed] in fixed_parts
          and np.linalg.norm(where[fixed] - where[loose]) < 1e-3):
        points.append(where[fixed])
  return np.array(points)


def _index(env, name):
  return [p.name for p in env.task.furniture.spec.parts].index(name)


@pytest.fixture(scope="module")
def cabinet():
  return _reset("cabinet_doors_w40_birch")


def test_a_door_over_the_far_sides_edge_waits_for_the_far_side(cabinet):
  # The carcass is built on its root side, lying flat; the door hinges to it and stands
  # 7.5 mm (scale 0.5) above the far side's mates, 1.5 mm in front of its edge, where the
  # hand holding that edge comes down. The far side lands on the shelves, back and
  # plinth, the door on the root's hinge slot.
  env = cabinet
  root, door, far = env.task.root_part, _index(env, "door0"), _index(env, "side1")
  carcass = [_index(env, n) for n in ("shelf0", "shelf1", "shelf2", "back", "plinth")]
  jobs = {door: _landing_on(env, door, [root]), far: _landing_on(env, far, carcass)}
  assert jobs[door].size and jobs[far].size
  assert next_part.must_wait(env.task, env.physics, jobs, _hand(env)) == {door}
  # The door stands beside the far side, not over its mates: only the hand meets it.
  assert next_part.must_wait(env.task, env.physics, jobs, 0.0) == set()


def test_the_part_landing_higher_never_waits(cabinet):
  # The far side stands over the door's hinge slot (the root's front edge) but lands
  # higher: the rule orders by landing height, so it never waits for the door.
  env = cabinet
  root, door, far = env.task.root_part, _index(env, "door0"), _index(env, "side1")
  hinge = _landing_on(env, door, [root])
  assert next_part.stands_over(env.task, env.physics, far, hinge[0], _hand(env))
  carcass = [_index(env, n) for n in ("shelf0", "shelf1", "shelf2", "back", "plinth")]
  jobs = {door: hinge, far: _landing_on(env, far, carcass)}
  assert far not in next_part.must_wait(env.task, env.physics, jobs, 1.0)


def test_shelves_ending_under_the_far_sides_mates_leave_its_way_clear():
  # A bookcase: the shelves, back and plinth end 1.5 mm under the far side's mates, and
  # nothing waits, whatever the hand's reach.
  env = _reset("bookcase_shelf_unit_billy")
  root = env.task.root_part
  names = [p.name for p in env.task.furniture.spec.parts]
  far = _index(env, "side1")
  standing = [i for i, n in enumerate(names) if i not in (root, far)]
  jobs = {p: _landing_on(env, p, [root]) for p in standing}
  jobs[far] = _landing_on(env, far, standing)
  assert all(points.size for points in jobs.values())
  assert next_part.must_wait(env.task, env.physics, jobs, _hand(env)) == set()
  assert not any(next_part.stands_over(env.task, env.physics, p, point, _hand(env))
                 for p in standing for point in jobs[far])


def test_the_next_job_passes_over_a_waiting_part():
  # The carcass stood in its assembled place on the root (set there and recorded as
  # joined; nothing steps): the door's mate is on the root and goes first without the
  # rule; with it the far side goes first.
  env = _reset("cabinet_doors_w40_birch")
  task, physics = env.task, env.physics
  root, door, far = task.root_part, _index(env, "door0"), _index(env, "side1")
  table, where = task.furniture.connectors, _assembled_connectors(env)
  for name in ("shelf0", "shelf1", "shelf2", "back", "plinth"):
    part = _index(env, name)
    pos, rot = part_geometry.assembled_pose(physics, task.furniture, root, part)
    task.furniture.parts[part].set_pose(physics, position=pos,
                                        quaternion=geometry.mat_to_quat(rot))
    pair = min((k for k in range(len(table.pair_a))
                if {table.part[table.pair_a[k]], table.part[table.pair_b[k]]} == {root, part}),
               key=lambda k: np.linalg.norm(where[table.pair_a[k]] - where[table.pair_b[k]]))
    a, b = table.pair_a[pair], table.pair_b[pair]
    task.state.connect(table.part[a], table.part[b], a, b)
  physics.forward()
  base, _ = task.robot.base_pose
  assert next_part.nearest_open_job(task, physics, base)[1] == door
  assert next_part.nearest_open_job(task, physics, base, hand=_hand(env))[1] == far
