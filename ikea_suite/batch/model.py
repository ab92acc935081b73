"""The MuJoCo model of the batched task: the furniture file's parts, its floor, grip targets
and every weld declared up front, with the one physics configuration.

Built with MjSpec from the same model file `ikea_suite.load` reads; then
`physics_settings.configure_model` applies the option block, contact and weld
parameters, exactly as for every other tool that simulates a model file.

Differences from the CPU environment's compiled model, and why:
- Visual-only geoms (contype = conaffinity = 0) and their meshes are dropped:
  they carry no mass (density 0) and no contact, and MJX would carry them.
- Collision: parts collide with the floor, never with each other. MJX's
  collision filter (contype/conaffinity, excludes) belongs to the model and
  cannot differ between worlds, while the CPU task turns collisions off
  between parts as they join. A fixed scheme has to choose; this one keeps
  joined groups (which overlap at their joints by design) stable and makes
  the pair count, hence the cost, linear in the parts. Consequence: parts
  pass through one another; nothing stacks on another part.
- The cursors are not bodies: a cursor is a pose in the task state, and each
  has a mocap body placed at the target pose of the part it holds. The grip
  weld (mocap -> part, identity pose) is switched on per world; the CPU
  cursor's world -> part weld with the target written into eq_data is the
  same constraint, with the same solref.
"""

import dataclasses

import mujoco
import numpy as np

from ikea_suite import physics_settings
from ikea_suite.batch import weld_table as weld_table_lib
from ikea_suite.props import catalog
from ikea_suite.props import connector_table
from ikea_suite.props import model_format
from ikea_suite.robots import cursor as cursor_lib

NUM_CURSORS = cursor_lib.NUM_CURSORS
PART_CONTYPE, PART_CONAFFINITY = 1, 2    # parts: floor yes (floor has 2/1), parts no
FLOOR_CONTYPE, FLOOR_CONAFFINITY = 2, 1
FLOOR_FRICTION = (0.9, 0.005, 0.0001)    # as arenas/floor.py's floor


@dataclasses.dataclass(frozen=True)
class BatchModel:
  """A compiled model and the index tables the batched task reads.

  Attributes:
    model: the mujoco.MjModel (CPU), to hand to mjx.put_model.
    spec: the furniture's FurnitureSpec.
    table: its ConnectorTable (candidate pairs).
    welds: the WeldTable; weld w is equality `weld_eq[w]`.
    part_qpos: (parts,) qpos address of each part's free joint.
    part_dof: (parts,) dof address of each part's free joint.
    grip_eq: (cursors, parts) equality id of cursor i's grip on part j.
    weld_eq: (welds,) equality id of each declared weld.
    geom_part, geom_pos, geom_rot, geom_center, geom_half: per collision geom of a part,
      its part, pose in the part frame, bounding-box centre and half size (geom frame);
      the Cursor's grasp_margin option (batch/settings.py) widens them for grabbing.
  """
  model: mujoco.MjModel
  spec: object
  table: connector_table.ConnectorTable
  welds: weld_table_lib.WeldTable
  part_qpos: np.ndarray
  part_dof: np.ndarray
  grip_eq: np.ndarray
  weld_eq: np.ndarray
  geom_part: np.ndarray
  geom_pos: np.ndarray
  geom_rot: np.ndarray
  geom_center: np.ndarray
  geom_half: np.ndarray

  @property
  def num_parts(self):
    return len(self.spec.parts)


def _strip_visuals(mj_spec, part_names):
  visual = [g for g in mj_spec.geoms
            if g.parent.name in part_names and g.contype == 0 and g.conaffinity == 0]
  for geom in visual:
    mj_spec.delete(geom)
  used = {g.meshname for g in mj_spec.geoms if g.type == mujoco.mjtGeom.mjGEOM_MESH}
  for mesh in [m for m in mj_spec.meshes if m.name not in used]:
    mj_spec.delete(mesh)


def _set_collision_bits(mj_spec, part_names):
  for geom in mj_spec.geoms:
    if geom.parent.name in part_names:
      geom.contype, geom.conaffinity = PART_CONTYPE, PART_CONAFFINITY
    elif geom.type == mujoco.mjtGeom.mjGEOM_PLANE:
      geom.contype, geom.conaffinity = FLOOR_CONTYPE, FLOOR_CONAFFINITY
      geom.friction = FLOOR_FRICTION


