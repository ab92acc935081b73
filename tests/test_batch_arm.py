"""The batched (MJX) task for the Panda, on MJX's JAX implementation on CPU: the model
matches the CPU environment's, task-space actions move the tool as the CPU env's do, the
vector env serves the arm, and the batched scripted expert completes the last part."""

import time

import jax
import numpy as np
import pytest

pytest.importorskip("mujoco.mjx")

import ikea_suite   # noqa: E402
from ikea_suite import errors   # noqa: E402
from ikea_suite import observations   # noqa: E402
from ikea_suite.batch import arm_control   # noqa: E402
from ikea_suite.batch import arm_env   # noqa: E402
from ikea_suite.batch import arm_scripted   # noqa: E402

FURNITURE = "table_four_leg_lack"
# The last-part task of the four-leg table: four of its five parts joined.
OPTIONS = dict(preassembled=4, layouts=4)
# Tool positions of the batched world and the CPU env after the same task-space actions
# differ by at most this (m) and their orientations by TOOL_ANGLE_TOL (rad): the IK
# solvers differ (arm_control.py: closed-form damped least squares against mink's QP).
TOOL_POS_TOL = 0.01
TOOL_ANGLE_TOL = 0.05


@pytest.fixture(scope="module")
def env():
  return arm_env.load(FURNITURE, "panda", impl="jax", **OPTIONS)


def _actions(steps):
  """A task-space sequence: moves along each axis, turns about each, gripper open."""
  out = np.zeros((steps, 8))
  out[:, 6] = -1.0
  out[:, 7] = -1.0
  pattern = [(0, 0.8), (1, -0.8), (2, -0.6), (5, 0.8), (3, 0.5), (0, -0.6), (4, -0.5)]
  for i in range(steps):
    axis, value = pattern[(i // 4) % len(pattern)]
    out[i, axis] = value
  return out


def test_model_matches_cpu(env):
  cpu = ikea_suite.load(FURNITURE, "panda", seed=0, **{"preassembled": 4})
  timestep = cpu.physics.model.opt.timestep
  model = env.arm_model.model
  assert model.opt.timestep == timestep
  assert model.opt.cone == cpu.physics.model.opt.cone
  assert model.opt.impratio == cpu.physics.model.opt.impratio
  assert env.settings.substeps == cpu.task.config.substeps
  assert env.settings.max_steps == cpu.task.config.max_steps
  assert env.action_names == cpu.task.action_names
  obs = env.reset_batch(jax.random.PRNGKey(0), 1).obs
  cpu_obs = cpu.reset().observation
  for key, value in cpu_obs.items():
    assert key in obs, key
    assert np.shape(value) == obs[key].shape[1:], key
  assert set(obs) == set(cpu_obs)
  for key in obs:
    observations.spec(key, obs[key].shape[1:], env.num_parts)
  # The home tool pose, by the jax forward kinematics.
  np.testing.assert_allclose(obs["robot/tcp_positions"][0],
                             cpu_obs["robot/tcp_positions"], atol=1e-6)


def test_forward_kinematics_matches_mujoco(env):
  import mujoco
  am = env.arm_model
  data = mujoco.MjData(am.model)
  rng = np.random.default_rng(0)
  for _ in range(3):
    q = rng.uniform(am.joint_low, am.joint_high)
    data.qpos[am.arm_qpos] = q
    mujoco.mj_kinematics(am.model, data)
    with env.precision():
      pos, rot = arm_control.tool_pose(env.chain, jax.numpy.asarray(q))
    np.testing.assert_allclose(pos, data.site_xpos[am.tcp_site], atol=1e-9)
    np.testing.assert_allclose(rot.ravel(), data.site_xmat[am.tcp_site], atol=1e-9)


def test_tool_motion_matches_cpu_env(env):
  steps = 28
  actions = _actions(steps)
  cpu = ikea_suite.load(FURNITURE, "panda", seed=0, **{"preassembled": 4})
  cpu.reset()
  cpu_tool = []
  for action in actions:
    obs = cpu.step(action).observation
    cpu_tool.append((obs["robot/tcp_positions"][0], obs["robot/tcp_quaternions"][0]))
  state = env.reset_batch(jax.random.PRNGKey(0), 1)
  errors_pos, errors_rot = [], []
  for action, (cpu_pos, cpu_quat) in zip(actions, cpu_tool):
    state = env.step_batch(state, action[None])
    pos = np.asarray(state.obs["robot/tcp_positions"])[0, 0]
    quat = np.asarray(state.obs["robot/tcp_quaternions"])[0, 0]
    errors_pos.append(np.linalg.norm(pos - cpu_pos))
    errors_rot.append(2 * np.arccos(min(1.0, abs(float(np.dot(quat, cpu_quat))))))
  moved = np.linalg.norm(cpu_tool[-1][0] - cpu_tool[0][0])
  print(f"tool moved {moved:.3f} m; batched vs CPU: max {max(errors_pos) * 1000:.1f} mm, "
        f"{np.degrees(max(errors_rot)):.2f} deg")
  assert moved > 0.1
  assert max(errors_pos) < TOOL_POS_TOL
  assert max(errors_rot) < TOOL_ANGLE_TOL


def test_bad_options():
  with pytest.raises(errors.UnknownNameError):
    arm_env.load(FURNITURE, "sawyer_x")
  with pytest.raises(errors.OptionValueError):
    arm_env.load(FURNITURE, "panda", control_mode="impedance")
  with pytest.raises(errors.UnknownNameError):
    arm_env.load(FURNITURE, "panda", cameras=("front",))


def test_scripted_expert_completes_last_part(env):
  start = time.time()
  success, steps, phase = arm_scripted.rollout(env, 4, 160, seed=0)
  print(f"completed {success.sum()}/4 in {steps.max()} steps ({time.time() - start:.0f} s); "
        f"phases {phase.tolist()}")
  assert success.mean() >= 0.75
