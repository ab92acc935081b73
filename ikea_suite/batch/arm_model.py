"""The MuJoCo model of the batched task for a single arm (arm_env.ROBOTS): the CPU environment's
own compiled scene, adapted for MJX.

Built from `ikea_suite.load(furniture, robot)`: the same furniture at the arm's work
scale (config.ArmConfig.WORK_SCALE), the same arena, the robot's MJCF, actuators and
gripper, and the physics configuration the CPU task applies after compiling
(physics_settings: contact, support and pad parameters, weld parameters, the time
step). Its MJCF is recompiled once with the changes below, and every compiled
per-geom, per-actuator and option value of the CPU model is copied over, so the two
models differ only where listed.

Differences from the CPU environment's compiled model, and why:
- Visual-only geoms (contype = conaffinity = 0) and meshes no kept geom uses are
  dropped: they carry no contact (parts' visual geoms no mass either) and MJX would
  carry them through every step.
- Collision: parts collide with the floor and the robot, never with each other. MJX's
  collision filter belongs to the model and cannot differ between worlds, while the CPU
  task turns collisions off between parts only as they join (see batch/model.py, which
  makes the same choice for the Cursor). Consequence: a carried part passes through
  the others.
- Welds: the CPU task's one weld per part pair takes the relative pose measured at the
  snap; MJX keeps a weld's pose in the model, shared by all worlds, so one weld per
  (candidate connector pair, allowed twist) is declared with its exact mated pose
  (batch/weld_table.py), as the Cursor's batched model does. Welds keep the CPU's
  solref, solimp and torquescale.
- MJX's JAX implementation (not Warp), which computes every collision pair of the
  model on every step with no broad phase and lacks cylinder-box and
  cylinder-capsule collisions, gets a lighter collision model (`light=True`): every
  collision cylinder becomes a capsule of the same radius and overall length, and
  only the gripper (the hand and fingers) collides; the arm's links touch nothing. With
  the full set a step of two worlds took 28 s on the 2-core development machine and
  its compile 7 minutes. The Warp implementation keeps the CPU's geometry and
  collisions.
- The wrist camera and the arena's cameras stay in the model but are never rendered.
"""

import dataclasses

import mujoco
import numpy as np
from dm_control import mjcf

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.batch import model as model_lib
from ikea_suite.batch import weld_table as weld_table_lib
from ikea_suite.props import model_format
from ikea_suite.tasks import arm_placement
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner

# Parts carry this collision type and every bit but it in their affinity: they touch the
# floor and the robot (default bits) and never one another.
PART_BIT = 1 << 30
_ALL = (1 << 31) - 1
DEFAULT_LAYOUTS = 32
LIFT_CLEARANCE = 0.001   # m between a turned-over group's lowest corner and the floor

_GEOM_FIELDS = ("contype", "conaffinity", "condim", "solref", "solimp", "solmix", "friction",
                "margin", "gap", "priority")
_ACTUATOR_FIELDS = ("gainprm", "biasprm", "dynprm", "ctrlrange", "forcerange", "gear",
                    "ctrllimited", "forcelimited")


