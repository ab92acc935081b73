"""The paper's Cursor agent: two floating, collision-free cursors that hold parts.

Each cursor moves in x, y, z and rotates about the world x, y, z axes. With
its select action on (> 0) it picks up the part it encloses and carries it
through a weld to the world whose target pose follows the cursor; select off
releases. Rates are set by `move_speed` (m/s) and `rotate_speed` (rad/s) for
an action of 1; actions outside [-1, 1] are clipped by the environment.
"""

import numpy as np
from dm_control import composer
from dm_control import mjcf

from ikea_suite import config as config_lib
from ikea_suite import geometry
from ikea_suite import mujoco_arrays
from ikea_suite import physics_settings
from ikea_suite.robots import base

NUM_CURSORS = 2
# Action entries of each cursor, in order; the action names are f"cursor{i}_{entry}".
PER_CURSOR_ACTIONS = ("move_x", "move_y", "move_z", "rotate_x", "rotate_y", "rotate_z", "select")
_COLORS = ((0.1, 0.4, 0.95, 0.8), (0.95, 0.3, 0.1, 0.8))
# World positions (m) of cursors 0 and 1 at the start of an episode (world-aligned).
HOME_POSITIONS = ((-0.4, 0.0, 0.6), (0.4, 0.0, 0.6))