def build(furniture):
  """Compiles the batched task's model of `furniture`.

  Args:
    furniture: a catalog name or a path to a furniture model file.

  Returns:
    A BatchModel.
  """
  spec = catalog.spec(furniture)
  table = connector_table.ConnectorTable(spec)
  welds = weld_table_lib.build(table)
  part_names = [p.name for p in spec.parts]
  mj_spec = mujoco.MjSpec.from_string(model_format.to_xml(spec.document))
  for eq in list(mj_spec.equalities):   # the file's design welds; ours are declared below
    mj_spec.delete(eq)
  _strip_visuals(mj_spec, set(part_names))
  _set_collision_bits(mj_spec, set(part_names))
  for i in range(NUM_CURSORS):
    mj_spec.worldbody.add_body(name=f"grip_target{i}", mocap=True,
                               pos=cursor_lib.HOME_POSITIONS[i])
  for i in range(NUM_CURSORS):
    for name in part_names:
      mj_spec.add_equality(type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                           name=f"grip{i}_{name}", name1=f"grip_target{i}", name2=name,
                           active=False)
  for w in range(welds.num_welds):
    mj_spec.add_equality(type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                         name=f"part_weld_{w}", name1=part_names[welds.body1[w]],
                         name2=part_names[welds.body2[w]], active=False)
  model = mj_spec.compile()
  physics_settings.configure_model(model)
  model.opt.timestep = physics_settings.TIMESTEP
  ids = lambda kind, names: np.array([mujoco.mj_name2id(model, kind, n) for n in names], dtype=int)
  grip_eq = ids(mujoco.mjtObj.mjOBJ_EQUALITY,
                [f"grip{i}_{n}" for i in range(NUM_CURSORS) for n in part_names]).reshape(
                    NUM_CURSORS, -1)
  weld_eq = ids(mujoco.mjtObj.mjOBJ_EQUALITY, [f"part_weld_{w}" for w in range(welds.num_welds)])
  # Grip welds: the cursor's soft grip, identity pose (the mocap body is the part's target).
  model.eq_solref[grip_eq.ravel()] = physics_settings.CURSOR_GRIP_SOLREF
  model.eq_solimp[grip_eq.ravel()] = mujoco.MjModel.from_xml_string(
      "<mujoco><worldbody><body name='a'/></worldbody><equality><weld body1='a'/></equality>"
      "</mujoco>").eq_solimp[0]
  model.eq_data[grip_eq.ravel()] = 0.0
  model.eq_data[grip_eq.ravel(), 6] = 1.0
  model.eq_data[grip_eq.ravel(), 10] = 1.0   # MJCF's default torquescale
  # Part welds: their fixed relative pose, then physics_settings' torquescale (kept).
  model.eq_data[weld_eq, :3] = 0.0
  model.eq_data[weld_eq, 3:6] = welds.relpos
  model.eq_data[weld_eq, 6:10] = welds.relquat
  bodies = ids(mujoco.mjtObj.mjOBJ_BODY, part_names)
  joints = model.body_jntadr[bodies]
  part_of_body = {int(b): i for i, b in enumerate(bodies)}
  geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] in part_of_body
           and (model.geom_contype[g] or model.geom_conaffinity[g])]
  rot = np.array([_quat_mat(model.geom_quat[g]) for g in geoms])
  return BatchModel(
      model=model, spec=spec, table=table, welds=welds,
      part_qpos=model.jnt_qposadr[joints].copy(), part_dof=model.jnt_dofadr[joints].copy(),
      grip_eq=grip_eq, weld_eq=weld_eq,
      geom_part=np.array([part_of_body[int(model.geom_bodyid[g])] for g in geoms], dtype=int),
      geom_pos=model.geom_pos[geoms].copy(), geom_rot=rot,
      geom_center=model.geom_aabb[geoms, :3].copy(),
      geom_half=model.geom_aabb[geoms, 3:].copy())


def _quat_mat(quat):
  out = np.empty(9)
  mujoco.mju_quat2Mat(out, np.asarray(quat, dtype=float))
  return out.reshape(3, 3)
