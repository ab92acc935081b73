"""The common body of every arm robot: actuators per control mode, IK, observables, reset.

A subclass builds its MJCF in `_build_body` and returns one `Arm` per arm.
Everything else (action spec, control modes, wrist cameras, the part
placement the robot can reach) is shared. Controls and targets are set once per
control step in `apply_action`; MuJoCo's actuators (arm_actuators) act on them
during the substeps, so no Python runs per physics substep."""

import copy
import dataclasses

import mujoco
import numpy as np
from dm_control import composer
from dm_control.composer.observation import observable

from ikea_suite import config as config_lib
from ikea_suite import geometry
from ikea_suite import mujoco_arrays
from ikea_suite import physics_settings
from ikea_suite.robots import arm_actuators
from ikea_suite.robots import base
from ikea_suite.robots import control_modes
from ikea_suite.robots import grippers
from ikea_suite.robots import ik

_HOME_CACHE = {}


@dataclasses.dataclass
class Arm:
  """What an arm robot's `_build_body` returns per arm: its joints, gripper, camera and home."""
  prefix: str                 # action-name prefix: "" or "right_" / "left_"
  joints: list                # joint elements, base to wrist
  torque_limits: np.ndarray   # N m per joint
  gripper: grippers.GripperParts
  camera: object              # wrist camera element
  seed: np.ndarray            # joint angles near the home pose, refined by IK
  home_tcp: np.ndarray        # home tool-centre point in the base frame
  workspace: np.ndarray       # (2, 3) box in the base frame the tool is kept in
  impedance_target: object = None   # the target site of impedance mode (arm_actuators)


def single_arm(root, elements, limits, joints, gripper_spec, seed, home_tcp, workspace_box):
  """The one Arm of a single-arm robot whose joints, hand and camera follow the sheets' names."""
  gripper = grippers.build(elements["right_hand"], gripper_spec, prefix="right_")
  return Arm(
      prefix="", joints=[root.find("joint", j) for j in joints],
      torque_limits=np.array([limits[j][1] for j in joints]), gripper=gripper,
      camera=root.find("camera", "eye_in_hand"), seed=np.array(seed),
      home_tcp=np.array(home_tcp), workspace=np.array(workspace_box))


def home_footprint(model, home_q, base_height):
  """The robot at its home pose seen from above, for the part placement (base.ReachZone).

  Measured on the robot's own compiled model, whose world frame is the base frame: a
  Baxter's arms hang at home over the band where parts lie, and its forearms touched a
  0.78 m panel standing in the rack there (tv_unit_open_dark_long at scale 0.5), so the
  placement keeps clear of every collision geom where it stands at home, not only of the
  torso.

  Args:
    model: the robot's compiled mujoco.MjModel (robots.ik.DifferentialIK.model).
    home_q: its qpos at the home pose.
    base_height: world z (m) of the base.
  Returns:
    (geoms, 5) array: per collision geom, the (x low, y low, x high, y high) corners (m) of
    its bounding box in the base frame, and the world z (m) of its lowest point.
  """
  data = mujoco.MjData(model)
  data.qpos[:] = home_q
  mujoco.mj_kinematics(model, data)
  rows = []
  for g in np.flatnonzero((model.geom_contype != 0) | (model.geom_conaffinity != 0)):
    centre, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
    corners = (geometry.box_corners(centre - half, centre + half)
               @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g])
    rows.append([*corners[:, :2].min(0), *corners[:, :2].max(0),
                 base_height + corners[:, 2].min()])
  return np.array(rows).reshape(-1, 5)


