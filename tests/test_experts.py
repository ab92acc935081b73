"""ikea_suite.experts: one entry point for every robot's scripted expert."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import experts
from ikea_suite.experts import bimanual
from ikea_suite.experts import cursor_oracle
from ikea_suite.experts import part_geometry
from ikea_suite.experts import single_arm
from tests import helpers


@pytest.mark.parametrize("robot,kind", [("cursor", cursor_oracle.CursorOracle),
                                        ("sawyer", single_arm.ArmAssemblyController),
                                        ("panda", single_arm.ArmAssemblyController),
                                        ("jaco", single_arm.ArmAssemblyController),
                                        ("baxter", bimanual.TwoArmExpert)])
def test_make_expert_returns_the_robots_policy_with_reset(robot, kind):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=0)
  expert = experts.make_expert(env)
  assert isinstance(expert, kind)
  expert.reset()
  timestep = env.reset()
  action = expert(timestep)
  assert np.shape(action) == env.action_spec().shape


def test_arm_expert_needs_a_task_space_move_mode():
  env = ikea_suite.load("table_four_leg_lack", "panda", control_mode="joint_position")
  with pytest.raises(ikea_suite.IkeaSuiteError,
                     match="'task_space' or 'impedance', got control_mode='joint_position'"):
    experts.make_expert(env)


def test_supported_names_the_robots_with_experts():
  with pytest.raises(ikea_suite.UnknownNameError, match="robot with an expert"):
    experts.supported("r2d2")
  assert set(experts.supported("cursor")) == set(ikea_suite.furniture_names())
  for robot in ("sawyer", "panda", "baxter", "jaco"):
    for furniture in experts.supported(robot):
      assert furniture in ikea_suite.furniture_names()
      assert 0.2 <= experts.supported_scale(robot, furniture) <= 2.0


def test_require_supported_rejects_an_unmeasured_pair():
  env = ikea_suite.load("bed_slatted_junior_pine", "jaco")
  with pytest.raises(ikea_suite.UnknownNameError, match="furniture the jaco expert assembles"):
    experts.make_expert(env, require_supported=True)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_baxter_expert_gives_each_part_to_the_arm_on_its_side(seed):
  env = ikea_suite.load("table_four_leg_lack", "baxter", seed=seed, scale=0.5)
  expert = experts.make_expert(env)
  timestep = env.reset()
  expert.reset()
  for _ in range(3):
    timestep = env.step(expert(timestep))
  part = expert.job[1]
  positions, _ = env.task.furniture.part_poses(env.physics)
  base_pos, base_rot = env.task.robot.base_pose
  right_of_torso = (base_rot.T @ (positions[part] - base_pos))[1] < 0
  assert expert.arms_used == {0 if right_of_torso else 1}
  assert expert.active_arm == (0 if right_of_torso else 1)


# Episodes an arm's expert once failed, each completed since the fix named beside it
# (success rates are in the sweep, README).
@pytest.mark.parametrize("furniture,robot,seed", [
    # Left the arm folded at its joint limits after the third leg, and it stalled on the
    # fourth for the rest of the episode (3 of 4 legs); it unwinds home now.
    pytest.param("table_four_leg_lack", "sawyer", 3, id="sawyer-lack-unwinds-home"),
    # In the gripper's default slot the fingertips stopped 14 mm apart and could not
    # squeeze the box's 4-6 mm walls; one slot in (grippers.RETHINK_SLOT_1) they meet.
    pytest.param("box_open_kuggis", "sawyer", 0, id="sawyer-thin-box-walls"),
    # The grasp the converged IK judged best left the wrist 0.3 rad short of its limit, and
    # the carry turned it into that limit; the grasp and mate are now judged along the
    # servo's own path (arm_motion.servo_path_end). Two of three connections before.
    pytest.param("desk_trestle_w120_white", "sawyer", 1, id="sawyer-wrist-the-long-way"),
    # The second trestle's carry stalled at the twist that turns its stretcher slot
    # inwards (the last joint at its limit); the other twist, only costlier, attached it
    # facing out, and the stretcher never went in (2 of 3 connections). Mates off the
    # design are no longer planned: the trestle goes back to the rack, taken the other way.
    pytest.param("desk_trestle_w100_birch", "panda", 6, id="panda-trestle-never-facing-out"),
    # The stretcher, lying on the floor beside the table, rose while it swung towards its
    # mate; its end struck a standing trestle and toppled it (2 of 3 connections). The
    # carry now rises straight up first while the held part would come over a standing
    # part it does not clear (clearance.AssemblyClearance.rise_first).
    pytest.param("table_trestle_l120_white", "panda", 1, id="panda-stretcher-rises-clear"),
])
def test_arm_expert_completes_an_episode_it_once_failed(furniture, robot, seed):
  env = ikea_suite.load(furniture, robot, seed=seed, scale=0.5)
  helpers.run_expert(env)
  assert env.task.state.complete   # every part joined through the action vector


def test_rise_first_holds_the_carry_over_its_start_only_while_a_standing_part_is_in_the_way():
  # Stop the seed-1 episode as the stretcher's carry begins, the trestles standing.
  env = ikea_suite.load("table_trestle_l120_white", "panda", seed=1, scale=0.5)
  names = [p.name for p in env.task.furniture.spec.parts]
  expert = next((e for e in helpers.expert_steps(env) if e.phase == single_arm.Phase.ALIGN
                 and e.job and names[e.job[1]] == "stretcher"), None)
  assert expert is not None
  task, physics, robot = env.task, env.physics, env.task.robot   # the physics reset made
  route, stretcher = expert._clearance, expert.job[1]
  tcp, _ = robot.tcp_pose(physics, 0)
  positions, _ = task.furniture.part_poses(physics)
  trestle = names.index("trestle0")
  assert trestle in part_geometry.root_group(task)   # standing on the top, 0.35 m tall
  over = positions[trestle][:2] - positions[stretcher][:2]   # the stretcher moved over it
  towards = tcp + np.r_[over, 0.05]
  held = route.rise_first(towards, stretcher, top=1.0)
  np.testing.assert_allclose(held[:2], tcp[:2])   # straight up from where it is
  assert held[2] == towards[2]
  # Where the carry's own height could not clear the trestle, it is not frozen.
  route.reset()
  np.testing.assert_array_equal(route.rise_first(towards, stretcher, top=tcp[2] + 0.01), towards)
  # Moving away from the assembly, nothing is in the way.
  away = tcp + np.r_[-over, 0.05]
  np.testing.assert_array_equal(route.rise_first(away, stretcher, top=1.0), away)


def test_expert_supported_pairs_are_loadable_pairs():
  pairs = set(ikea_suite.EXPERT_SUPPORTED)
  assert pairs <= set(ikea_suite.ALL)
  assert {f for f, r in pairs if r == "cursor"} == set(ikea_suite.furniture_names())


def test_rollout_cli_runs_the_expert(capsys):
  from ikea_suite import cli
  assert cli.main(["--policy", "expert", "--robot", "sawyer", "--scale", "0.5",
                   "--time-limit", "1"]) == 0
  assert "expert policy" in capsys.readouterr().out
