"""The batched assembly environment: functional reset/step in MuJoCo Playground's style.

    env = ikea_suite.batch.load("table_four_leg_lack", num_worlds=4096)
    state = env.reset_batch(jax.random.PRNGKey(0), num_worlds=4096)
    state = env.step_batch(state, actions)            # actions (4096, 15) in [-1, 1]

`reset(rng)` and `step(state, action)` are pure single-world functions
(vmap and jit them as you like); `reset_batch` / `step_batch` are their
vmapped, jitted forms. A step is the CPU environment's step: the cursors act,
connect is tried when the last action entry is > 0, then `substeps` physics
steps (25 at the defaults). A world whose episode ended (complete, time limit
or divergence) is reset inside the same step with a fresh random placement:
`reward`, `done` and `info["truncation"]` describe the step that ended, `obs`
and `data` already the next episode's start (gymnasium's same-step
autoreset), `info["final_obs"]` the last observation of the ended one.
Observations carry the CPU environment's keys (ikea_suite.observations); the
gymnasium vector env (gym_vector.py) gives them its dtypes and turns this into
gymnasium's default next-step autoreset with `restart_batch`.
"""

import functools
import typing

import jax
import jax.numpy as jnp

from ikea_suite.batch import backend
from ikea_suite.batch import connect as connect_lib
from ikea_suite.batch import contact_buffers
from ikea_suite.batch import cursor as cursor_lib
from ikea_suite.batch import model as model_lib
from ikea_suite.batch import observe
from ikea_suite.batch import placement
from ikea_suite.batch import rigid
from ikea_suite.batch import settings as settings_lib
from ikea_suite.batch import tables as tables_lib
from ikea_suite.batch import task_state
from ikea_suite.batch import worlds
from ikea_suite.robots import cursor as cpu_cursor

CONNECT_ACTION = "connect"
# Beyond this speed (m/s or rad/s) a part has left the physics the time step resolves.
DIVERGED_SPEED = 1e3


class State(typing.NamedTuple):
  """One world's state (batched: a leading world axis on every leaf).

  Attributes:
    data: mjx.Data.
    task: TaskState (cursors, holding, groups, used connectors, scene graph).
    obs: dict of observations (observe.observe).
    reward: reward of the last step.
    done: bool, the last step ended the episode.
    metrics: dict: connections (made this episode), success (last step completed).
    info: dict: rng (the world's key), truncation (time limit), diverged, final_obs,
      contact_overflow (int32: contact_buffers.OVERFLOW_BUFFERS bits of the Warp buffers that
      overflowed during the step; always 0 on MJX's JAX implementation, which has no fixed
      buffers), buffer_peak ((2,) int32: most contacts of all worlds and rows of this world
      a substep needed; zeros on JAX).
  """
  data: typing.Any
  task: task_state.TaskState
  obs: dict
  reward: jnp.ndarray
  done: jnp.ndarray
  metrics: dict
  info: dict