class Manipulator(base.Robot):
  """An arm robot on a fixed base; see control_modes for the action of each mode.

  The placement figures say where the task lays the parts (the band and sector around the
  base, `reach_zone`); a robot overrides those its own reach calls for (robots/baxter.py).
  """

  DEFAULT_NAME = "manipulator"
  # The arm's load() options (base_pos: the world position of its base, facing +x); each
  # arm's subclass of config.ArmConfig sets its own base position.
  CONFIG = config_lib.ArmConfig
  REACH = 0.85                   # metres from the base where parts are placed
  # Metres from the base inside which no part is placed: an arm pointing down cannot
  # reach right beside itself.
  PLACEMENT_INNER = 0.55
  # Metres out to the centre of the part built onto (more for a wide one): a held part mated
  # nearer the base folds the elbow into it (measured with the Sawyer at 0.4 m).
  ROOT_DISTANCE = 0.45
  # Parts lie within this angle either side of the base's heading (rad).
  PLACEMENT_SECTOR = np.radians(110)
  # (bearing, metres): parts beyond that bearing may lie out that far (base.ReachZone).
  PLACEMENT_SIDE_REACH = None
  KP_PER_NM = 10.0               # position gain per N m of torque limit
  VELOCITY_LIMIT = 2.0           # rad/s per joint in the IK
  # {arm joint index: (low, high) rad} the task-space IK keeps within, inside the physical
  # limits (joint modes keep those), so the redundant arm stays on one branch: over a few
  # carries differential IK can wind it into a flipped one, base joint at its limit, from
  # which most of the work area is out of reach though it was reachable from home.
  IK_WORKING_RANGES = {}

  def _build(self, name=None, config=None, mount_height=0.0, **options):
    """Builds the arm.

    Args:
      name: the MJCF model name (default DEFAULT_NAME).
      config: the arm's options (its CONFIG; None: the defaults), with any of them given as
        keywords replacing its values.
      mount_height: how far (m) the base is raised above base_pos: the work table's
        pedestal (arenas/work_table.py), so base_pos's z is measured from the table top.
    """
    self._config = config = self.CONFIG.of(config, **options)
    self._mode = config.control_mode
    max_translation, max_rotation = config.max_translation, config.max_rotation
    self._base_pos = np.array(config.base_pos, dtype=float)
    if mount_height:
      self._base_pos = self._base_pos + [0.0, 0.0, mount_height]
    self._base_rot = geometry.rot_z(config.base_yaw)
    wrist_camera, camera_size = config.wrist_camera, config.camera_size
    self._mjcf_root, self._arms = self._build_body(name or self.DEFAULT_NAME)
    stiffness = config.impedance_stiffness
    tcp_sites = [arm.gripper.tcp_site for arm in self._arms]
    arm_joints = [j for arm in self._arms for j in arm.joints]
    working = {arm.joints[j]: r for arm in self._arms for j, r in self.IK_WORKING_RANGES.items()}
    self._ik = ik.DifferentialIK(self._mjcf_root, tcp_sites, arm_joints, self.VELOCITY_LIMIT,
                                 working_ranges=working)
    self._home_q = self._home_configuration()
    self._home_footprint = home_footprint(self._ik.model, self._home_q, self._base_pos[2])
    self._ik.set_posture(self._home_q)
    self._home_rot = [rot for _, rot in self._ik.tcp_poses(self._home_q)]
    # Arm actuators after the home pose, which impedance's posture spring pulls towards
    # (the IK's own compiled model moves no actuator and needs none).
    for arm in self._arms:
      home = self._home_q[self._ik.qpos_index[[list(self._ik.joints).index(j) for j in arm.joints]]]
      arm.actuators = arm_actuators.add(self._mjcf_root, arm, self._mode, self.KP_PER_NM,
                                        arm.joints[0].parent.parent, home, stiffness)
    boxes = [self._box_to_world(arm.workspace) for arm in self._arms]
    self._targets = control_modes.TaskSpaceTargets(len(self._arms), max_translation,
                                                    max_rotation, boxes)
    # The same pose as Python floats, for the task-space targets' per-step frame change.
    self._base_pos_floats = self._base_pos.tolist()
    self._base_rot_floats = self._base_rot.reshape(9).tolist()
    self._dt = 0.05   # the control step (s), which bounds each IK step's joint speeds
    self._wrist_camera, self._camera_size = bool(wrist_camera), tuple(camera_size)
    self._episodes_started = False

  def _build_body(self, name):
    """Returns (mjcf root, [Arm]) of the robot without arm actuators."""
    raise NotImplementedError

  def _home_configuration(self):
    key = (type(self).__name__, self._mjcf_root.model)
    if key not in _HOME_CACHE:
      q = np.zeros(self._ik.model.nq)
      for arm in self._arms:
        index = np.array([list(self._ik.joints).index(j) for j in arm.joints])
        q[self._ik.qpos_index[index]] = arm.seed
        for joint, value in zip(arm.gripper.joints, arm.gripper.open_qpos):
          q[self._ik.qpos_index[list(self._ik.joints).index(joint)]] = value
      self._ik.set_posture(q)
      # Home: tool pointing down at home_tcp, wrist turned as in the seed pose.
      targets = [(arm.home_tcp, geometry.pointing_down(rot))
                 for arm, (_, rot) in zip(self._arms, self._ik.tcp_poses(q))]
      _HOME_CACHE[key] = self._ik.solve(self._ik.clip_to_limits(q), targets)
    return _HOME_CACHE[key].copy()

  def _box_to_world(self, box):
    corners = geometry.box_corners(box[0], box[1])
    world = corners @ self._base_rot.T + self._base_pos
    return np.stack([world.min(0), world.max(0)])

  # -- robot interface -----------------------------------------------------------

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def control_mode(self):
    """The control mode given at construction (robots.control_modes)."""
    return self._mode

  @property
  def max_translation(self):
    """Metres the task-space target moves per control step at a move action of 1."""
    return self._targets.max_translation

  @property
  def max_rotation(self):
    """Radians the task-space target turns per control step at a rotate action of 1."""
    return self._targets.max_rotation

  @property
  def ik(self):
    """The robot's differential IK (ik.DifferentialIK, on its own copy of the arm model)."""
    return self._ik

  @property
  def num_arms(self):
    return len(self._arms)

  @property
  def arms(self):
    return list(self._arms)

  @property
  def cameras(self):
    """Named wrist cameras ("wrist", or "right_wrist" and "left_wrist"), selectable with
    load(cameras=...) for RGB, depth, segmentation and part boxes."""
    return {f"{arm.prefix}wrist": arm.camera for arm in self._arms}

  @property
  def wrist_camera_size(self):
    """(height, width) in pixels of the wrist camera observables, or None when they are off."""
    return self._camera_size if self._wrist_camera else None

  @property
  def base_pose(self):
    """World position and rotation of the robot base."""
    return self._base_pos.copy(), self._base_rot.copy()

  @property
  def action_names(self):
    names = []
    for arm in self._arms:
      joints = [j.name[len(arm.prefix):] if j.name.startswith(arm.prefix) else j.name
                for j in arm.joints]   # Baxter's right_s0 is named once: right_s0_position
      names += [arm.prefix + n for n in control_modes.arm_action_names(self._mode, joints)]
    return names

  @property
  def actions_per_arm(self):
    return len(self._arms[0].joints) + 1 if self._mode in (
        control_modes.JOINT_POSITION, control_modes.JOINT_TORQUE) else 7

  @property
  def reach_zone(self):
    """base.ReachZone: where the task may put parts for this arm (tasks/arm_placement.py)."""
    return base.ReachZone(self._base_pos[:2].copy(), self._base_rot.copy(), float(self.REACH),
                          float(self.PLACEMENT_SECTOR), float(self.PLACEMENT_INNER),
                          float(self.ROOT_DISTANCE), len(self._arms), self.PLACEMENT_SIDE_REACH,
                          self._home_footprint.copy())

  def mount(self, arena):
    frame = arena.attach(self)
    frame.pos = self._base_pos
    frame.quat = geometry.mat_to_quat(self._base_rot)
    return frame

  def bind_scene(self, arena, furniture, assembly, control_timestep):
    self._dt = control_timestep

  def _build_observables(self):
    return ManipulatorObservables(self)

  def after_compile(self, physics, random_state):
    bind = physics.bind
    self._ik_to_qpos = np.array(bind(self._ik.joints).qposadr)
    self._ik_to_dof = np.array(bind(self._ik.joints).dofadr)
    self._arm_qpos = np.array([bind(a.joints).qposadr for a in self._arms])
    self._arm_dof = np.array([bind(a.joints).dofadr for a in self._arms])
    self._arm_ik = np.array([[list(self._ik.joints).index(j) for j in a.joints] for a in self._arms])
    self._arm_act = np.array([bind(a.actuators).element_id for a in self._arms])
    self._finger_qpos = np.array([bind(a.gripper.joints).qposadr for a in self._arms])
    self._finger_act = np.array([bind(a.gripper.actuators).element_id for a in self._arms])
    grips = [a.gripper for a in self._arms]
    opened = np.array([g.open_qpos for g in grips])                  # (arms, fingers)
    travel = np.array([g.squeeze_qpos - g.open_qpos for g in grips])
    closed = np.array([g.closed_qpos for g in grips])
    span = np.array([g.open_qpos - g.closed_qpos for g in grips])
    # Per arm, as Python floats, for the per-step gripper command and opening (a handful of
    # numbers: each numpy call would cost more than its arithmetic).
    self._finger_rows = [list(zip(*rows)) for rows in zip(
        self._finger_qpos.tolist(), closed.tolist(), span.tolist())]
    self._finger_command = [(act, list(zip(*rows))) for act, *rows in zip(
        self._finger_act.tolist(), opened.tolist(), travel.tolist())]
    self._tcp_ids = np.array(bind([a.gripper.tcp_site for a in self._arms]).element_id)
    self._scratch = None   # (model, MjData, the robot's geoms, those behind its hands)
    # What the per-step paths read and write, as kept views and slices where they can be;
    # one assignment writes every arm's joint targets from the IK's joint vector.
    self._arrays = mujoco_arrays.ArrayViews("qpos", "qvel", "ctrl", "site_xpos", "site_xmat")
    self._tcp_rows = mujoco_arrays.compact_index(self._tcp_ids)
    self._ik_qpos_rows = mujoco_arrays.compact_index(self._ik_to_qpos)
    self._arm_act_rows = mujoco_arrays.compact_index(self._arm_act)
    self._arm_from_ik_rows = mujoco_arrays.compact_index(self._ik.qpos_index[self._arm_ik])
    self._arm_qpos_rows = mujoco_arrays.compact_index(self._arm_qpos)
    self._arm_dof_rows = mujoco_arrays.compact_index(self._arm_dof)
    self._finger_bodies = [np.array(bind([j.parent for j in a.gripper.joints]).element_id)
                           for a in self._arms]
    self._finger_table = grippers.finger_of_body(physics, self._finger_bodies)
    ranges = np.array([bind(a.joints).range for a in self._arms])            # (arms, joints, 2)
    limited = np.array([bind(a.joints).limited for a in self._arms]).astype(bool)
    self._joint_low = np.where(limited, ranges[..., 0], -np.pi)
    self._joint_high = np.where(limited, ranges[..., 1], np.pi)
    # After the task's configure_contacts: composer calls the task's hook first.
    if self._mode == control_modes.IMPEDANCE:
      self._impedance = arm_actuators.ImpedanceTargets(
          physics, [a.impedance_target for a in self._arms],
          [a.impedance_target.parent for a in self._arms])
      arm_actuators.critical_damping(physics, self._arm_act.ravel(), self._ik_to_qpos, self._home_q)
    physics_settings.configure_pads(
        physics.model, bind([g for a in self._arms for g in a.gripper.pad_geoms]).element_id)

  def max_physics_timestep(self, physics):
    """The largest physics time step the arm's servos take (arm_actuators.SERVO_STEP_FRACTION
    of a period of the stiffest, at the home pose), and why."""
    ids = np.concatenate([self._arm_act.ravel(), self._finger_act.ravel()])
    omega, actuator = arm_actuators.stiffest_servo(physics, ids, self._ik_to_qpos, self._home_q)
    if actuator < 0:
      return float("inf"), ""
    name = physics.model.id2name(actuator, "actuator")
    return arm_actuators.SERVO_STEP_FRACTION / omega, (
        f"{arm_actuators.SERVO_STEP_FRACTION} / {omega:.0f} rad/s, the natural frequency of "
        f"its stiffest servo ({name}) at home")

  def home_tcp_poses(self):
    """World poses of every tool-centre point at the home configuration."""
    return [(self._base_rot @ p + self._base_pos, self._base_rot @ r)
            for p, r in self._ik.tcp_poses(self._home_q)]

  @property
  def episodes_started(self):
    """Whether an episode has begun (the wrist cameras render only from then on)."""
    return self._episodes_started

  def initialize_episode(self, physics, random_state):
    self._episodes_started = True
    data = physics.data
    data.qpos[self._ik_to_qpos] = self._home_q
    data.qvel[self._ik_to_dof] = 0.0
    for i, arm in enumerate(self._arms):
      home = self._home_q[self._ik.qpos_index[self._arm_ik[i]]]
      data.ctrl[self._arm_act[i]] = home if self._mode in control_modes.POSITION_ACTUATED else 0.0
      data.ctrl[self._finger_act[i]] = arm.gripper.open_qpos
    self._targets.reset(self.home_tcp_poses())
    if self._mode == control_modes.IMPEDANCE:
      self._impedance.place(physics, self._targets.pos, self._targets.rot)

  # -- acting ----------------------------------------------------------------------

  def apply_action(self, physics, action, random_state):
    action = np.ascontiguousarray(action, dtype=float).reshape(len(self._arms), -1)
    arrays = self._arrays(physics)
    if self._mode == control_modes.TASK_SPACE:   # the targets move by the action, then IK
      self._targets.apply_deltas(action, arrays.site_xpos[self._tcp_rows])
      self._track_task_space(arrays)
    elif self._mode == control_modes.TASK_SPACE_POSE:
      for i in range(len(self._arms)):
        self._targets.apply_pose(i, action[i], self._base_rot @ self._home_rot[i])
      self._track_task_space(arrays)
    elif self._mode == control_modes.IMPEDANCE:   # springs pull the tools there; ctrl stays 0
      self._targets.apply_deltas(action, arrays.site_xpos[self._tcp_rows])
      self._impedance.place(physics, self._targets.pos, self._targets.rot)
    elif self._mode == control_modes.JOINT_POSITION:
      for i in range(len(self._arms)):
        arrays.ctrl[self._arm_act[i]] = control_modes.joint_targets(
            action[i, :-1], self._joint_low[i], self._joint_high[i])
    else:
      for i, arm in enumerate(self._arms):
        arrays.ctrl[self._arm_act[i]] = action[i, :-1] * arm.torque_limits
    # grippers.command for every arm, in Python floats.
    ctrl = arrays.ctrl
    for squeeze, (actuators, fingers) in zip(action[:, -1].tolist(), self._finger_command):
      fraction = (min(max(squeeze, -1.0), 1.0) + 1.0) / 2.0
      for actuator, (opened, travel) in zip(actuators, fingers):
        ctrl[actuator] = opened + fraction * travel

  def _track_task_space(self, arrays):
    """Joint targets for the position actuators from the task-space targets, by IK
    (`arrays`: this physics' ArrayViews)."""
    targets = self._targets.in_frame(self._base_pos_floats, self._base_rot_floats)
    q = self._ik.step(arrays.qpos[self._ik_qpos_rows], targets, self._dt)   # step copies it
    arrays.ctrl[self._arm_act_rows] = q[self._arm_from_ik_rows]

  # -- state readers ---------------------------------------------------------------

  def joint_limits(self, arm=0):
    """(low, high) position limits (rad) of one arm's joints; unlimited joints get +-pi."""
    return self._joint_low[arm].copy(), self._joint_high[arm].copy()

  @property
  def ik_failures(self):
    """IK steps so far in which the QP had no solution and the arms held still."""
    return self._ik.failures

  def arm_qpos(self, physics):
    """Joint positions of every arm joint the IK drives, in IK order."""
    return physics.data.qpos[self._ik_to_qpos].copy()

  def ik_joint_indices(self, arm=0):
    """Indices into `ik.joints` of one arm's joints, base to wrist."""
    return self._arm_ik[arm].copy()

  def tcp_pose(self, physics, arm=0):
    """World position and rotation matrix of an arm's tool-centre point."""
    site = self._tcp_ids[arm]
    return physics.data.site_xpos[site].copy(), physics.data.site_xmat[site].reshape(3, 3).copy()

  def finger_positions(self, physics, arm=0):
    """World positions (fingers, 3) of an arm's gripper finger bodies."""
    return physics.data.xpos[self._finger_bodies[arm]].copy()

  @property
  def finger_body_ids(self):
    """Per arm, the MuJoCo body ids of its gripper's finger bodies (set after compile)."""
    return [ids.copy() for ids in self._finger_bodies]

  def reach_check(self, physics, arm, goal_pos, goal_rot, iterations=40, start=None):
    """How well `arm` can put its tool at a world pose: IK solved from the present joints
    (or from `start`, an arm_qpos vector), the other arms holding their poses; nothing moves.

    Returns:
      (miss: position error in m plus 0.2 m per rad of orientation error, per-joint
      margin to the limits the IK keeps in (IK_WORKING_RANGES) in rad, joint travel in rad).
    """
    q = (physics.data.qpos[self._ik_to_qpos] if start is None else np.asarray(start)).copy()
    targets = list(self._ik.tcp_poses(q))
    to_base = self._base_rot.T
    targets[arm] = (to_base @ (goal_pos - self._base_pos), to_base @ goal_rot)
    solution = self._ik.solve(q, targets, iterations=iterations)
    arm_q = solution[self._ik.qpos_index[self._arm_ik[arm]]]
    low, high = (b[self._ik.qpos_index[self._arm_ik[arm]]] for b in self._ik.limits)
    margin = np.minimum(arm_q - low, high - arm_q)   # infinite for an endless joint
    pos, rot = self._ik.tcp_poses(solution)[arm]
    miss = (np.linalg.norm(pos - targets[arm][0])
            + 0.2 * np.linalg.norm(geometry.mat_to_axis_angle(rot @ targets[arm][1].T)))
    return float(miss), margin, float(np.linalg.norm(solution - q))

  def contacts_at(self, physics, q, hand=True):
    """What the robot would touch with its IK joints at `q` (an arm_qpos vector) and
    everything else where it is now: MuJoCo's own collision check, in a scratch copy of
    the state; nothing moves. The IK knows no obstacles: it put the Sawyer's forearm into
    the floor beside a chair it reached round low, and the arm stopped there.

    Args:
      physics: the environment's physics.
      q: joint positions of every arm joint the IK drives, in IK order.
      hand: whether to count the hands' own contacts too (the bodies that move with a
        tool: its last link, the gripper and fingers), or only the links behind them.

    Returns:
      [(robot geom id, other body id, metres the two overlap)], one per contact with
      something that is not the robot.
    """
    model = physics.model
    if self._scratch is None or self._scratch[0] is not model:
      geoms = np.array(physics.bind(self.mjcf_model.find_all("geom")).element_id)
      hands = set(model.body_weldid[model.site_bodyid[self._tcp_ids]].tolist())
      in_hand = np.zeros(model.nbody, dtype=bool)
      for body in range(1, model.nbody):   # parents come before their children
        in_hand[body] = body in hands or in_hand[model.body_parentid[body]]
      self._scratch = (model, mujoco.MjData(model.ptr), set(geoms.tolist()),
                       set(geoms[~in_hand[model.geom_bodyid[geoms]]].tolist()))
    _, data, mine, links = self._scratch
    data.qpos[:] = physics.data.qpos
    data.qpos[self._ik_to_qpos] = q
    mujoco.mj_fwdPosition(model.ptr, data)
    out = []
    contacts = data.contact
    for a, b, dist in zip(contacts.geom1.tolist(), contacts.geom2.tolist(), contacts.dist.tolist()):
      if (a in mine) == (b in mine):
        continue
      robot_geom, other = (a, b) if a in mine else (b, a)
      if hand or robot_geom in links:
        out.append((robot_geom, int(model.geom_bodyid[other]), -dist))
    return out

  @property
  def finger_actuator_ids(self):
    """(arms, fingers) MuJoCo actuator ids of the gripper fingers (set after compile)."""
    return self._finger_act.copy()

  def replay_targets(self):
    """A copy of the task-space targets (control_modes.TaskSpaceTargets) as they stand,
    for replaying delta actions without moving the robot's own."""
    return copy.deepcopy(self._targets)

  def task_space_target(self, arm=0):
    """World position and rotation of the tool target the task-space modes track."""
    return self._targets.pos[arm], self._targets.rot[arm]

  def gripper_opening(self, physics, arm=0):
    gripper = self._arms[arm].gripper
    return grippers.opening(gripper.open_qpos, gripper.closed_qpos,
                            physics.data.qpos[self._finger_qpos[arm]])

  def tcp_positions(self, physics):
    """(arms, 3) tool-centre-point positions."""
    return self._arrays(physics).site_xpos[self._tcp_rows].copy()

  def tool_positions(self, physics):
    return self.tcp_positions(physics)

  def held_parts_by_tool(self, physics, part_body_ids):
    """A part is held by an arm whose gripper touches it with two fingers."""
    return grippers.held_by_fingers(physics, self._finger_table, part_body_ids)

  def tcp_quaternions(self, physics):
    """(arms, 4) tool-centre-point orientations, w x y z."""
    quats = np.empty((len(self._arms), 4))
    xmat = self._arrays(physics).site_xmat
    for i, site in enumerate(self._tcp_ids.tolist()):
      mujoco.mju_mat2Quat(quats[i], xmat[site])
    return quats

  def gripper_openings(self, physics):
    """(arms,) gripper openings, 1 open .. 0 closed (grippers.opening of every arm)."""
    qpos = self._arrays(physics).qpos
    openings = []
    for fingers in self._finger_rows:
      fractions = [min(max((qpos.item(i) - closed) / span, 0.0), 1.0)
                   for i, closed, span in fingers]
      openings.append(sum(fractions) / len(fractions))
    return np.array(openings)

  def joint_positions(self, physics):
    return self._arrays(physics).qpos[self._arm_qpos_rows].copy()

  def joint_velocities(self, physics):
    return self._arrays(physics).qvel[self._arm_dof_rows].copy()


