"""Impedance control mode: a Cartesian spring and damper MuJoCo evaluates every substep."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import config


def _env(robot, seed=0):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=seed, control_mode="impedance")
  env.reset()
  return env


def _hold(env):
  """The zero action with every gripper open."""
  action = np.zeros(env.action_spec().shape)
  names = env.action_spec().name.split("\t")
  action[[i for i, n in enumerate(names) if n.endswith("gripper")]] = -1.0
  return action


def _angle(a, b):
  return np.degrees(np.arccos(np.clip((np.trace(a.T @ b) - 1) / 2, -1, 1)))


@pytest.mark.parametrize("robot", ("sawyer", "panda", "baxter", "jaco"))
def test_impedance_tracks_task_space_moves(robot):
  env = _env(robot)
  arm = env.task.robot
  assert env.action_spec().name.split("\t")[:3] == [
      f"{'right_' if robot == 'baxter' else ''}move_{axis}" for axis in "xyz"]
  start, _ = arm.tcp_pose(env.physics, 0)
  action = _hold(env)
  action[2], action[5] = 1.0, 1.0   # up 2.5 cm and 0.15 rad about world z per step
  for _ in range(4):
    env.step(action)
  action[2] = action[5] = 0.0
  for _ in range(30):
    env.step(action)
  pos, rot = arm.tcp_pose(env.physics, 0)
  target_pos, target_rot = arm.task_space_target(0)
  assert pos[2] - start[2] == pytest.approx(0.1, abs=0.01)
  # The Jaco's home pose is near a wrist singularity (11 N and 4 N m at its tool come to
  # under 0.5 N m at its joints) and its joints hold 1-2 N m of friction: it settles
  # about 9 mm and 4 degrees off where the 7-joint arms settle within 2-3 mm and 2.5 degrees.
  jaco = robot == "jaco"
  assert np.linalg.norm(pos - target_pos) < (0.015 if jaco else 0.004)
  assert _angle(rot, target_rot) < (6.0 if jaco else 3.5)


def test_impedance_yields_to_a_push_by_its_stiffness():
  # A steady push at the hand moves the tool by force / stiffness, whatever the arm's posture.
  push, stiffness = 15.0, config.IMPEDANCE_STIFFNESS[0]
  for axis in (0, 1, 2):
    env = _env("sawyer")
    arm = env.task.robot
    start, _ = arm.tcp_pose(env.physics, 0)
    hand = env.physics.model.site_bodyid[arm._tcp_ids[0]]
    for _ in range(40):
      env.physics.data.xfrc_applied[hand, axis] = push
      env.step(_hold(env))
    moved = arm.tcp_pose(env.physics, 0)[0] - start
    assert moved[axis] == pytest.approx(push / stiffness, rel=0.2), axis
    assert np.linalg.norm(np.delete(moved, axis)) < 0.3 * moved[axis], axis


def test_impedance_joint_torques_stay_within_the_arm_limits():
  env = _env("panda")
  arm = env.task.robot
  limits = arm.arms[0].torque_limits
  dofs = env.physics.bind(arm.arms[0].joints).dofadr
  action = _hold(env)
  action[0] = action[2] = -1.0   # drive the target down and back into the floor
  worst = np.zeros(len(dofs))
  for _ in range(20):
    env.step(action)
    worst = np.maximum(worst, np.abs(env.physics.data.qfrc_actuator[dofs]))
  assert np.all(worst <= limits + 1e-6)
  assert np.any(worst > 0.5 * limits)   # the push was hard enough to matter


def test_the_expert_drives_an_arm_in_impedance_mode():
  from ikea_suite import experts
  env = ikea_suite.load("stool_round_frosta", "sawyer", seed=3, control_mode="impedance")
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  while not timestep.last():
    timestep = env.step(expert(timestep))
  assert len(env.task.state.connections) >= 2


def test_impedance_stiffness_option_sets_the_spring_and_is_checked():
  env = ikea_suite.load("table_four_leg_lack", "panda", seed=0, control_mode="impedance",
                        impedance_stiffness=(500.0, 20.0))
  model = env.physics.model
  gains = [model.actuator_gainprm[i, 0] for i in range(model.nu)
           if "impedance" in model.id2name(i, "actuator")]
  assert gains == [500.0] * 3 + [20.0] * 3
  with pytest.raises(ikea_suite.OptionValueError, match="control_mode='impedance' only"):
    ikea_suite.load("table_four_leg_lack", "panda", impedance_stiffness=(500.0, 20.0))
  with pytest.raises(ikea_suite.OptionValueError, match="impedance_stiffness"):
    ikea_suite.load("table_four_leg_lack", "panda", control_mode="impedance",
                    impedance_stiffness=(500.0, -1.0))