@dataclasses.dataclass(frozen=True)
class ArmBatchModel:
  """The compiled arm scene and the index tables the batched arm task reads.

  Attributes:
    base: a model.BatchModel of the same scene (parts, connector table, welds, part
      collision boxes; grip_eq is -1 throughout: an arm holds parts by friction, not
      by a grip weld), for the tables and connect code the Cursor's batched task shares.
    arm_qpos, arm_dof, arm_act: (joints,) qpos / dof addresses and actuator ids of the arm.
    finger_qpos, finger_act: (fingers,) qpos addresses and actuator ids of the gripper.
    finger_body: (fingers,) body ids of the finger bodies.
    tcp_site: site id of the tool-centre point.
    ik_low, ik_high: (joints,) joint ranges the task-space IK keeps in (the CPU IK's, with
      the robot's IK_WORKING_RANGES).
    joint_low, joint_high: (joints,) physical joint ranges (joint_position mode).
    home_qpos: (nq,) robot at home, parts as in the CPU model's default.
    home_ctrl: (nu,) actuator targets at home (fingers open).
    open_qpos, squeeze_qpos, closed_qpos: (fingers,) gripper finger targets and limits.
    home_tcp_pos, home_tcp_rot: world pose of the tool at home.
    workspace: (2, 3) world box the task-space target is kept in.
    max_translation, max_rotation: task-space action scales (m, rad per step at 1).
    velocity_limit: rad/s per joint in the IK.
    robot_config: the robot's resolved config; task_config: the task's resolved config.
    layouts: Layouts, the CPU task's episode starts the batched resets draw from.
    cpu_env: the CPU environment the model was taken from (its MJCF tree is modified:
      use it only as a reference for its model's values).
  """
  base: model_lib.BatchModel
  arm_qpos: np.ndarray
  arm_dof: np.ndarray
  arm_act: np.ndarray
  finger_qpos: np.ndarray
  finger_act: np.ndarray
  finger_body: np.ndarray
  tcp_site: int
  ik_low: np.ndarray
  ik_high: np.ndarray
  joint_low: np.ndarray
  joint_high: np.ndarray
  home_qpos: np.ndarray
  home_ctrl: np.ndarray
  open_qpos: np.ndarray
  squeeze_qpos: np.ndarray
  closed_qpos: np.ndarray
  home_tcp_pos: np.ndarray
  home_tcp_rot: np.ndarray
  workspace: np.ndarray
  max_translation: float
  max_rotation: float
  velocity_limit: float
  robot_config: object
  task_config: object
  layouts: "Layouts"
  cpu_env: object

  @property
  def model(self):
    return self.base.model

  @property
  def num_parts(self):
    return self.base.num_parts


@dataclasses.dataclass(frozen=True)
class Layouts:
  """Episode starts made by the CPU task's initializer (tasks/arm_placement.py), one per
  CPU reset: parts within the arm's reach, preassembled pairs joined and welded.

  Attributes:
    part_qpos: (layouts, parts, 7) part positions and quaternions.
    group: (layouts, parts) group label per part.
    connector_used: (layouts, connectors) bool.
    adjacency: (layouts, parts, parts) bool.
    eq_active: (layouts, neq) bool, the declared welds on (one per joined part pair).
  """
  part_qpos: np.ndarray
  group: np.ndarray
  connector_used: np.ndarray
  adjacency: np.ndarray
  eq_active: np.ndarray

  def __len__(self):
    return len(self.part_qpos)


def _record_layouts(env, count):
  """(part qpos, group, used, adjacency, connector pairs joined) of `count` CPU resets."""
  task = env.task
  frames = task.furniture.part_frames
  out = []
  for _ in range(count):
    env.reset()
    physics = env.physics   # composer may recompile at a reset
    joints = physics.model.body_jntadr[np.array(physics.bind(frames).element_id)]
    addr = physics.model.jnt_qposadr[joints][:, None] + np.arange(7)
    state = task.state
    out.append((physics.data.qpos[addr].copy(), state.group_labels().copy(),
                state.connector_used.copy(), state.adjacency.astype(bool),
                list(state.connections) + list(state.closures)))
  return out


def _last_part_from_above(spec, table, group, pos, rot):
  """With one part loose and the root (tasks/planner.root_part) in the joined group, the
  group turned over about the world x axis through its centre and set on the floor when
  the CPU placement lays the root alone turned over (its mates attach from below:
  tasks/arm_placement.mates_from_below), so that the group lies as the root would and the
  last part goes in from above: a table's or stool's last leg (upright, a three-legged
  table tips over onto the missing leg's corner), a bench's end or stretcher, which the
  panel rack stands the way up it mates onto the turned-over seat
  (tasks/panel_placement.upright_panels). Other layouts are returned as they are."""
  labels, counts = np.unique(group, return_counts=True)
  if len(labels) != 2 or counts.min() != 1:
    return pos, rot
  loose = int(np.flatnonzero(group == labels[np.argmin(counts)])[0])
  members = np.flatnonzero(group != group[loose])
  root = planner.root_part(spec)
  rest = placement.resting_rotation(spec.parts[root].bounds)
  if root == loose or not arm_placement.mates_from_below(spec, table, root, rest):
    return pos, rot
  flip = np.diag([1.0, -1.0, -1.0])
  centre = pos[members].mean(0)
  pos, rot = pos.copy(), rot.copy()
  pos[members] = centre + (pos[members] - centre) @ flip.T
  rot[members] = flip @ rot[members]
  lowest = np.inf
  for i in members:
    lo, hi = np.asarray(spec.parts[i].bounds, dtype=float)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    lowest = min(lowest, (pos[i] + corners @ rot[i].T)[:, 2].min())
  pos[members, 2] += LIFT_CLEARANCE - lowest
  return pos, rot


