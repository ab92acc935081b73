"""The batched assembly environment for a single arm (ROBOTS): functional reset/step.

    env = ikea_suite.batch.load("table_four_leg_lack", robot="panda", num_worlds=4096)
    state = env.reset_batch(jax.random.PRNGKey(0), num_worlds=4096)
    state = env.step_batch(state, actions)            # actions (4096, 8) in [-1, 1]

The CPU environment `ikea_suite.load(furniture, robot)` in many worlds: the same
scene and physics (arm_model.py), the same action (task_space: move_x..rotate_z,
gripper, connect; or joint_position: one target per joint, gripper, connect; see
arm_control.py), thresholds, rewards, time limit and observation keys and shapes
(robot/joint_positions, robot/joint_velocities, robot/tcp_positions,
robot/tcp_quaternions, robot/gripper_opening, furniture/*, task/*). A step: the
arm's targets are set (IK in task-space mode), connect is tried when the last
action entry is > 0 (batch/connect.py, the Cursor's batched connect), then
`substeps` physics steps. The gripper holds parts by friction, as on the CPU.
Auto-reset and the State's fields are as in env.py (BatchAssembly), with the arm's
task-space target added (`targets`).

Differences from the CPU environment, and why:
- Episode starts: a reset draws one of `layouts` starts that the CPU task's own
  initializer made (tasks/arm_placement.py: parts within reach, `preassembled`
  pairs joined), recorded from the CPU environment at `layout_seed` when the
  environment is built, instead of a fresh
  layout per episode: the placement is rejection sampling over the arm's reach
  zone in numpy, not array code.
- The model's differences (arm_model.py): parts never collide with each other;
  welds at exact mated poses (connect snaps exactly, as the Cursor's batch does).
- The connect snap check is the Cursor batch's analytic floor check (connect.py).
- The IK: the CPU IK's own QP (mink's frame task, posture, damping and limits),
  solved by a batched projected Newton method where the CPU calls DAQP
  (arm_control.py).
- Control modes: task_space and joint_position (not task_space_pose, joint_torque,
  impedance); no dense reward, cameras or domain randomization.
"""

import functools
import typing

import jax
import jax.numpy as jnp
import numpy as np

from ikea_suite import errors
from ikea_suite.batch import arm_control
from ikea_suite.batch import arm_model
from ikea_suite.batch import backend
from ikea_suite.batch import connect as connect_lib
from ikea_suite.batch import contact_buffers
from ikea_suite.batch import env as env_lib
from ikea_suite.batch import observe
from ikea_suite.batch import rigid
from ikea_suite.batch import tables as tables_lib
from ikea_suite.batch import task_state
from ikea_suite.batch import worlds
from ikea_suite.robots import control_modes
from ikea_suite.tasks import alignment

ROBOTS = ("panda", "sawyer", "jaco")
CONNECT_ACTION = env_lib.CONNECT_ACTION
MODES = (control_modes.TASK_SPACE, control_modes.JOINT_POSITION)
# Warp buffer sizing (buffer_sizing): recorded starts settled, and the most contacts two
# finger pads make on a held part (MuJoCo's box-box collider writes up to 8 per pair).
SIZING_LAYOUTS = 8
GRIP_CONTACTS = 16
TASK_OPTIONS = ("time_limit", "control_timestep", "distance_threshold", "up_threshold",
                "forward_threshold", "connection_reward", "completion_bonus", "spread",
                "yaw_range", "preassembled", "scale")
ROBOT_OPTIONS = ("control_mode", "max_translation", "max_rotation", "base_pos", "base_yaw")
OPTIONS = TASK_OPTIONS + ROBOT_OPTIONS + ("layouts", "layout_seed")


class State(typing.NamedTuple):
  """One world's state (batched: a leading world axis on every leaf); env.State's fields
  and `targets`, the arm's task-space target (arm_control.TaskTargets).

  `task` is the Cursor's TaskState: its scene-graph fields (group, connector_used,
  adjacency, steps) are the arm's; its cursor fields stay at rest (held -1).
  """
  data: typing.Any
  task: task_state.TaskState
  targets: arm_control.TaskTargets
  obs: dict
  reward: jnp.ndarray
  done: jnp.ndarray
  metrics: dict
  info: dict