class BatchAssembly(worlds.BatchWorlds):
  """The assembly task of one furniture for the Cursor agent, stepped in many worlds by MJX.

  Args:
    furniture: catalog name or model file path.
    impl: "warp" (MJX Warp, CUDA GPU) or "jax" (MJX's JAX implementation); default: warp
      when a GPU and warp-lang are present, else jax.
    num_worlds: worlds stepped together (sizes Warp's shared contact buffer; unused by jax).
    buffer_sizes: (nconmax, njmax) per world for Warp instead of the measured sizing
      (contact_buffers.sizing).
    **options: load()'s task options (settings.OPTIONS).
  """

  def __init__(self, furniture, impl=None, num_worlds=None, buffer_sizes=None, **options):
    super().__init__(impl, num_worlds, buffer_sizes)
    self._batch_model = model_lib.build(furniture)
    with self.precision():
      self._build(options)

  def _build(self, options):
    bm = self._batch_model
    self._settings = settings_lib.resolve(bm.num_parts, **options)
    self._tables = tables_lib.build(bm)
    self._scatter = placement.scatter(bm.spec, spread=self._settings.spread,
                                      yaw_range=self._settings.yaw_range)
    self._home = rigid.real(cpu_cursor.HOME_POSITIONS)
    self._put(bm.model)

  @functools.cached_property
  def buffer_sizing(self):
    """contact_buffers.Sizing of Warp's contact and constraint buffers for this model."""
    return self._given_sizing() or contact_buffers.sizing(self._batch_model,
                                                          cpu_cursor.NUM_CURSORS)

  @property
  def action_names(self):
    """The 15 action entries, named as the CPU environment's action spec."""
    return [f"cursor{i}_{a}" for i in range(cpu_cursor.NUM_CURSORS)
            for a in cpu_cursor.PER_CURSOR_ACTIONS] + [CONNECT_ACTION]

  @property
  def action_size(self):
    return len(self.action_names)

  # -- one world -------------------------------------------------------------------

  def initial_task_state(self):
    """Cursors home, nothing held, every part its own group."""
    p, c = self.num_parts, len(self._batch_model.table)
    return task_state.TaskState(
        cursor_pos=self._home, cursor_quat=jnp.tile(jnp.array([1.0, 0, 0, 0]), (2, 1)),
        held=jnp.full(2, -1, dtype=jnp.int32), grip_pos=jnp.zeros((2, 3)),
        grip_rot=jnp.tile(jnp.eye(3), (2, 1, 1)), group=jnp.arange(p, dtype=jnp.int32),
        connector_used=jnp.zeros(c, dtype=bool), adjacency=jnp.zeros((p, p), dtype=bool),
        steps=jnp.int32(0))

  def with_part_poses(self, state, pos, rot):
    """`state` with the parts at (pos (p, 3), rot (p, 3, 3)), at rest; for curricula and tests."""
    data = state.data
    qpos, qvel = task_state.write_part_poses(self._tables, data.qpos, data.qvel, pos, rot,
                                             jnp.ones(self.num_parts, dtype=bool))
    data = data.replace(qpos=qpos, qvel=qvel)
    return state._replace(data=data, obs=observe.observe(self._tables, state.task, qpos))

  def reset(self, rng):
    """A fresh episode: parts scattered flat around the origin at random yaws.

    Args:
      rng: a jax PRNG key.

    Returns:
      State of one world.
    """
    rng, key = jax.random.split(rng)
    pos, rot = placement.place(self._scatter, key)
    data = self._data0
    qvel = jnp.zeros_like(data.qvel)
    qpos, qvel = task_state.write_part_poses(self._tables, data.qpos, qvel, pos, rot,
                                             jnp.ones(self.num_parts, dtype=bool))
    data = data.replace(qpos=qpos, qvel=qvel, eq_active=jnp.zeros_like(data.eq_active),
                        mocap_pos=self._home,
                        mocap_quat=jnp.tile(jnp.array([1.0, 0, 0, 0]), (2, 1)),
                        time=jnp.zeros_like(data.time))
    task = self.initial_task_state()
    obs = observe.observe(self._tables, task, qpos)
    return State(data=data, task=task, obs=obs, reward=rigid.real(0.0), done=jnp.bool_(False),
                 metrics={"connections": jnp.int32(0), "success": jnp.bool_(False)},
                 info={"rng": rng, "truncation": jnp.bool_(False),
                       "diverged": jnp.bool_(False), "final_obs": obs,
                       "contact_overflow": jnp.int32(0),
                       "buffer_peak": jnp.zeros(2, dtype=jnp.int32)})

  def step(self, state, action):
    """One control step of one world, with auto-reset when the episode ends.

    Args:
      state: State of one world.
      action: (15,) actions; clipped to [-1, 1], non-finite entries read as 0.

    Returns:
      The next State.
    """
    s = self._settings
    action = jnp.clip(jnp.nan_to_num(rigid.real(action), nan=0.0, posinf=0.0,
                                     neginf=0.0), -1.0, 1.0)
    data = state.data
    task, eq_active, mocap_pos, mocap_quat = cursor_lib.act(
        s.cursor, self._tables, s.control_timestep, state.task, action[:-1], data.qpos,
        data.eq_active, data.mocap_pos, data.mocap_quat)
    task, qpos, qvel, eq_active, connected = connect_lib.connect(
        self._tables, s.thresholds, task, data.qpos, data.qvel, eq_active, action[-1] > 0)
    mocap_pos, mocap_quat = cursor_lib.grip_targets(task, mocap_pos, mocap_quat)
    data = data.replace(qpos=qpos, qvel=qvel, eq_active=eq_active, mocap_pos=mocap_pos,
                        mocap_quat=mocap_quat)
    data, overflow, peak = backend.substeps_watched(self._mx, data, s.substeps)
    task = task._replace(steps=task.steps + 1)
    complete = task_state.complete(task)
    diverged = ~(jnp.isfinite(data.qpos).all() & jnp.isfinite(data.qvel).all()
                 & (jnp.abs(data.qvel).max() < DIVERGED_SPEED))
    reward = rigid.real(jnp.where(
        diverged, 0.0,
        connected * s.connection_reward + (connected & complete) * s.completion_bonus))
    timeout = task.steps >= s.max_steps
    done = complete | diverged | timeout
    obs = observe.observe(self._tables, task, data.qpos)
    fresh = self.reset(state.info["rng"])
    pick = lambda new, old: jax.tree.map(lambda x, y: jnp.where(done, x, y), new, old)
    # Data.where knows which Warp buffers are shared by all worlds (contacts) and keeps them.
    # A world that ended last step is in its new episode: count from zero.
    connections = (jnp.where(state.done, 0, state.metrics["connections"])
                   + connected.astype(jnp.int32))
    return State(
        data=data.where(done, fresh.data), task=pick(fresh.task, task), obs=pick(fresh.obs, obs),
        reward=reward, done=done,
        metrics={"connections": connections, "success": complete},
        info={"rng": jnp.where(done, fresh.info["rng"], state.info["rng"]),
              "truncation": timeout & ~complete & ~diverged, "diverged": diverged,
              "final_obs": obs, "contact_overflow": overflow, "buffer_peak": peak})


