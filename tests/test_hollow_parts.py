"""Hollow parts (drawer boxes) and boards (plinths): how they lie for an arm, how a gripper
takes them, and the Panda putting both into a nightstand through the action vector."""

import pytest

import ikea_suite
from ikea_suite.experts import gripper_fit
from ikea_suite.experts import next_part
from ikea_suite.experts import part_geometry
from ikea_suite.experts import registry
from ikea_suite.experts import top_down_grasp
from ikea_suite.props import catalog
from ikea_suite.tasks import hollow_parts
from ikea_suite.tasks import panel_placement

NIGHTSTAND = "nightstand_drawer_white"


def _env(furniture=NIGHTSTAND, robot="panda", seed=1000):
  env = ikea_suite.load(furniture, robot, scale=0.5, seed=seed)
  env.reset()
  return env


def _index(env, name):
  return [p.name for p in env.task.furniture.spec.parts].index(name)


def test_drawer_boxes_are_hollow_and_panels_plinths_and_legs_are_not():
  spec = catalog.spec(NIGHTSTAND, 0.5)
  assert [p.name for p in spec.parts if hollow_parts.is_hollow(p)] == ["drawer0"]
  assert not any(hollow_parts.is_hollow(p) for p in catalog.spec("stool_round_frosta", 0.5).parts)


@pytest.mark.parametrize("furniture", [NIGHTSTAND, "dresser_chest_three_white"])
def test_a_drawer_lies_for_an_arm_as_it_stands_in_the_furniture_on_the_root(furniture):
  env = _env(furniture)
  furniture_, root = env.task.furniture, env.task.root_part
  for part in range(len(furniture_.parts)):
    if not hollow_parts.is_hollow(furniture_.spec.parts[part]):
      continue
    _, rot = part_geometry.part_pose(env.physics, furniture_, part)
    _, assembled = part_geometry.assembled_pose(env.physics, furniture_, root, part)
    # The same up to a turn about the vertical, and the few degrees the front's
    # overhang tips it by as it rests on the floor.
    assert rot[:, 0] @ assembled[:, 0] > 0.99 and abs(rot[2, 0]) > 0.99


def test_a_drawer_is_taken_across_its_front_by_the_top_edge_and_fits_the_gripper():
  env = _env()
  drawer = _index(env, "drawer0")
  grasp = top_down_grasp.TopDownGrasp(env, 0, env.task.arena.support.height,
                                      _route(env))
  assert grasp.by_top_edge(drawer) and not grasp.turns_flat(drawer)
  point, rot = grasp.pose(drawer, 1.0)
  pos, part_rot = part_geometry.part_pose(env.physics, env.task.furniture, drawer)
  local = part_rot.T @ (point - pos)
  assert local[1] == pytest.approx(-0.0905, abs=0.02)   # over the front (y -0.0905)
  closing = rot @ grasp.closing_local()
  assert abs(closing @ part_rot[:, 1]) > 0.99   # across the front's 8 mm thickness
  assert rot[2, 2] == pytest.approx(-1.0, abs=1e-6)   # tool down
  assert gripper_fit.grasp_width(env, drawer) == pytest.approx(0.008, abs=1e-4)
  assert gripper_fit.grasp_problems(env) == []


def _route(env):
  from ikea_suite.experts import clearance
  return clearance.AssemblyClearance(env, 0, env.task.arena.support.height)


def test_a_plinth_is_a_board_racked_as_it_stands_and_taken_by_its_top_end():
  env = _env()
  plinth = _index(env, "plinth")
  extents = env.task.furniture.spec.parts[plinth].bounds
  assert panel_placement.is_panel(extents[1] - extents[0])   # 8 x 18 x 206 mm: a board
  assert plinth in env.task.initializer.racked_parts
  _, rot = part_geometry.part_pose(env.physics, env.task.furniture, plinth)
  assert abs(rot[2, 0]) > 0.99   # its length upright, as in the furniture
  grasp = top_down_grasp.TopDownGrasp(env, 0, env.task.arena.support.height, _route(env))
  assert grasp.by_top_edge(plinth) and not grasp.turns_flat(plinth)


def test_panda_puts_the_drawer_and_plinth_in_and_assembles_the_nightstand():
  env = ikea_suite.load(NIGHTSTAND, "panda", scale=0.5, seed=1000)
  expert = registry.make_expert(env, require_supported=False)
  timestep = env.reset()
  expert.reset()
  while not timestep.last() and not env.task.state.complete:
    timestep = env.step(expert(timestep))
  assert env.task.state.complete   # the drawer by its front's top edge, the plinth racked


def test_the_far_side_covers_the_drawer_and_panels_wait_for_the_plinth():
  env = _env()
  task, physics = env.task, env.physics
  side1, drawer, shelf, plinth = (_index(env, n) for n in ("side1", "drawer0", "shelf0",
                                                            "plinth"))
  assert next_part.covers(task, physics, side1, drawer)
  assert not next_part.covers(task, physics, drawer, side1)
  assert not next_part.covers(task, physics, shelf, drawer)
  loose = list(task.initializer.racked_parts)
  assert next_part.waits_for_a_board(task, shelf, loose)
  assert not next_part.waits_for_a_board(task, plinth, loose)
  assert not next_part.waits_for_a_board(task, shelf, [p for p in loose if p != plinth])