class Settings(typing.NamedTuple):
  """The resolved task options the step reads (from the CPU env's resolved TaskConfig)."""
  thresholds: alignment.Thresholds
  control_timestep: float
  substeps: int
  max_steps: int
  connection_reward: float
  completion_bonus: float
  control_mode: str


def check_options(robot, options):
  """Raises for a robot or option the batched arm task does not take."""
  if robot not in ROBOTS:
    raise errors.UnknownNameError("batched robot", robot, ("cursor",) + ROBOTS)
  for key in options:
    if key not in OPTIONS:
      raise errors.UnknownNameError("option", key, OPTIONS)
  mode = options.get("control_mode", control_modes.TASK_SPACE)
  if mode not in MODES:
    raise errors.OptionValueError(
        f"the batched arm takes control_mode {' or '.join(map(repr, MODES))}, got {mode!r}")
  layouts = options.get("layouts", arm_model.DEFAULT_LAYOUTS)
  if not isinstance(layouts, (int, np.integer)) or layouts < 1:
    raise errors.OptionValueError(f"layouts must be an integer >= 1, got {layouts!r}")
  seed = options.get("layout_seed", 0)
  if not isinstance(seed, (int, np.integer)) or seed < 0:
    raise errors.OptionValueError(f"layout_seed must be an integer >= 0, got {seed!r}")