def _layouts(records, table, welds, weld_eq, neq, spec=None):
  """Layouts with each joined part pair's declared weld on, at the twist slot nearest the
  pair's measured twist (as batch/scripted.py preassembles)."""
  from ikea_suite.tasks import alignment
  pair_of = {(int(a), int(b)): k for k, (a, b) in enumerate(zip(table.pair_a, table.pair_b))}
  rows = []
  for qpos, group, used, adjacency, joined in records:
    pos = qpos[:, :3]
    rot = np.array([model_lib._quat_mat(q) for q in qpos[:, 3:]])
    if spec is not None:
      pos, rot = _last_part_from_above(spec, table, group, pos, rot)
      qpos = np.concatenate([pos, [geometry.mat_to_quat(r) for r in rot]], axis=1)
    twist = alignment.align_pairs(*table.world_frames(pos, rot), table).twist
    active = np.zeros(neq, dtype=bool)
    welded = set()
    for a, b in joined:
      k = pair_of.get((int(a), int(b)), pair_of.get((int(b), int(a))))
      parts = tuple(sorted((int(table.part[a]), int(table.part[b]))))
      if k is None or parts in welded:
        continue
      welded.add(parts)
      valid = welds.twist_valid[k]
      slot = int(np.argmax(np.where(valid, np.cos(welds.twist_angles[k] - twist[k]), -np.inf)))
      active[weld_eq[welds.weld_of[k, slot]]] = True
    rows.append((qpos, group, used, adjacency, active))
  return Layouts(*(np.array(x) for x in zip(*rows)))


def _lighten(kept, types, sizes, robot_root, gripper_root):
  """The light collision model in place: cylinders as capsules, only the gripper's geoms
  colliding on the robot. `types` and `sizes` are the kept geoms' compiled values (a geom
  may take its type and size from a default class: the Jaco's joint rings). Returns the
  geoms switched off."""
  # find_all crosses attachments: the Jaco's hand is a model attached to its arm's.
  robot = {id(g) for g in robot_root.find_all("geom")}
  gripper = set()
  stack = [gripper_root]
  while stack:
    body = stack.pop()
    gripper.update(id(g) for g in body.find_all("geom", immediate_children_only=True))
    stack.extend(body.find_all("body", immediate_children_only=True))
  off = []
  for geom, kind, size in zip(kept, types, sizes):
    if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
      size = np.asarray(size, dtype=float)
      if geom.fromto is not None:
        ends = np.asarray(geom.fromto, dtype=float).reshape(2, 3)
        axis = ends[1] - ends[0]
        length = np.linalg.norm(axis)
        shrink = min(size[0], length / 2 - 1e-6) / max(length, 1e-12)
        geom.fromto = np.concatenate([ends[0] + shrink * axis, ends[1] - shrink * axis])
        geom.size = [size[0]]
      else:
        geom.size = [size[0], max(size[1] - size[0], 1e-6)]
      geom.type = "capsule"
    if id(geom) in robot and id(geom) not in gripper:
      off.append(geom)
  return off


def _world_box(box, base_pos, base_rot):
  lo, hi = np.asarray(box[0], float), np.asarray(box[1], float)
  corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                      for z in (lo[2], hi[2])])
  world = corners @ base_rot.T + base_pos
  return np.stack([world.min(0), world.max(0)])


