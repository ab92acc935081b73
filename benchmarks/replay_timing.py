"""Times env.step against raw mujoco.mj_step over the same substeps from the same states.

Each env step's starting state (integration state and weld data) is recorded
outside the timing; raw MuJoCo then steps from each recorded state in turn,
so both sides integrate the same contacts, constraints and controls and the
ratio measures only what the environment adds.

The two sides alternate in blocks of `block` control steps: a block of env
steps, then raw MuJoCo over that block's states in a tight loop, then the next
block. On a shared machine whose speed drifts over seconds, a whole env pass
followed by a whole raw pass put the drift into the ratio (the same code
measured 1.16 to 1.40 on one afternoon); in alternating blocks both sides see
the same machine.

`clock` is time.perf_counter (wall time) by default; time.thread_time counts
only the CPU time of this thread, which a machine shared with other jobs
disturbs far less (time spent waiting for a core is not counted).
"""

import time

import mujoco
import numpy as np

BLOCK = 25   # control steps per alternation: about 20 ms of each side


def time_env_and_raw(env, actions, clock=time.perf_counter, block=BLOCK):
  """(seconds per env step, seconds per raw step, substeps) over `actions`.

  An episode that ends mid-run is reset and the run continues.
  """
  spec = mujoco.mjtState.mjSTATE_INTEGRATION
  env.reset()
  env_seconds = raw_seconds = 0.0
  raw_model = raw_data = None
  for start in range(0, len(actions), block):
    states, eq_data = [], []
    for action in actions[start:start + block]:
      # Fetched every step: composer may recompile the physics on reset.
      model, data = env.physics.model.ptr, env.physics.data.ptr
      state = np.empty(mujoco.mj_stateSize(model, spec))
      mujoco.mj_getState(model, data, state, spec)
      states.append(state)
      eq_data.append(model.eq_data.copy())
      begin = clock()
      last = env.step(action).last()
      env_seconds += clock() - begin
      if last:
        env.reset()
    model = env.physics.model.ptr
    if model is not raw_model:
      raw_model, raw_data = model, mujoco.MjData(model)
    substeps = int(round(env.control_timestep() / model.opt.timestep))
    env_eq_data = model.eq_data.copy()   # the env goes on with its own welds
    for state, eq in zip(states, eq_data):
      mujoco.mj_setState(model, raw_data, state, spec)
      model.eq_data[:] = eq
      begin = clock()
      mujoco.mj_step(model, raw_data, substeps)
      raw_seconds += clock() - begin
    model.eq_data[:] = env_eq_data
  return env_seconds / len(actions), raw_seconds / len(actions), substeps
