"""The furniture prop: its parts as free entities, connectors as arrays, the assembly graph."""


import numpy as np
from dm_control import composer
from dm_control import mjcf

from ikea_suite import mujoco_arrays
from ikea_suite.props import connector_table
from ikea_suite.props import model_format
from ikea_suite.props import part as part_lib


class Furniture(composer.Entity):
  """A furniture model, built from its FurnitureSpec.

  The entity itself holds no bodies: each part is its own `Part` entity which
  `attach_to` adds to an arena as a free body (MuJoCo allows free joints only
  on top-level bodies). Connector geometry is precomputed as arrays so the
  task's alignment check is pure numpy.
  """

  def _build(self, spec):
    """Args: spec: the furniture's FurnitureSpec (catalog.spec), at the size it is built."""
    self._spec = spec
    self._mjcf_root = mjcf.RootElement(model=self._spec.name)
    self._parts = [part_lib.Part(p, self._spec) for p in self._spec.parts]
    self._connectors = connector_table.ConnectorTable(self._spec)
    self._frames = None
    self._body_ids = None

  def attach_to(self, arena):
    """Adds every part to `arena` as a free body carrying the part's inertial from its file;
    returns their attachment frames."""
    arena.attach(self)
    self._frames = [arena.add_free_entity(p) for p in self._parts]
    for part, frame in zip(self._parts, self._frames):
      if part.inertial is not None:
        frame.add("inertial", **part.inertial)
    return self._frames

  def _build_observables(self):
    return FurnitureObservables(self)

  def after_compile(self, physics, random_state):
    self._body_ids = np.array(physics.bind(self._frames).element_id)
    self._collision_geoms, self._collision_geom_parts = model_format.collision_geoms(
        physics.model, self._body_ids)
    # qpos/qvel addresses of each part's free joint, so poses are written without
    # dm_control's named indexing on the step path.
    joints = physics.model.body_jntadr[self._body_ids]
    self._qpos_adr = physics.model.jnt_qposadr[joints][:, None] + np.arange(7)
    self._dof_adr = physics.model.jnt_dofadr[joints][:, None] + np.arange(6)
    self._arrays = mujoco_arrays.ArrayViews("xpos", "xquat")   # the observables' reads
    self._body_rows = mujoco_arrays.compact_index(self._body_ids)

  def set_part_pose(self, physics, part, position, quaternion):
    """Puts part `part` (index) at a world pose and stops it; call physics.forward() after."""
    physics.data.qpos[self._qpos_adr[part, :3]] = position
    physics.data.qpos[self._qpos_adr[part, 3:]] = quaternion
    physics.data.qvel[self._dof_adr[part]] = 0.0

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def spec(self):
    return self._spec

  @property
  def scale(self):
    """Size factor of this furniture relative to its design (the `scale` load option)."""
    return self._spec.scale

  @property
  def name(self):
    return self._spec.name

  @property
  def parts(self):
    return self._parts

  @property
  def part_frames(self):
    """The attachment frame (free body) of each part, in part order."""
    return self._frames

  @property
  def connectors(self):
    return self._connectors

  @property
  def body_ids(self):
    """MuJoCo body ids of the parts, valid after compilation."""
    return self._body_ids

  @property
  def collision_geoms(self):
    """(geom ids, part index of each) of the parts' collision geoms, valid after compilation."""
    return self._collision_geoms, self._collision_geom_parts

  def part_positions(self, physics):
    """(parts, 3) world positions of the parts (a copy)."""
    return self._arrays(physics).xpos[self._body_rows].copy()

  def part_quaternions(self, physics):
    """(parts, 4) world orientations of the parts, w x y z (a copy)."""
    return self._arrays(physics).xquat[self._body_rows].copy()

  def part_poses(self, physics):
    """World positions (n, 3) and rotation matrices (n, 3, 3) of all parts."""
    data = physics.data
    return data.xpos[self._body_ids], data.xmat[self._body_ids].reshape(-1, 3, 3)


class FurnitureObservables(composer.Observables):
  """Part positions and orientations in the world frame."""

  @composer.observable
  def part_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.part_positions)

  @composer.observable
  def part_quaternions(self):
    return mujoco_arrays.FreshGeneric(self._entity.part_quaternions)
