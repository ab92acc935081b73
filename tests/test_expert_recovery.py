"""How the arm expert recovers when a carry stalls: it notices, plans a joint-space path
to the mate, or else sets the part back down where it took it to take it with the other of
its two grasps."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import experts
from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import finger_room
from ikea_suite.experts import joint_planner
from ikea_suite.experts import mating
from ikea_suite.experts import part_geometry
from ikea_suite.experts import single_arm

Phase = single_arm.Phase


def test_progress_watch_stalls_only_after_a_window_without_gain():
  watch = arm_motion.ProgressWatch(window=5, min_gain=0.01)
  errors = [0.5, 0.4, 0.3] + [0.295] * 5
  assert not any(watch.stalled(e, 0.0) for e in errors)   # 5 steps without 1 cm
  assert watch.stalled(0.295, 0.0)
  assert not watch.stalled(0.2, 0.0)   # progress again
  watch.reset()
  assert not watch.stalled(1.0, 0.2)


def _stalled_twice(env, expert):
  """Runs the expert to a carry and makes it stall twice; (moving part, grasp sign, where
  the part was taken from, timestep)."""
  timestep = env.reset()
  expert.reset()
  furniture = env.task.furniture
  while expert.phase != Phase.CLOSE:
    timestep = env.step(expert(timestep))
  moving, sign = expert.job[1], expert._grasp_sign
  taken_from = furniture.part_poses(env.physics)[0][moving].copy()
  while expert.phase != Phase.ALIGN or expert._plan is None:
    timestep = env.step(expert(timestep))
  for _ in range(5):   # carrying
    timestep = env.step(expert(timestep))
  assert furniture.part_poses(env.physics)[0][moving][2] > taken_from[2] + 0.05
  expert._carry_stalled(moving, *expert._plan)   # first stall: another mate
  assert expert.phase == Phase.ALIGN and expert._plan is None
  timestep = env.step(expert(timestep))
  expert._carry_stalled(moving, *expert._plan)   # second: a planned path, or put it back
  return moving, sign, taken_from, timestep


def test_twice_stalled_carry_with_no_planned_path_puts_the_part_back(monkeypatch):
  # As without OMPL (the `planning` extra): no joint-space path, so the part goes back.
  monkeypatch.setattr(joint_planner, "AVAILABLE", False)
  env = ikea_suite.load("stool_round_frosta", "sawyer", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  furniture = env.task.furniture
  moving, sign, taken_from, timestep = _stalled_twice(env, expert)
  phases = [expert.phase]
  for _ in range(300):
    timestep = env.step(expert(timestep))
    if expert.phase != phases[-1]:
      phases.append(expert.phase)
    if expert.job_just_chosen:
      break
  assert phases == [Phase.PUT_BACK, Phase.RELEASE, Phase.RETREAT, Phase.REACH]
  put_at = furniture.part_poses(env.physics)[0][moving]
  assert np.linalg.norm(put_at - taken_from) < 0.03   # back on the floor where it lay
  assert expert.job[1] == moving and expert._grasp_sign == -sign


def test_twice_stalled_carry_follows_a_planned_joint_path_to_the_mate():
  pytest.importorskip("ompl")
  env = ikea_suite.load("stool_round_frosta", "sawyer", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  moving, _, _, timestep = _stalled_twice(env, expert)
  assert expert.phase == Phase.PLANNED_CARRY and expert._plan is not None
  phases = [expert.phase]
  for _ in range(600):
    timestep = env.step(expert(timestep))
    if expert.phase != phases[-1]:
      phases.append(expert.phase)
    if env.task.state.connections:
      break
  # Along the path, to the approach pose, in, connected: never put back.
  assert phases[:3] == [Phase.PLANNED_CARRY, Phase.ALIGN, Phase.INSERT]
  assert len(env.task.state.connections) == 1


def test_a_grasp_that_does_not_hold_is_not_tried_again_until_both_have_failed():
  # Lifted with nothing in the fingers (put in ALIGN with the part still on the floor):
  # the part is taken with its other grasp next; when that fails too, another part.
  env = ikea_suite.load("stool_round_frosta", "sawyer", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  timestep = env.step(expert(timestep))   # a part and a grasp chosen
  moving, sign = expert.job[1], expert._grasp_sign
  expert.phase = Phase.ALIGN
  timestep = env.step(expert(timestep))
  assert expert.phase == Phase.REACH and (moving, sign) in expert._stalled_grasps
  timestep = env.step(expert(timestep))
  assert expert.job[1] == moving and expert._grasp_sign == -sign
  assert moving not in expert._unreachable
  expert.phase = Phase.ALIGN
  timestep = env.step(expert(timestep))
  assert moving in expert._unreachable
  timestep = env.step(expert(timestep))
  assert expert.job[1] != moving


def test_an_arm_taking_over_remembers_its_stalled_grasps_until_a_connection():
  env = ikea_suite.load("stool_round_frosta", "baxter", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  env.reset()
  expert.reset()
  right = expert._arms[0]
  right._stalled_grasps.add((1, 1.0))
  right.take_over()   # the other arm worked meanwhile, without connecting anything
  assert (1, 1.0) in right._stalled_grasps
  right._connections = -1   # a connection made since this arm last worked
  right.take_over()
  assert not right._stalled_grasps


def test_an_arm_folded_against_its_limits_is_brought_home_by_task_space_actions():
  # The Sawyer as a tuning episode (table_four_leg_lack, seed 3) left it: shoulder, elbow
  # and wrist at the limits the IK keeps them in. Servoed straight to its home tool pose
  # from there, the arm stayed folded 0.57 m short; the Unwinder's joint-space path gets it
  # home through nothing but task-space actions.
  env = ikea_suite.load("table_four_leg_lack", "sawyer", seed=0, scale=0.5)
  env.reset()
  robot, physics = env.task.robot, env.physics
  physics.bind(robot.arms[0].joints).qpos = [0.85, 0.23, -1.19, 2.89, 2.01, 1.75, 4.70]
  physics.forward()
  unwinder = arm_motion.Unwinder()
  assert unwinder.distance_from_home(robot, physics, 0) > 1.0
  unwinder.start(robot, physics, 0)
  action = np.zeros(env.action_spec().shape)
  action[6] = -1.0   # fingers open
  for _ in range(200):
    if unwinder.done:
      break
    action[:6] = unwinder(robot, physics, 0)
    env.step(action)
  assert unwinder.done
  assert unwinder.distance_from_home(robot, physics, 0) < 0.25   # home branch; the posture settles it
  home_pos, home_rot = robot.home_tcp_poses()[0]
  distance, angle = arm_motion.pose_error(robot, physics, 0, home_pos, home_rot)
  assert distance < 0.02 and angle < 0.05


def _sawyer_expert(furniture):
  """(env, expert, first TimeStep) of the Sawyer's expert on `furniture` at scale 0.5, seed 0."""
  env = ikea_suite.load(furniture, "sawyer", seed=0, scale=0.5)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  return env, expert, timestep


