"""Times env.step against raw mujoco.mj_step over the same substeps from the same states.

Each env step's starting state (integration state and weld data) is recorded
outside the timing; raw MuJoCo then steps from each recorded state in turn,
so both sides integrate the same contacts, constraints and controls and the
ratio measures only what the environment adds.

`clock` is time.perf_counter (wall time) by default; time.thread_time counts
only the CPU time of this thread, which a machine shared with other jobs
disturbs far less (time spent waiting for a core is not counted).
"""

import time

import mujoco
import numpy as np


def time_env_and_raw(env, actions, clock=time.perf_counter):
  """(seconds per env step, seconds per raw step, substeps) over `actions`.

  An episode that ends mid-run is reset and the run continues.
  """
  spec = mujoco.mjtState.mjSTATE_INTEGRATION
  env.reset()
  states, eq_data, env_seconds = [], [], 0.0
  for action in actions:
    # Fetched every step: composer may recompile the physics on reset.
    model, data = env.physics.model.ptr, env.physics.data.ptr
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)
    states.append(state)
    eq_data.append(model.eq_data.copy())
    start = clock()
    last = env.step(action).last()
    env_seconds += clock() - start
    if last:
      env.reset()
  model = env.physics.model.ptr
  substeps = int(round(env.control_timestep() / model.opt.timestep))
  raw_data = mujoco.MjData(model)
  raw_seconds = 0.0
  for state, eq in zip(states, eq_data):
    mujoco.mj_setState(model, raw_data, state, spec)
    model.eq_data[:] = eq
    start = clock()
    mujoco.mj_step(model, raw_data, substeps)
    raw_seconds += clock() - start
  return env_seconds / len(actions), raw_seconds / len(actions), substeps
