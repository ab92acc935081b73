"""Grippers carry the manufacturers' figures and hold real-mass parts by friction alone.

Each hold test stands a part of its catalog mass (never lightened) in front
of the arm, moves the other parts out of the way (test set-up), then acts
only through the action vector: down to the part, close, lift, and for 3 s
carry it round a circle while turning the wrist. The part may slip in the
fingers by less than 5 mm, and falls when the gripper opens.
"""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import single_arm
from ikea_suite.experts import top_down_grasp
from ikea_suite.robots import grippers
from ikea_suite.robots import jaco
from tests import helpers


# (sheet, force N, stroke m): the published figures the sheets must carry.
_FIGURES = [("panda_gripper", 70.0, 0.08), ("rethink_gripper", 22.0, 0.0647),
            ("kinova_hand", 25.0, 0.086)]


@pytest.mark.parametrize("sheet,force,stroke", _FIGURES)
def test_grip_figures_have_sources(sheet, force, stroke):
  facts = grippers.grip_facts(sheet)
  assert facts.force == force and facts.stroke == pytest.approx(stroke)
  assert facts.peak_force >= facts.force
  for figure in ("force_continuous_n", "stroke_m", "finger_friction"):
    assert len(facts.sources[figure]) > 20   # a written source, not a placeholder


@pytest.mark.parametrize("robot,sheet", [("sawyer", "rethink_gripper"), ("panda", "panda_gripper"),
                                         ("baxter", "rethink_gripper")])
def test_finger_actuators_are_limited_to_the_published_grasp_force(robot, sheet):
  env = ikea_suite.load("table_four_leg_lack", robot)
  physics, arm_robot = env.physics, env.task.robot
  for arm in range(arm_robot.num_arms):
    limits = physics.model.actuator_forcerange[arm_robot.finger_actuator_ids[arm]]
    np.testing.assert_allclose(np.abs(limits), grippers.grip_facts(sheet).force)


def _stand_part(env, part, pose_rot, xy):
  """Test set-up: `part` stands at `xy` turned by `pose_rot`; every other part is moved away."""
  physics, furniture = env.physics, env.task.furniture
  for i, other in enumerate(furniture.parts):
    if i != part:
      other.set_pose(physics, position=np.array([3.0 + i, 3.0, 0.2]))
  lo, hi = furniture.spec.parts[part].bounds
  corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                      for z in (lo[2], hi[2])]) @ pose_rot.T
  furniture.parts[part].set_pose(
      physics, position=np.array([*xy, -corners[:, 2].min() + 1e-3]),
      quaternion=geometry.mat_to_quat(pose_rot))
  physics.forward()
  return corners[:, 2].max() - corners[:, 2].min()


def _drive(env, arm, goal_pos, goal_rot, grip, steps, tolerance=0.004, gain=1.0):
  robot, physics = env.task.robot, env.physics
  action = np.zeros(env.action_spec().shape)
  servo = arm_motion.PoseServo()
  for _ in range(steps):
    action[:6] = servo(robot, physics, arm, goal_pos, goal_rot, gain=gain)
    action[6] = grip
    env.step(action)
    if arm_motion.pose_error(robot, physics, arm, goal_pos, goal_rot)[0] < tolerance:
      return True
  return False


# Where the part lies from the robot's base (m, base frame axes): 0.6 m straight ahead,
# but the Baxter's is in front of its right arm, which grips it. From straight ahead of the
# torso the circle brought the stool leg's end against the torso (24 N), which pried it
# 9.2 mm round in the fingers (the slip once recorded as the Baxter's grip); there it held
# the leg to 2.6 mm.
_LIES_AT = {"baxter": (0.75, -0.2)}