def _closes_and_lifts(env, expert, timestep):
  """Steps the expert to its close and on into the carry; checks the part it took rose
  5 cm (held). Returns the (moving part, grasp position) it closed on."""
  furniture, physics = env.task.furniture, env.physics
  while expert.phase != Phase.CLOSE:
    timestep = env.step(expert(timestep))
  moving, grasp = expert.job[1], expert._grasp[0].copy()
  lying_at = furniture.part_poses(physics)[0][moving][2]
  while expert.phase != Phase.ALIGN:
    timestep = env.step(expert(timestep))
  for _ in range(3):
    timestep = env.step(expert(timestep))
  assert expert.job[1] == moving and expert.phase == Phase.ALIGN
  assert furniture.part_poses(physics)[0][moving][2] > lying_at + 0.05   # lifted: held
  return moving, grasp


def test_a_round_leg_lying_rolled_is_taken_with_the_fingertips_above_the_floor():
  # Rolled 45 degrees about its axis, a round leg lies as before, but its bounding box
  # reaches 3.7 mm below the floor; fingertips aimed 3 mm above that box pressed on the
  # floor and could not close (Baxter, tuning seed 1 of table_four_leg_side_oak).
  env, expert, timestep = _sawyer_expert("stool_round_frosta")
  furniture, physics = env.task.furniture, env.physics
  positions, rotations = furniture.part_poses(physics)
  with physics.reset_context():
    for leg in range(1, 4):
      rolled = rotations[leg] @ geometry.rot_z(np.pi / 4)
      furniture.set_part_pose(physics, leg, positions[leg], geometry.mat_to_quat(rolled))
  _, grasp = _closes_and_lifts(env, expert, timestep)
  assert grasp[2] >= expert._clearance.pad_below + 0.003 - 1e-6   # tips 3 mm above the floor


