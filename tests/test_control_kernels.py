"""The compiled twins of TaskSpaceTargets' per-step arithmetic (robots/_ik_kernels.c) against
the Python, to the bit."""

import copy

import numpy as np
import pytest

from ikea_suite.robots import compiled_kernels
from ikea_suite.robots import control_modes

pytestmark = pytest.mark.skipif(compiled_kernels.kernels is None,
                                reason="the optional compiled _ik_kernels was not built")


def _bits(values):
  return [float(v).hex() for v in np.ravel(values)]


@pytest.mark.parametrize("arms", [1, 2])
def test_compiled_target_updates_agree_with_the_python_to_the_bit(arms):
  # Moves that turn and that do not, turns below the 1e-12 rad cut-off, targets pulled back
  # to 0.1 m from a stuck tool, targets clamped to the workspace box, over 300 steps.
  rng = np.random.default_rng(3)
  workspace = np.tile([[[-2.0, -2.0, 0.0], [2.0, 2.0, 0.2]]], (arms, 1, 1))
  compiled = control_modes.TaskSpaceTargets(arms, 0.02, 0.05, workspace)
  home = [(rng.uniform(-0.2, 0.4, 3), np.eye(3)) for _ in range(arms)]
  compiled.reset(home)
  python = copy.deepcopy(compiled)
  python.use_compiled = False
  assert compiled.use_compiled
  origin, rotation = [0.1, -0.2, 0.05], np.linalg.qr(rng.normal(size=(3, 3)))[0].ravel().tolist()
  lagged = clamped = 0
  for step in range(300):
    actions = rng.uniform(-1.5, 1.5, (arms, 7))
    if step % 5 == 0:
      actions[:, 3:6] = 0.0   # no turn
    elif step % 7 == 0:
      actions[:, 3:6] = 1e-13   # a turn below the cut-off: the identity
    tcp = np.array(python.pos) + rng.normal(scale=0.01, size=(arms, 3))   # the tool follows
    if step % 11 == 0:
      tcp[:, 0] += 0.3   # a tool held back: the target is pulled to 0.1 m from it
    for targets in (compiled, python):
      targets.apply_deltas(actions, tcp)
    lagged += np.isclose(np.linalg.norm(np.array(python.pos) - tcp, axis=1), 0.1).sum()
    clamped += np.isin(np.array(python.pos)[:, 2], workspace[0, :, 2]).sum()
    assert _bits(compiled.pos) == _bits(python.pos) and _bits(compiled.rot) == _bits(python.rot)
    for (cpos, crot), (ppos, prot) in zip(compiled.in_frame(origin, rotation),
                                          python.in_frame(origin, rotation)):
      assert _bits(cpos) == _bits(ppos) and _bits(crot) == _bits(prot)
      assert isinstance(cpos, list) and isinstance(crot, list)
  assert lagged >= 5 and clamped >= 5   # both clamps ran


def test_compiled_delta_target_reads_any_float_arrays_and_rejects_bad_ones():
  kernels = compiled_kernels.kernels
  turn = np.zeros((3, 3))
  args = ([0.0, 0.0, 0.5], np.float32([0.1, 0, 0, 0, 0, 0.2]), np.array([0.0, 0.0, 0.5]),
          0.02, 0.05, 0.1,
          [-1.0] * 3, [1.0] * 3, turn)
  pos, turned = kernels.delta_target(*args)
  assert turned and np.allclose(pos, [0.002, 0.0, 0.5], atol=1e-9)
  assert np.allclose(turn @ turn.T, np.eye(3))
  with pytest.raises(ValueError, match="move must hold 6"):
    kernels.delta_target(args[0], [0.0] * 5, *args[2:])
  with pytest.raises(TypeError, match="turn_out must be 9 contiguous float64"):
    kernels.delta_target(*args[:8], np.zeros((3, 3), dtype=np.float32))