def _hold_test(robot_name, furniture_name, part_name, standing, scale=1.0):
  env = ikea_suite.load(furniture_name, robot_name, seed=0, scale=scale)
  env.reset()
  physics, robot, furniture = env.physics, env.task.robot, env.task.furniture
  part = furniture.spec.part_index(part_name)
  bounds = furniture.spec.parts[part].bounds
  thin = int(np.argmin(bounds[1] - bounds[0]))
  base_pos, base_rot = robot.base_pose
  xy = base_pos[:2] + (base_rot[:2, :2] @ np.array(_LIES_AT.get(robot_name, (0.6, 0.0))))
  # Part frame -> world: the long axis along world x; standing parts put their
  # thin axis along world y (gripped across it), lying parts keep it vertical.
  axes = np.argsort(bounds[1] - bounds[0])[::-1]
  rot = np.zeros((3, 3))
  if standing:
    rot[0, axes[0]], rot[2, axes[1]], rot[1, thin] = 1.0, 1.0, 1.0
  else:
    rot[0, axes[0]], rot[1, axes[1]], rot[2, thin] = 1.0, 1.0, 1.0
  if np.linalg.det(rot) < 0:
    rot[1] *= -1
  height = _stand_part(env, part, rot, xy)
  mass = physics.model.body_mass[furniture.body_ids[part]]
  assert mass == pytest.approx(furniture.spec.parts[part].mass, rel=1e-6)   # the catalog mass
  for _ in range(10):   # let it settle
    env.step(np.zeros(env.action_spec().shape))
  part_pos = physics.data.xpos[furniture.body_ids[part]].copy()
  # Fingers close along world y, across the part's thin side (standing) or its width (lying).
  controller = single_arm.ArmAssemblyController(env)
  _, home_rot = robot.tcp_pose(physics)
  candidates = [arm_motion.tool_rotation(np.array([0.0, 0.0, -1.0]), closing,
                                             controller.closing_local())
                for closing in (np.array([0.0, 1.0, 0.0]), np.array([0.0, -1.0, 0.0]))]
  tool_rot = min(candidates, key=lambda r: np.linalg.norm(geometry.mat_to_axis_angle(r @ home_rot.T)))
  grasp = np.array([*part_pos[:2], part_pos[2] + height / 2 - min(0.03, height / 2)])
  assert _drive(env, 0, grasp + [0, 0, 0.12], tool_rot, -1.0, 200, tolerance=0.01)
  # Down slowly, as the expert does: a fast descent swings the open fingers sideways
  # by centimetres, onto the part.
  assert _drive(env, 0, grasp, tool_rot, -1.0, 200, gain=top_down_grasp.DESCEND_GAIN)
  action = np.zeros(env.action_spec().shape)
  servo = arm_motion.PoseServo()
  close_time = robot.arms[0].gripper.close_time   # the Jaco's hand takes 1.2 s
  for _ in range(max(10, int(np.ceil(close_time / env.control_timestep())))):   # close on it
    action[:6] = servo(robot, physics, 0, grasp, tool_rot)
    action[6] = 1.0
    env.step(action)
  assert not helpers.welds_on(physics).any(), "no weld may hold the part"

  def part_in_tool():
    pos = physics.data.xpos[furniture.body_ids[part]]
    tcp_pos, tcp_rot = robot.tcp_pose(physics)
    return tcp_rot.T @ (pos - tcp_pos)

  _drive(env, 0, grasp + [0, 0, 0.2], tool_rot, 1.0, 60, tolerance=0.01)
  start = part_in_tool()
  lifted = physics.data.xpos[furniture.body_ids[part]][2]
  assert lifted > part_pos[2] + 0.1
  steps = int(round(3.0 / env.control_timestep()))
  tcp_path, slip = [], []
  for k in range(steps):   # 3 s: a horizontal circle while the wrist turns back and forth
    phase = 2 * np.pi * k / steps
    action = np.zeros(env.action_spec().shape)
    action[:2] = 0.5 * np.array([-np.sin(phase), np.cos(phase)])
    action[5] = 0.6 * np.cos(phase)
    action[6] = 1.0
    env.step(action)
    tcp_path.append(robot.tcp_pose(physics)[0])
    slip.append(np.linalg.norm(part_in_tool() - start))
  assert np.ptp(np.array(tcp_path)[:, :2], axis=0).max() > 0.1   # the arm really carried it
  assert max(slip) < 0.005, f"slipped {1000 * max(slip):.1f} mm holding {mass:.2f} kg"
  assert not helpers.welds_on(physics).any()
  action = np.zeros(env.action_spec().shape)
  action[6] = -1.0   # open: friction was all that held it
  for _ in range(25):
    env.step(action)
  assert physics.data.xpos[furniture.body_ids[part]][2] < lifted - 0.1
  return mass, max(slip)


_LEG = ("table_four_leg_lack", "leg0", False)                 # 0.19 kg, 5 cm square, lying
_SHELF = ("bookcase_shelf_unit_billy", "shelf0", True)         # 1.5 kg, 18 mm panel, on edge
# The Sawyer's and the Baxter's fingers sit one slot in (grippers.RETHINK_SLOT_1) and open
# to 60 mm, too little room for the 50 mm Lack leg: they take a 35 mm stool leg, and as
# their panel the bench end they assemble, at their work scale (below). Not held by the
# Sawyer (measured):
# the full-size 1.5 kg shelf swings about the finger
# axis in its 22 N grasp, 5.8 mm at 0.75 m (at 0.6 m the shelf's end strikes the arm's
# first link), and a 12 mm box wall standing on edge is pushed over by the first finger.
_STOOL_LEG = ("stool_square_pine", "leg0", False)              # 0.26 kg, 35 mm square, lying
_CASES = [("sawyer", _STOOL_LEG), ("panda", _LEG), ("panda", _SHELF), ("jaco", _LEG),
          ("baxter", _STOOL_LEG), ("baxter", _SHELF)]


@pytest.mark.parametrize("robot,part", _CASES, ids=[f"{r}-{p[1]}" for r, p in _CASES])
def test_arm_holds_a_real_mass_part_while_carrying_and_turning_it(robot, part):
  mass, slip = _hold_test(robot, *part)
  assert mass > 0.15 and slip < 0.005


@pytest.mark.parametrize("robot", ["sawyer", "baxter"])
def test_rethink_fingers_one_slot_in_hold_a_work_scale_panel_by_its_edge(robot):
  # A plank bench's end at the work scale (0.5: 15 x 150 x 210 mm, 0.24 kg, its scaled
  # catalog mass), standing on edge, the way the expert takes it from the rack. Measured
  # 1.3 mm (Sawyer).
  mass, slip = _hold_test(robot, "bench_plank_pine", "end0", True, scale=0.5)
  assert mass == pytest.approx(1.89 / 8, rel=0.05) and slip < 0.005


def test_jaco_holds_a_work_scale_leg_between_thumb_and_fingers():
  # The Lack leg at the Jaco's work scale (0.5: 25 mm square, 24 g, its scaled catalog
  # mass), the part the expert carries: before the pinch-depth TCP and the stiff finger
  # contacts, the fingertips struck the floor or sank into the light leg and lost it.
  # Measured 4.9 mm, close to the bound: the two fingers (1 N m each) back-drive the single
  # thumb (1 N m) and push the leg towards it over the first 1.5 s of the carry, until they
  # reach their closed limit. On a softer floor (MuJoCo's default impedance rather than
  # physics_settings.SUPPORT_SOLIMP) it is 5.3 mm.
  assert jaco.Jaco.CONFIG.WORK_SCALE == 0.5
  mass, slip = _hold_test("jaco", *_LEG, scale=0.5)
  assert mass == pytest.approx(0.19 / 8, rel=0.05) and slip < 0.005