def test_a_leg_with_another_part_beside_its_middle_is_taken_where_the_fingers_land_clear():
  # A leg lying across the middle of the leg to be taken: an open finger came down on it
  # and the reach stalled there for the rest of the episode (kids_white, tuning seeds 5, 9).
  env, expert, timestep = _sawyer_expert("table_four_leg_lack")
  furniture, physics = env.task.furniture, env.physics
  base, _ = env.task.robot.base_pose
  legs = [k for k in range(len(furniture.parts)) if k != env.task.root_part]
  moving, blocker, others = legs[0], legs[1], legs[2:]
  half = furniture.spec.parts[blocker].bounds[1][2]   # legs are long along their own z
  radius = furniture.spec.parts[moving].bounds[1][0]
  along_x = geometry.mat_to_quat(geometry.axis_angle_to_mat([0.0, np.pi / 2, 0.0]))
  along_y = geometry.mat_to_quat(geometry.axis_angle_to_mat([np.pi / 2, 0.0, 0.0]))
  centre = base + [0.6, -0.3, radius + 0.001]   # the nearest leg: the expert's first job
  root = env.task.root_part
  root_pos, root_rot = (x[root] for x in furniture.part_poses(physics))
  with physics.reset_context():
    # reset_context puts every body back at its model pose: the top, too, would lie there,
    # right way up and half in the floor, and every leg's mate under it.
    furniture.set_part_pose(physics, root, root_pos, geometry.mat_to_quat(root_rot))
    furniture.set_part_pose(physics, moving, centre, along_x)
    furniture.set_part_pose(physics, blocker, centre - [0.0, radius + 0.004 + half, 0.0], along_y)
    for k, spot in zip(others, ([0.35, 0.75], [0.75, 0.4])):
      furniture.set_part_pose(physics, k, base + [*spot, radius + 0.001], along_x)
  point, rot = single_arm.ArmAssemblyController._grasp_pose(expert, moving)
  fingers = finger_room.finger_points(env.task.robot, physics, 0) @ rot.T
  middle = part_geometry.part_pose(physics, furniture, moving)[0]
  middle[2] = point[2]
  assert finger_room.lands_on_another_part(physics, furniture, moving, middle + fingers)
  assert not finger_room.lands_on_another_part(physics, furniture, moving, point + fingers)
  taken, grasp = _closes_and_lifts(env, expert, timestep)
  assert taken == moving
  assert abs(grasp[0] - centre[0]) > 0.02   # moved along the leg, off the blocker


def test_a_held_part_with_no_mate_left_is_set_down_and_taken_the_other_way():
  # Every mate and twist failed: an expert that lets go where the part hangs takes it the
  # same way again, 30 times to the end of the episode (kids_white, tuning seed 7).
  env, expert, timestep = _sawyer_expert("table_four_leg_lack")
  moving, _ = _closes_and_lifts(env, expert, timestep)
  sign = expert._grasp_sign
  failed = set()
  while (plan := mating.plan_mating(env, 0, moving, expert._approach, failed)) is not None:
    failed.add(plan[1:])
  expert._plan, expert._failed_plans = None, failed
  timestep = env.step(expert(timestep))
  assert expert.phase == Phase.PUT_BACK and not expert._failed_plans
  assert (moving, sign) in expert._stalled_grasps and moving not in expert._unreachable
  while expert.phase != Phase.CLOSE:   # set down, let go, and taken again
    timestep = env.step(expert(timestep))
  assert expert.job[1] == moving and expert._grasp_sign == -sign
