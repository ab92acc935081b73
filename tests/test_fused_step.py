"""The fused task-space step (robots/_ik_kernels.c task_space_assemble) against the separate
steps it replaces (TaskSpaceTargets.apply_deltas, in_frame, DifferentialIK.step), to the bit."""

import logging

import numpy as np
import pytest

import ikea_suite
from ikea_suite.robots import compiled_kernels
from ikea_suite.robots import registry

pytestmark = pytest.mark.skipif(not compiled_kernels.fused,
                                reason="the fused step cannot run on this install")

ARMS = ("sawyer", "baxter", "panda", "jaco")


def _env(robot, fused, mode="task_space"):
  env = ikea_suite.load("table_four_leg_lack", robot, seed=0, control_mode=mode)
  env.task.robot.tracker.use_fused = fused
  env.reset()
  return env


@pytest.mark.parametrize("mode", ["task_space", "task_space_pose"])
@pytest.mark.parametrize("robot", ARMS)
def test_the_fused_step_moves_the_arms_as_the_separate_steps_do(robot, mode):
  # Moves with and without turns, turns below the 1e-12 rad cut-off, large moves that the
  # lag and workspace clamps hold back, joints pushed past their limits, and (the Jaco)
  # endless joints wound whole turns, which re-targets the posture in Python before the
  # compiled call. task_space_pose sets the targets in Python and fuses the rest.
  fused, separate = _env(robot, True, mode), _env(robot, False, mode)
  arm = fused.task.robot
  ik = arm.ik
  _, high = ik.limits
  ik_rows, rows = ik.qpos_index, arm._ik_to_qpos   # the IK's joints in its model and the env's
  limited = np.isfinite(high[ik_rows])
  pushed, beyond = rows[limited][:2], high[ik_rows][limited][:2] + 0.02
  wound = rows[np.isin(ik_rows, ik._endless_qpos)]
  rng = np.random.default_rng(7)
  size = fused.action_spec().shape[0]
  rewound = 0
  for step in range(60):
    action = rng.uniform(-1, 1, size)
    if step % 5 == 0:
      action[:] = np.where(np.arange(size) % 7 >= 3, 0.0, action)   # no turn
    elif step % 7 == 0:
      action[:] = np.where(np.arange(size) % 7 >= 3, 1e-13, action)   # below the cut-off
    if step % 10 == 3:
      for env in (fused, separate):
        qpos = env.physics.data.qpos
        qpos[pushed] = beyond
        qpos[wound] += 4 * np.pi
        env.physics.forward()
      rewound += len(wound) > 0
    for env in (fused, separate):
      env.step(action)
    assert fused.physics.data.ctrl.tobytes() == separate.physics.data.ctrl.tobytes(), step
    assert fused.physics.data.qpos.tobytes() == separate.physics.data.qpos.tobytes(), step
  assert arm.tracker.fused and not separate.task.robot.tracker.fused
  assert (robot != "jaco") or rewound >= 5
  assert arm.ik_failures == separate.task.robot.ik_failures


def test_a_fused_step_that_disagrees_with_the_python_is_left_off(monkeypatch, caplog):
  robot = registry.get("panda").factory()
  qp = robot.ik._qp
  assemble = qp.assemble

  def off_by_a_bit(*args, **kwargs):
    h, c, lower, upper = assemble(*args, **kwargs)
    h[0, 0] = np.nextafter(h[0, 0], np.inf)
    return h, c, lower, upper

  monkeypatch.setattr(qp, "assemble", off_by_a_bit)
  with caplog.at_level(logging.WARNING):
    assert robot.ik.fused_plan(0.05) is None
  assert "differs from the separate steps" in caplog.text
  monkeypatch.setattr(qp, "assemble", assemble)
  assert robot.ik.fused_plan(0.1) is not None   # a new step length checks again


def test_the_fused_calls_reject_bad_arguments():
  kernels = compiled_kernels.kernels
  robot = registry.get("panda").factory()
  plan = robot.ik.fused_plan(0.05)
  targets = robot._targets.fused_plan([0.0] * 3, np.eye(3).ravel().tolist())
  q = np.zeros(robot.ik.model.nv)
  actions, tcp = np.zeros((1, 7)), np.zeros((1, 3))
  kernels.task_space_assemble(plan, targets, actions, tcp, q)   # well formed
  kernels.task_space_assemble(plan, targets, None, "not read", q)   # targets left as they are
  with pytest.raises(TypeError, match="takes 5 arguments"):
    kernels.task_space_assemble(plan, targets, actions, tcp)
  with pytest.raises(ValueError, match="incorrect name"):
    kernels.task_space_assemble(targets, plan, actions, tcp, q)
  with pytest.raises(ValueError, match="at least 6 numbers per arm"):
    kernels.task_space_assemble(plan, targets, np.zeros((1, 5)), tcp, q)
  with pytest.raises(TypeError, match="q must be 9 contiguous float64"):
    kernels.task_space_assemble(plan, targets, actions, tcp, q[:-1])
  with pytest.raises(TypeError, match="tcp_pos must be 3 contiguous float64"):
    kernels.task_space_assemble(plan, targets, actions, np.zeros((1, 3), np.float32), q)
  with pytest.raises(ValueError, match="targets must hold 12"):
    kernels.qp_assemble(plan, q, [0.0] * 11)
  with pytest.raises(ValueError, match="must not be 0"):
    kernels.qp_plan(0, 0, [0], 9, 1.0, *[np.zeros(1)] * 23)
  with pytest.raises(ValueError, match="nv must be 1 to 256"):
    kernels.qp_plan(1, 1, [0], 0, 1.0, *[np.zeros(1)] * 23)
  with pytest.raises(ValueError, match="site_ids must hold 1 to 8 sites"):
    kernels.qp_plan(1, 1, [], 9, 1.0, *[np.zeros(1)] * 23)
  with pytest.raises(TypeError, match="qpos must be 9 contiguous float64"):
    kernels.qp_plan(1, 1, [0], 9, 1.0, *[np.zeros(1)] * 23)
  with pytest.raises(ValueError, match="arms must be 1 to 8"):
    kernels.target_plan(0, 0.1, 0.1, 0.1, [0.0] * 3, [0.0] * 9, *[np.zeros(1)] * 5)
