"""The flattened MuJoCo state a demonstration stores, and restoring it.

`mjSTATE_INTEGRATION` is everything `mj_step` reads from mjData: time,
qpos, qvel, act, the constraint solver's warm start, ctrl, applied forces,
active equality constraints (welds that hold or join parts), mocap poses,
userdata and plugin state. Restoring it and stepping the same actions gives
the same trajectory bit for bit on the same machine and versions; model
fields the task writes during an episode (weld poses, collision bits) are
reproduced by replaying the actions from the episode start, where the task
has reset them.
"""

import mujoco
import numpy as np
from dm_control import mjcf

from ikea_suite import errors

STATE_KIND = mujoco.mjtState.mjSTATE_INTEGRATION
STATE_KIND_NAME = "mjSTATE_INTEGRATION"


def state_size(physics: mjcf.Physics) -> int:
  """Length of the flattened state of `physics`' model.

  Args:
    physics: a dm_control Physics.
  Returns:
    The number of float64 entries get_state returns.
  """
  return mujoco.mj_stateSize(physics.model.ptr, STATE_KIND)


def get_state(physics: mjcf.Physics) -> np.ndarray:
  """The flattened integration state, float64 of length `state_size(physics)`.

  Args:
    physics: a dm_control Physics.
  Returns:
    A new array (STATE_KIND's fields, in MuJoCo's order).
  """
  state = np.empty(state_size(physics))
  mujoco.mj_getState(physics.model.ptr, physics.data.ptr, state, STATE_KIND)
  return state


def set_state(physics: mjcf.Physics, state: np.ndarray) -> None:
  """Writes a flattened integration state back and recomputes derived quantities.

  Args:
    physics: a dm_control Physics of the model the state came from.
    state: array from `get_state` on the same model.
  Raises:
    IkeaSuiteError: a state of the wrong length for this model.
  """
  state = np.ascontiguousarray(state, dtype=np.float64)
  if state.shape != (state_size(physics),):
    raise errors.IkeaSuiteError(
        f"state has shape {state.shape}, the model needs ({state_size(physics)},)")
  mujoco.mj_setState(physics.model.ptr, physics.data.ptr, state, STATE_KIND)
  physics.forward()