class Cursor(base.Robot):
  """Two cursors; their poses live in physics state as slide + ball joints.

  Args (to _build):
    name: the MJCF model name.
    config: a config.CursorConfig (None: the defaults), with any of its options given as
      keywords replacing its values.
  """

  CONFIG = config_lib.CursorConfig

  def _build(self, name="cursor", config=None, **options):
    self._config = config = self.CONFIG.of(config, **options)
    self._mjcf_root = mjcf.RootElement(model=name)
    self._move_speed = config.move_speed
    self._rotate_speed = config.rotate_speed
    self._grasp_margin = config.grasp_margin
    self._workspace = np.array(config.workspace, dtype=float)
    radius = config.radius
    self._slides, self._balls = [], []
    for i in range(NUM_CURSORS):
      body = self._mjcf_root.worldbody.add("body", name=f"cursor{i}", gravcomp=1)
      self._slides.append([body.add("joint", name=f"cursor{i}_{axis}", type="slide", axis=vec,
                                    damping=0, armature=0.01)
                           for axis, vec in zip("xyz", np.eye(3))])
      self._balls.append(body.add("joint", name=f"cursor{i}_rot", type="ball", armature=0.01))
      body.add("geom", name=f"cursor{i}", type="sphere", size=(radius,), rgba=_COLORS[i],
               contype=0, conaffinity=0, mass=0.01, group=2)
    self._grip_welds = []
    self._held = np.full(NUM_CURSORS, -1)
    self._grip_pos = np.zeros((NUM_CURSORS, 3))
    self._grip_rot = np.tile(np.eye(3), (NUM_CURSORS, 1, 1))

  def _build_observables(self):
    return CursorObservables(self)

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def action_names(self):
    return [f"cursor{i}_{a}" for i in range(NUM_CURSORS) for a in PER_CURSOR_ACTIONS]

  @property
  def move_speed(self):
    """Metres per second at a move action of 1."""
    return self._move_speed

  @property
  def rotate_speed(self):
    """Radians per second at a rotate action of 1."""
    return self._rotate_speed

  def grip_offset(self, i):
    """Pose (position, rotation) of the part cursor i holds, in the cursor's frame."""
    return self._grip_pos[i].copy(), self._grip_rot[i].copy()

  @property
  def held_parts(self):
    """Index of the part each cursor holds, -1 for none."""
    return self._held.copy()

  def bind_scene(self, arena, furniture, assembly, control_timestep):
    self._furniture, self._assembly, self._dt = furniture, assembly, control_timestep
    # One inactive weld per (cursor, part) from the world to the part: its
    # relpose is then simply the part's target pose in the world frame.
    self._grip_welds = [[arena.mjcf_model.equality.add(
        "weld", name=f"{self._mjcf_root.model}{i}_grip_{j}", body1="world", body2=frame,
        active=False,
        solref=physics_settings.CURSOR_GRIP_SOLREF) for j, frame in enumerate(furniture.part_frames)]
        for i in range(NUM_CURSORS)]

  def after_compile(self, physics, random_state):
    slides = [physics.bind(s) for s in self._slides]
    self._slide_qpos = np.array([b.qposadr for b in slides])          # (2, 3)
    self._slide_dof = np.array([b.dofadr for b in slides])
    ball_qpos = np.array([physics.bind(b).qposadr for b in self._balls])
    ball_dof = np.array([physics.bind(b).dofadr for b in self._balls])
    self._ball_quat_index = ball_qpos[:, None] + np.arange(4)
    self._ball_vel_index = ball_dof[:, None] + np.arange(3)
    self._weld_ids = np.array([physics.bind(w).element_id for w in self._grip_welds])
    # Views into MuJoCo's buffers, fetched once: the wrapper's attribute lookup
    # costs more than the arithmetic done with them every step.
    self._qpos, self._qvel = physics.data.qpos, physics.data.qvel
    self._eq_active, self._eq_data = physics.data.eq_active, physics.model.eq_data
    self._geom_xpos, self._geom_xmat = physics.data.geom_xpos, physics.data.geom_xmat
    self._xpos, self._xmat = physics.data.xpos, physics.data.xmat
    model = physics.model
    self._geom_ids, self._geom_part = self._furniture.collision_geoms
    geoms = self._geom_ids
    self._geom_center = model.geom_aabb[geoms, :3].copy()
    self._geom_half = model.geom_aabb[geoms, 3:].copy() + self._grasp_margin

  def initialize_episode(self, physics, random_state):
    self._held[:] = -1
    for i in range(NUM_CURSORS):
      self.set_cursor_pose(physics, i, np.array(HOME_POSITIONS[i]), np.eye(3))

  def cursor_positions(self, physics):
    """(2, 3) world positions of both cursors."""
    return self._qpos[self._slide_qpos]

  def tool_positions(self, physics):
    return self.cursor_positions(physics)

  def held_parts_by_tool(self, physics, part_body_ids):
    out = np.zeros((NUM_CURSORS, len(part_body_ids)), dtype=bool)
    holding = np.flatnonzero(self._held >= 0)
    out[holding, self._held[holding]] = True
    return out

  def cursor_quaternions(self, physics):
    """(2, 4) world orientations; the ball joint sits in a world-aligned frame."""
    return self._qpos[self._ball_quat_index]

  def cursor_pose(self, physics, i):
    quat = physics.data.qpos[self._ball_quat_index[i]]
    return physics.data.qpos[self._slide_qpos[i]], geometry.quat_to_mat(quat)

  def set_cursor_pose(self, physics, i, pos, rot):
    self._write_pose(physics, i, pos, geometry.mat_to_quat(rot))

  def _write_pose(self, physics, i, pos, quat):
    data = physics.data
    data.qpos[self._slide_qpos[i]] = pos
    data.qpos[self._ball_quat_index[i]] = quat
    data.qvel[self._slide_dof[i]] = 0.0
    data.qvel[self._ball_vel_index[i]] = 0.0

  def apply_action(self, physics, action, random_state):
    action = action.reshape(NUM_CURSORS, len(PER_CURSOR_ACTIONS))
    qpos = self._qpos
    positions = np.minimum(np.maximum(
        qpos[self._slide_qpos] + action[:, :3] * (self._move_speed * self._dt),
        self._workspace[0]), self._workspace[1])
    qpos[self._slide_qpos] = positions
    self._qvel[self._slide_dof] = 0.0
    self._qvel[self._ball_vel_index] = 0.0
    turns = action[:, 3:6] * (self._rotate_speed * self._dt)
    for i in range(NUM_CURSORS):
      quat = geometry.quat_mul(geometry.axis_angle_to_quat(turns[i]), qpos[self._ball_quat_index[i]])
      qpos[self._ball_quat_index[i]] = quat / np.sqrt(quat @ quat)
      selecting, held = action[i, 6] > 0, self._held[i]
      if not selecting and held < 0:
        continue  # idle cursor: nothing to grab, release or steer
      rot = geometry.quat_to_mat(quat)
      if selecting and held < 0:
        self._grab(physics, i, positions[i], rot)
      elif not selecting:
        self._release(physics, i)
      if self._held[i] >= 0:
        self._write_grip_target(i, positions[i], rot)

  def _enclosed_part(self, point):
    """The part whose collision geom (bounding box plus margin) holds `point`, or -1."""
    ids = self._geom_ids
    rot = self._geom_xmat[ids].reshape(-1, 3, 3)
    local = np.einsum("gji,gj->gi", rot, point - self._geom_xpos[ids])
    offset = np.abs(local - self._geom_center)
    inside = np.flatnonzero((offset <= self._geom_half).all(axis=1))
    if not len(inside):
      return -1
    # Among enclosing geoms, the one whose centre is nearest.
    return int(self._geom_part[inside[np.argmin((offset[inside] ** 2).sum(axis=1))]])

  def _grab(self, physics, i, pos, rot):
    part = self._enclosed_part(pos)
    if part < 0:
      return
    other = self._held[1 - i]
    if other >= 0 and self._assembly.same_group(part, other):
      return  # the other cursor already holds this assembly
    self._held[i] = part
    self._update_grip_offset(physics, i, pos, rot)
    self._eq_active[self._weld_ids[i, part]] = 1

  def _release(self, physics, i):
    self._eq_active[self._weld_ids[i, self._held[i]]] = 0
    self._held[i] = -1

  def _update_grip_offset(self, physics, i, pos, rot):
    body = self._furniture.body_ids[self._held[i]]
    part_pos = self._xpos[body]
    part_rot = self._xmat[body].reshape(3, 3)
    self._grip_pos[i] = rot.T @ (part_pos - pos)
    self._grip_rot[i] = rot.T @ part_rot

  def _write_grip_target(self, i, pos, rot):
    target_rot = rot @ self._grip_rot[i]
    target_pos = pos + rot @ self._grip_pos[i]
    eq = self._eq_data[self._weld_ids[i, self._held[i]]]
    eq[3:6] = target_pos
    eq[6:10] = geometry.mat_to_quat(target_rot)

  def on_parts_moved(self, physics, part_indices):
    moved = set(int(p) for p in part_indices)
    holders = [i for i in range(NUM_CURSORS) if self._held[i] in moved]
    for i in holders:
      pos, rot = self.cursor_pose(physics, i)
      self._update_grip_offset(physics, i, pos, rot)
      self._write_grip_target(i, pos, rot)
    # Two cursors on one rigid assembly would fight: the mover lets go.
    if self._held.min() >= 0 and self._assembly.same_group(self._held[0], self._held[1]):
      for i in holders[:1]:
        self._release(physics, i)


class CursorObservables(composer.Observables):
  """Cursor positions, orientations and the part each holds (-1 for none)."""

  # Named as every robot's tool pose (observations.py): the cursor is the Cursor's tool.
  @composer.observable
  def tcp_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.cursor_positions)

  @composer.observable
  def tcp_quaternions(self):
    return mujoco_arrays.FreshGeneric(self._entity.cursor_quaternions)

  @composer.observable
  def held_parts(self):
    return mujoco_arrays.FreshGeneric(lambda physics: self._entity.held_parts.astype(np.float64))
