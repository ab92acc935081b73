"""The Cursor agent: moving, rotating, holding parts through the same action interface."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite.experts import part_geometry
from tests import helpers


@pytest.fixture
def env():
  environment = ikea_suite.load("table_four_leg_lack", seed=3)
  environment.reset()
  return environment


def cursor_action(env, cursor, move=(0, 0, 0), rotate=(0, 0, 0), select=False):
  action = helpers.idle_action(env)
  base = 7 * cursor
  action[base:base + 3] = move
  action[base + 3:base + 6] = rotate
  action[base + 6] = 1.0 if select else -1.0
  return action


def fly_to(env, cursor, point, select=False, steps=200):
  robot = env.task.robot
  speed = robot.move_speed * env.control_timestep()
  for _ in range(steps):
    pos = robot.cursor_positions(env.physics)[cursor]
    if np.linalg.norm(point - pos) < 1e-3:
      return
    env.step(cursor_action(env, cursor, move=np.clip((point - pos) / speed, -1, 1), select=select))
  raise AssertionError("cursor did not arrive")


def test_action_spec_names_every_entry(env):
  spec = env.action_spec()
  names = spec.name.split("\t")
  assert spec.shape == (15,) and len(names) == 15
  assert names[:7] == ["cursor0_move_x", "cursor0_move_y", "cursor0_move_z", "cursor0_rotate_x",
                       "cursor0_rotate_y", "cursor0_rotate_z", "cursor0_select"]
  assert names[-1] == "connect" and (spec.minimum == -1).all() and (spec.maximum == 1).all()


def test_move_rate_and_clipping(env):
  robot = env.task.robot
  start = robot.cursor_positions(env.physics).copy()
  env.step(cursor_action(env, 0, move=(5.0, 0, -5.0)))   # clipped to 1 and -1
  moved = robot.cursor_positions(env.physics) - start
  step = robot.move_speed * env.control_timestep()
  np.testing.assert_allclose(moved[0], [step, 0, -step], atol=1e-9)
  np.testing.assert_allclose(moved[1], 0, atol=1e-12)


def test_rotation_rate(env):
  robot = env.task.robot
  env.step(cursor_action(env, 1, rotate=(0, 0, 1)))
  quat = robot.cursor_quaternions(env.physics)[1]
  angle = 2 * np.arccos(np.clip(quat[0], -1, 1))
  assert np.isclose(angle, robot.rotate_speed * env.control_timestep())


def test_grab_lift_carry_and_release(env):
  robot, physics, furniture = env.task.robot, env.physics, env.task.furniture
  top = helpers.part_index(env, "top")
  point = part_geometry.grasp_point(physics, furniture, top)
  fly_to(env, 0, point)
  env.step(cursor_action(env, 0, select=True))
  assert robot.held_parts[0] == top
  for _ in range(20):
    env.step(cursor_action(env, 0, move=(0, 0, 1), select=True))
  pos, _ = part_geometry.part_pose(physics, furniture, top)
  assert pos[2] > 0.4   # 20 steps x 2.5 cm, minus the grip's lag
  for _ in range(10):
    env.step(cursor_action(env, 0, rotate=(1, 0, 0), select=True))
  _, rot = part_geometry.part_pose(physics, furniture, top)
  tilt = np.degrees(np.arccos(rot[2, 2]))
  assert 30 < tilt < 60   # about 45 degrees commanded
  env.step(cursor_action(env, 0, select=False))
  assert robot.held_parts[0] == -1
  for _ in range(30):
    env.step(cursor_action(env, 0, select=False))
  assert part_geometry.part_pose(physics, furniture, top)[0][2] < 0.1   # it fell


def test_select_in_empty_space_holds_nothing(env):
  env.step(cursor_action(env, 0, select=True))
  assert env.task.robot.held_parts[0] == -1


def test_two_cursors_cannot_hold_one_assembly(env):
  robot, physics, furniture = env.task.robot, env.physics, env.task.furniture
  top, leg = helpers.part_index(env, "top"), helpers.part_index(env, "leg0")
  helpers.place_assembled(env, [top, leg], offset=np.zeros(3))
  env.step(helpers.connect_action(env))
  fly_to(env, 1, part_geometry.grasp_point(physics, furniture, leg))
  fly_to(env, 0, part_geometry.grasp_point(physics, furniture, top))
  env.step(cursor_action(env, 0, select=True))
  action = cursor_action(env, 1, select=True)
  action[6] = 1.0   # cursor 0 keeps holding
  env.step(action)
  assert robot.held_parts[0] == top and robot.held_parts[1] == -1


def test_cursor_observables(env):
  observation = env.step(helpers.idle_action(env)).observation
  assert observation["robot/tcp_positions"].shape == (2, 3)
  np.testing.assert_allclose(np.linalg.norm(observation["robot/tcp_quaternions"], axis=1), 1)
  assert (observation["robot/held_parts"] == -1).all()