@functools.lru_cache(maxsize=8)
def _cached(furniture, impl, num_worlds, buffer_sizes, options):
  return BatchAssembly(furniture, impl=impl, num_worlds=num_worlds, buffer_sizes=buffer_sizes,
                       **dict(options))


def load(furniture="table_four_leg_lack", impl=None, num_worlds=None, buffer_sizes=None,
         robot="cursor", **options):
  """The batched assembly environment of `furniture` (cached: equal arguments return the same
  object, so its jitted functions compile once per process).

  Args:
    furniture: catalog name or model file path.
    impl: "warp", "jax" or None (warp on a GPU with warp-lang, else jax).
    num_worlds: worlds to be stepped together (Warp buffer sizing).
    buffer_sizes: (nconmax, njmax) per world for Warp instead of the measured sizing.
    robot: "cursor", or an arm of arm_env.ROBOTS (an arm_env.BatchArmAssembly).
    **options: ikea_suite.load's task options, see settings.OPTIONS (arm_env.OPTIONS for
      an arm).

  Returns:
    A BatchAssembly (or BatchArmAssembly).
  """
  if robot != "cursor":
    from ikea_suite.batch import arm_env   # imports this module
    return arm_env.load(furniture, robot, impl=impl, num_worlds=num_worlds,
                        buffer_sizes=buffer_sizes, **options)
  impl = backend.check_impl(impl)
  if impl == "jax":
    num_worlds = None   # only Warp sizes buffers by it; one cached env serves every size
  key = tuple(sorted((k, tuple(map(tuple, v)) if k == "workspace" else v)
                     for k, v in options.items()))
  if buffer_sizes is not None:   # checked here, and hashable for the cache
    sizes = contact_buffers.given(buffer_sizes)
    buffer_sizes = (sizes.nconmax, sizes.njmax)
  return _cached(furniture, impl, num_worlds, buffer_sizes, key)