class BatchArmAssembly(worlds.BatchWorlds):
  """The assembly task of one furniture for a single arm, stepped in many worlds by MJX.

  Args:
    furniture: catalog name or model file path.
    robot: one of ROBOTS.
    impl: "warp", "jax" or None (see BatchAssembly).
    num_worlds: worlds stepped together (sizes Warp's buffers; unused by jax).
    layouts: CPU episode starts recorded for the resets (arm_model.Layouts).
    layout_seed: the CPU environment's seed whose resets are recorded (default 0).
    **options: ikea_suite.load's options among OPTIONS.
  """

  def __init__(self, furniture, robot="panda", impl=None, num_worlds=None, buffer_sizes=None,
               layouts=arm_model.DEFAULT_LAYOUTS, layout_seed=0, **options):
    check_options(robot, dict(options, layouts=layouts, layout_seed=layout_seed))
    super().__init__(impl, num_worlds, buffer_sizes)
    self._robot = robot
    self._arm = am = arm_model.build(furniture, robot, layouts=layouts,
                                     light=self._impl == "jax", layout_seed=layout_seed,
                                     **options)
    config = am.task_config
    self._settings = Settings(
        thresholds=alignment.Thresholds.of(config), control_timestep=config.control_timestep,
        substeps=config.substeps, max_steps=config.max_steps,
        connection_reward=config.connection_reward, completion_bonus=config.completion_bonus,
        control_mode=am.robot_config.control_mode)
    self._batch_model = am.base
    with self.precision():
      self._build()

  def _build(self):
    am = self._arm
    bm = am.base
    self._tables = tables_lib.build(bm)
    f = lambda x: rigid.real(np.asarray(x))
    i = lambda x: jnp.asarray(np.asarray(x), dtype=jnp.int32)
    self._chain = arm_control.chain(bm.model, am.tcp_site, am.arm_qpos)
    self._a = dict(
        arm_qpos=i(am.arm_qpos), arm_dof=i(am.arm_dof), arm_act=i(am.arm_act),
        finger_qpos=i(am.finger_qpos), finger_act=i(am.finger_act),
        ik_low=f(am.ik_low), ik_high=f(am.ik_high), joint_low=f(am.joint_low),
        joint_high=f(am.joint_high), home_qpos=f(am.home_qpos), home_ctrl=f(am.home_ctrl),
        home_q=f(am.home_qpos[am.arm_qpos]), open=f(am.open_qpos), squeeze=f(am.squeeze_qpos),
        closed=f(am.closed_qpos), home_pos=f(am.home_tcp_pos), home_rot=f(am.home_tcp_rot),
        ws_low=f(am.workspace[0]), ws_high=f(am.workspace[1]))
    lay = am.layouts
    self._layouts = dict(part_qpos=f(lay.part_qpos), group=i(lay.group),
                         used=jnp.asarray(lay.connector_used), adjacency=jnp.asarray(lay.adjacency),
                         eq_active=jnp.asarray(lay.eq_active))
    self._put(bm.model)

  @property
  def robot(self):
    return self._robot

  @property
  def arm_model(self):
    """The arm_model.ArmBatchModel (compiled model, index tables, layouts)."""
    return self._arm

  @property
  def chain(self):
    """The arm's arm_control.Chain (forward kinematics of the tool)."""
    return self._chain

  @property
  def control_mode(self):
    return self._settings.control_mode

  @property
  def action_names(self):
    """The action entries, named as the CPU environment's action spec."""
    joints = [f"joint{k}" for k in range(1, len(self._arm.arm_qpos) + 1)]
    return control_modes.arm_action_names(self.control_mode, joints) + [CONNECT_ACTION]

  @property
  def action_size(self):
    return len(self.action_names)

  # -- one world -------------------------------------------------------------------

  def _task(self, k):
    lay = self._layouts
    return task_state.TaskState(
        cursor_pos=jnp.zeros((2, 3)), cursor_quat=jnp.tile(jnp.array([1.0, 0, 0, 0]), (2, 1)),
        held=jnp.full(2, -1, dtype=jnp.int32), grip_pos=jnp.zeros((2, 3)),
        grip_rot=jnp.tile(jnp.eye(3), (2, 1, 1)), group=lay["group"][k],
        connector_used=lay["used"][k], adjacency=lay["adjacency"][k], steps=jnp.int32(0))

  def observe(self, task, qpos, qvel):
    """The CPU environment's state observations of one world (jax default float)."""
    a = self._a
    q = qpos[a["arm_qpos"]]
    pos, rot = arm_control.tool_pose(self._chain, q)
    obs = observe.task_observations(self._tables, task, qpos)
    obs.update({
        "robot/joint_positions": q, "robot/joint_velocities": qvel[a["arm_dof"]],
        "robot/tcp_positions": pos[None], "robot/tcp_quaternions": rigid.mat_to_quat(rot)[None],
        "robot/gripper_opening": arm_control.gripper_opening(
            qpos[a["finger_qpos"]], a["open"], a["closed"])[None]})
    return {k: rigid.real(v) for k, v in obs.items()}

  @functools.cached_property
  def buffer_sizing(self):
    """contact_buffers.Sizing of Warp's buffers for this model (or the sizes given).

    The Cursor's rule (every part dropped on each face, contact_buffers.part_faces), taken
    together with the worst of settling each recorded episode start with the arm at home,
    plus room for the gripper: two finger pads holding a part, each a box on the part's
    geoms, give up to GRIP_CONTACTS contacts at the model's worst rows per contact.
    """
    given = self._given_sizing()
    if given is not None:
      return given
    am = self._arm
    bm, lay = am.base, am.layouts
    measured = contact_buffers.part_faces(bm)
    home = np.asarray(am.home_qpos, dtype=float)
    part_qpos = np.asarray(self._tables.part_qpos)
    for k in range(min(len(lay), SIZING_LAYOUTS)):
      qpos = home.copy()
      qpos[part_qpos] = lay.part_qpos[k]
      measured = measured.peak(contact_buffers.settle(
          bm.model, [qpos], eq_active=bm.model.eq_active0.astype(bool) | lay.eq_active[k]))
    rows_per_contact = max(1, -(-measured.contact_rows // max(1, measured.contacts)))
    measured = measured._replace(
        contacts=measured.contacts + GRIP_CONTACTS,
        candidates=measured.candidates + GRIP_CONTACTS,
        contact_rows=measured.contact_rows + GRIP_CONTACTS * rows_per_contact)
    return contact_buffers.size(
        measured, contact_buffers.equality_rows(0, bm.welds.num_welds, bm.num_parts))

  def tool_pose(self, qpos):
    """World position and rotation of the tool at the world's qpos."""
    return arm_control.tool_pose(self._chain, qpos[self._a["arm_qpos"]])

  def reset(self, rng):
    """A fresh episode: the arm at home, fingers open, parts as one of the recorded layouts.

    Args:
      rng: a jax PRNG key.

    Returns:
      State of one world.
    """
    a, lay = self._a, self._layouts
    rng, key = jax.random.split(rng)
    # int32 whatever the precision: jax draws other integers under x64, so the same key
    # would start a world from another layout on MJX's JAX implementation (and the host
    # physics) than on Warp.
    k = jax.random.randint(key, (), 0, lay["part_qpos"].shape[0], dtype=jnp.int32)
    data = self._data0
    qpos = a["home_qpos"].at[self._tables.part_qpos].set(lay["part_qpos"][k])
    data = data.replace(qpos=qpos, qvel=jnp.zeros_like(data.qvel), ctrl=a["home_ctrl"],
                        eq_active=self._data0.eq_active | lay["eq_active"][k],
                        time=jnp.zeros_like(data.time))
    task = self._task(k)
    targets = arm_control.TaskTargets(pos=a["home_pos"], rot=a["home_rot"])
    obs = self.observe(task, qpos, data.qvel)
    return State(data=data, task=task, targets=targets, obs=obs, reward=rigid.real(0.0),
                 done=jnp.bool_(False),
                 metrics={"connections": jnp.int32(0), "success": jnp.bool_(False)},
                 info={"rng": rng, "truncation": jnp.bool_(False), "diverged": jnp.bool_(False),
                       "final_obs": obs, "contact_overflow": jnp.int32(0),
                       "buffer_peak": jnp.zeros(2, dtype=jnp.int32)})

  def controls(self, state, action):
    """(ctrl, targets) of an action (clipped, finite) in the world's present state."""
    a, am = self._a, self._arm
    data = state.data
    q = data.qpos[a["arm_qpos"]]
    joints = len(am.arm_qpos)
    if self.control_mode == control_modes.TASK_SPACE:
      tool_pos, _ = arm_control.tool_pose(self._chain, q)
      targets = arm_control.apply_deltas(state.targets, action[:6], tool_pos, am.max_translation,
                                         am.max_rotation, a["ws_low"], a["ws_high"])
      arm_ctrl = arm_control.ik_step(self._chain, q, targets.pos, targets.rot, a["home_q"],
                                     a["ik_low"], a["ik_high"],
                                     am.velocity_limit * self._settings.control_timestep)
      squeeze = action[6]
    else:
      targets = state.targets
      arm_ctrl = arm_control.joint_targets(action[:joints], a["joint_low"], a["joint_high"])
      squeeze = action[joints]
    fingers = arm_control.gripper_targets(squeeze, a["open"], a["squeeze"])
    ctrl = data.ctrl.at[a["arm_act"]].set(arm_ctrl).at[a["finger_act"]].set(fingers)
    return ctrl, targets

  def step(self, state, action):
    """One control step of one world, with auto-reset when the episode ends.

    Args:
      state: State of one world.
      action: (action_size,) actions; clipped to [-1, 1], non-finite entries read as 0.

    Returns:
      The next State.
    """
    data, task, targets, connected = self.before_physics(state, action)
    data, overflow, peak = backend.substeps_watched(self._mx, data, self._settings.substeps)
    stepped = self.after_physics(state, data, task, targets, connected)
    return stepped._replace(info=dict(stepped.info, contact_overflow=overflow, buffer_peak=peak))

  def before_physics(self, state, action):
    """The step up to the physics: the arm's controls and connect.

    Returns:
      (data to step, task state, task-space targets, connected: bool).
    """
    s = self._settings
    action = jnp.clip(jnp.nan_to_num(rigid.real(action), nan=0.0, posinf=0.0, neginf=0.0),
                      -1.0, 1.0)
    ctrl, targets = self.controls(state, action)
    data = state.data
    task, qpos, qvel, eq_active, connected = connect_lib.connect(
        self._tables, s.thresholds, state.task, data.qpos, data.qvel, data.eq_active,
        action[-1] > 0)
    data = data.replace(qpos=qpos, qvel=qvel, eq_active=eq_active, ctrl=ctrl)
    return data, task, targets, connected

  def after_physics(self, state, data, task, targets, connected):
    """The step after `substeps` physics steps of `data`: rewards, termination, reset."""
    s = self._settings
    task = task._replace(steps=task.steps + 1)
    complete = task_state.complete(task)
    diverged = ~(jnp.isfinite(data.qpos).all() & jnp.isfinite(data.qvel).all()
                 & (jnp.abs(data.qvel).max() < env_lib.DIVERGED_SPEED))
    reward = rigid.real(jnp.where(
        diverged, 0.0,
        connected * s.connection_reward + (connected & complete) * s.completion_bonus))
    timeout = task.steps >= s.max_steps
    done = complete | diverged | timeout
    obs = self.observe(task, data.qpos, data.qvel)
    fresh = self.reset(state.info["rng"])
    pick = lambda new, old: jax.tree.map(lambda x, y: jnp.where(done, x, y), new, old)
    connections = (jnp.where(state.done, 0, state.metrics["connections"])
                   + connected.astype(jnp.int32))
    return State(
        data=data.where(done, fresh.data), task=pick(fresh.task, task),
        targets=pick(fresh.targets, targets), obs=pick(fresh.obs, obs), reward=reward, done=done,
        metrics={"connections": connections, "success": complete},
        info={"rng": jnp.where(done, fresh.info["rng"], state.info["rng"]),
              "truncation": timeout & ~complete & ~diverged, "diverged": diverged,
              "final_obs": obs, "contact_overflow": jnp.int32(0),
              "buffer_peak": jnp.zeros(2, dtype=jnp.int32)})

  @functools.cached_property
  def _host_parts(self):
    return (jax.jit(jax.vmap(self.before_physics)), jax.jit(jax.vmap(self.after_physics)))

  def step_batch_host(self, state, actions):
    """`step_batch` with the physics stepped by MuJoCo's C library on the host, world by
    world, on the same compiled model; everything else (controls, IK, connect, rewards,
    resets) is the device code. For tests on machines where MJX's JAX implementation is
    too slow for this model (see docs/batch.md): MJX's agreement with MuJoCo is MJX's.
    """
    import mujoco   # host physics only
    self._check_actions(state, actions)
    before, after = self._host_parts
    model = self._arm.model
    with self.precision():
      data, task, targets, connected = before(state, actions)
      fields = {f: np.array(getattr(data, f)) for f in
                ("qpos", "qvel", "ctrl", "eq_active", "qacc_warmstart", "time")}
      host = mujoco.MjData(model)
      for w in range(fields["qpos"].shape[0]):
        for f, values in fields.items():
          if f == "time":
            host.time = float(values[w])
          else:
            getattr(host, f)[:] = values[w]
        mujoco.mj_step(model, host, nstep=self._settings.substeps)
        for f in ("qpos", "qvel", "qacc_warmstart"):
          fields[f][w] = getattr(host, f)
        fields["time"][w] = host.time
      data = data.replace(**{f: jnp.asarray(fields[f]) for f in
                             ("qpos", "qvel", "qacc_warmstart", "time")})
      return after(state, data, task, targets, connected)


@functools.lru_cache(maxsize=8)
def _cached(furniture, robot, impl, num_worlds, buffer_sizes, options):
  return BatchArmAssembly(furniture, robot=robot, impl=impl, num_worlds=num_worlds,
                          buffer_sizes=buffer_sizes, **dict(options))


def load(furniture="table_four_leg_lack", robot="panda", impl=None, num_worlds=None,
         buffer_sizes=None, **options):
  """The batched arm environment of `furniture` (cached as env.load is).

  Args:
    furniture: catalog name or model file path.
    robot: one of ROBOTS.
    impl: "warp", "jax" or None (warp on a GPU with warp-lang, else jax).
    num_worlds: worlds to be stepped together (Warp buffer sizing).
    buffer_sizes: (nconmax, njmax) per world for Warp instead of the measured sizing.
    **options: OPTIONS (ikea_suite.load's, `layouts` and `layout_seed`).

  Returns:
    A BatchArmAssembly.
  """
  check_options(robot, options)
  impl = backend.check_impl(impl)
  if impl == "jax":
    num_worlds = None
  key = tuple(sorted((k, tuple(v) if isinstance(v, (list, tuple)) else v)
                     for k, v in options.items()))
  if buffer_sizes is not None:   # checked here, and hashable for the cache
    sizes = contact_buffers.given(buffer_sizes)
    buffer_sizes = (sizes.nconmax, sizes.njmax)
  return _cached(furniture, robot, impl, num_worlds, buffer_sizes, key)