class _WristCamera(observable.MJCFCamera):
  """MJCFCamera that shows black until the robot's first episode: composer reads every
  observable once when the environment is built and drops the values at reset, and
  rendering then would make an OpenGL context in a process that may fork next
  (gymnasium's AsyncVectorEnv), whose children could not render (tasks/cameras.py)."""

  def __init__(self, entity, *args, **kwargs):
    super().__init__(*args, **kwargs)
    self._entity = entity

  def _callable(self, physics):
    render = super()._callable(physics)
    blank = np.zeros(self.array_spec.shape, self.array_spec.dtype)
    return lambda: render() if self._entity.episodes_started else blank


class ManipulatorObservables(composer.Observables):
  """Arm joint positions and velocities, tool poses, gripper openings; wrist cameras on request."""

  def __init__(self, entity):
    super().__init__(entity)
    if entity.wrist_camera_size is not None:
      height, width = entity.wrist_camera_size
      for arm in entity.arms:
        # An image: the task files it under cameras/ as `<camera>_rgb` (observations.py).
        self.add_observable(f"{arm.prefix}wrist_rgb",
                            _WristCamera(entity, arm.camera, height=height, width=width))

  @composer.observable
  def joint_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.joint_positions)

  @composer.observable
  def joint_velocities(self):
    return mujoco_arrays.FreshGeneric(self._entity.joint_velocities)

  @composer.observable
  def tcp_positions(self):
    return mujoco_arrays.FreshGeneric(self._entity.tcp_positions)

  @composer.observable
  def tcp_quaternions(self):
    return mujoco_arrays.FreshGeneric(self._entity.tcp_quaternions)

  @composer.observable
  def gripper_opening(self):
    return mujoco_arrays.FreshGeneric(self._entity.gripper_openings)