def build(furniture, robot="panda", layouts=DEFAULT_LAYOUTS, light=False, layout_seed=0,
          **options):
  """Compiles the batched arm task's model of `furniture`.

  Args:
    furniture: a catalog name or a path to a furniture model file.
    robot: a single-arm robot name.
    layouts: CPU resets recorded as the batched resets' starts.
    layout_seed: the seed of the CPU environment whose resets are recorded: other seeds,
      other starts.
    light: the light collision model (for MJX's JAX implementation; see above).
    **options: ikea_suite.load's options for the CPU environment the model is taken from.

  Returns:
    An ArmBatchModel.
  """
  import ikea_suite   # the suite's load() sits above batch in the package
  env = ikea_suite.load(furniture, robot, seed=layout_seed, **options)
  records = _record_layouts(env, layouts)
  env.reset()
  task, physics = env.task, env.physics
  robot_entity, furniture_prop = task.robot, task.furniture
  arm = robot_entity.arms[0]
  root = task.root_entity.mjcf_model
  old_model = physics.model
  # Compiled values of what stays, read before the tree changes.
  geoms = [g for g in root.find_all("geom")]
  bound = physics.bind(geoms)
  visual = (np.asarray(bound.contype) == 0) & (np.asarray(bound.conaffinity) == 0)
  kept = [g for g, v in zip(geoms, visual) if not v]
  kept_values = {f: np.array(getattr(physics.bind(kept), f)) for f in _GEOM_FIELDS}
  act_values = {f: np.array(getattr(old_model, f"actuator_{f}")) for f in _ACTUATOR_FIELDS}
  # Meshes by the compiled model's ids: a geom may take its mesh from a default class
  # (the Jaco hand's fingers), so its `mesh` attribute can be empty while it uses one.
  kept_bound = physics.bind(kept)
  used = set(np.asarray(kept_bound.dataid)[
      np.asarray(kept_bound.type) == mujoco.mjtGeom.mjGEOM_MESH].tolist())
  meshes = root.find_all("mesh")
  mesh_ids = np.asarray(physics.bind(meshes).element_id) if meshes else []
  for geom, is_visual in zip(geoms, visual):
    if is_visual:
      geom.remove()
  for mesh, mesh_id in zip(meshes, mesh_ids):
    if int(mesh_id) not in used:
      mesh.remove()
  switched_off = (_lighten(kept, np.asarray(kept_bound.type), np.array(kept_bound.size),
                          robot_entity.mjcf_model, arm.gripper.root_body) if light else [])
  for weld in root.find_all("equality"):
    if weld.tag == "weld" and (weld.name or "").startswith("part_weld_"):
      weld.remove()
  spec = furniture_prop.spec
  table = furniture_prop.connectors
  welds = weld_table_lib.build(table)
  frames = furniture_prop.part_frames
  weld_elements = [root.equality.add(
      "weld", name=f"batch_weld_{w}", body1=frames[welds.body1[w]], body2=frames[welds.body2[w]],
      active=False, solref=physics_settings.WELD_SOLREF, solimp=physics_settings.WELD_SOLIMP,
      torquescale=physics_settings.WELD_TORQUESCALE) for w in range(welds.num_welds)]
  new = mjcf.Physics.from_mjcf_model(root)
  model = new.model.ptr
  for field, values in kept_values.items():
    setattr(new.bind(kept), field, values)
  bodies = np.array(new.bind(frames).element_id, dtype=int)
  part_geom_ids, _ = model_format.collision_geoms(model, bodies)
  part_geom_ids = np.asarray(part_geom_ids, dtype=int)
  if switched_off:
    new.bind(switched_off).contype = 0
    new.bind(switched_off).conaffinity = 0
  model.geom_contype[part_geom_ids] = PART_BIT
  model.geom_conaffinity[part_geom_ids] = _ALL & ~PART_BIT
  for field, values in act_values.items():
    getattr(model, f"actuator_{field}")[:] = values
  model.opt.timestep = old_model.opt.timestep
  model.opt.integrator, model.opt.cone = old_model.opt.integrator, old_model.opt.cone
  model.opt.impratio = old_model.opt.impratio
  weld_eq = np.array(new.bind(weld_elements).element_id, dtype=int)
  model.eq_data[weld_eq, :3] = 0.0
  model.eq_data[weld_eq, 3:6] = welds.relpos
  model.eq_data[weld_eq, 6:10] = welds.relquat
  model.eq_data[weld_eq, 10] = physics_settings.WELD_TORQUESCALE
  # Index tables.
  joints = model.body_jntadr[bodies]
  part_of_body = {int(b): i for i, b in enumerate(bodies)}
  rot = np.array([model_lib._quat_mat(model.geom_quat[g]) for g in part_geom_ids])
  base = model_lib.BatchModel(
      model=model, spec=spec, table=table, welds=welds,
      part_qpos=model.jnt_qposadr[joints].copy(), part_dof=model.jnt_dofadr[joints].copy(),
      grip_eq=np.full((model_lib.NUM_CURSORS, len(frames)), -1, dtype=int), weld_eq=weld_eq,
      geom_part=np.array([part_of_body[int(model.geom_bodyid[g])] for g in part_geom_ids],
                         dtype=int),
      geom_pos=model.geom_pos[part_geom_ids].copy(), geom_rot=rot,
      geom_center=model.geom_aabb[part_geom_ids, :3].copy(),
      geom_half=model.geom_aabb[part_geom_ids, 3:].copy())
  arm_joints = new.bind(arm.joints)
  finger_joints = new.bind(arm.gripper.joints)
  ik_index = robot_entity.ik_joint_indices(0)
  ik_low, ik_high = (b[robot_entity.ik.qpos_index[ik_index]] for b in robot_entity.ik.limits)
  joint_low, joint_high = robot_entity.joint_limits(0)
  # Home: the CPU env's state after reset (robot at home, fingers open).
  home_qpos = np.array(model.qpos0)
  old_arm = physics.bind(arm.joints)
  old_fingers = physics.bind(arm.gripper.joints)
  home_qpos[np.array(arm_joints.qposadr)] = physics.data.qpos[np.array(old_arm.qposadr)]
  home_qpos[np.array(finger_joints.qposadr)] = physics.data.qpos[np.array(old_fingers.qposadr)]
  home_ctrl = np.zeros(model.nu)
  arm_act = np.array(new.bind(arm.actuators).element_id, dtype=int)
  finger_act = np.array(new.bind(arm.gripper.actuators).element_id, dtype=int)
  home_ctrl[arm_act] = physics.data.ctrl[np.array(physics.bind(arm.actuators).element_id)]
  home_ctrl[finger_act] = physics.data.ctrl[np.array(physics.bind(arm.gripper.actuators).element_id)]
  tcp_pos, tcp_rot = robot_entity.home_tcp_poses()[0]
  base_pos, base_rot = robot_entity.base_pose
  rc = robot_entity.config
  return ArmBatchModel(
      base=base, arm_qpos=np.array(arm_joints.qposadr, dtype=int),
      arm_dof=np.array(arm_joints.dofadr, dtype=int), arm_act=arm_act,
      finger_qpos=np.array(finger_joints.qposadr, dtype=int), finger_act=finger_act,
      finger_body=np.array(new.bind([j.parent for j in arm.gripper.joints]).element_id, dtype=int),
      tcp_site=int(new.bind(arm.gripper.tcp_site).element_id),
      ik_low=np.asarray(ik_low, float), ik_high=np.asarray(ik_high, float),
      joint_low=np.asarray(joint_low, float), joint_high=np.asarray(joint_high, float),
      home_qpos=home_qpos, home_ctrl=home_ctrl,
      open_qpos=np.asarray(arm.gripper.open_qpos, float),
      squeeze_qpos=np.asarray(arm.gripper.squeeze_qpos, float),
      closed_qpos=np.asarray(arm.gripper.closed_qpos, float),
      home_tcp_pos=np.asarray(tcp_pos, float), home_tcp_rot=np.asarray(tcp_rot, float),
      workspace=_world_box(arm.workspace, base_pos, base_rot),
      max_translation=float(rc.max_translation), max_rotation=float(rc.max_rotation),
      velocity_limit=float(type(robot_entity).VELOCITY_LIMIT), robot_config=rc,
      task_config=task.config,
      layouts=_layouts(records, table, welds, weld_eq, model.neq, spec), cpu_env=env)
