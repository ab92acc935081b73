"""Task-space motion for scripted arms: tool orientations, pose-seeking actions, the way
home in joint space, pose errors and what the hand and fingers reach, shared by the
single-arm and two-arm experts and their skills."""

import mujoco
import numpy as np

from ikea_suite import geometry
from ikea_suite.robots import grippers


class FingerPoser:
  """A scratch copy of the state in which one arm's fingers can be set to any opening
  (0 open, 1 closed) and its finger collision geoms read; the simulation is untouched."""

  def __init__(self, robot, physics, arm):
    model = physics.model
    self.model, self.gripper = model, robot.arms[arm].gripper
    self.data = mujoco.MjData(model.ptr)
    self.data.qpos[:] = physics.data.qpos
    self._qposadr = np.asarray(physics.bind(self.gripper.joints).qposadr)
    self.tcp_site = int(physics.bind(self.gripper.tcp_site).element_id)
    finger = grippers.finger_of_body(physics, [robot.finger_body_ids[arm]])[0]
    self.geoms = [g for g in range(model.ngeom)
                  if model.geom_contype[g] and finger[model.geom_bodyid[g]] >= 0]
    self.finger_of_geom = {g: int(finger[model.geom_bodyid[g]]) for g in self.geoms}

  def set(self, fraction):
    g = self.gripper
    self.data.qpos[self._qposadr] = g.open_qpos + fraction * (g.closed_qpos - g.open_qpos)
    mujoco.mj_kinematics(self.model.ptr, self.data)

  def points(self, g):
    """World points that bound finger geom `g` in the scratch state: a mesh's vertices
    (MuJoCo collides its convex hull, whose corners they are), else its bounding box's
    corners. The Jaco's curved mesh fingertips reach 2 mm less than their box."""
    model, data = self.model, self.data
    mesh = model.geom_dataid[g] if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH else -1
    if mesh >= 0:
      start = model.mesh_vertadr[mesh]
      local = model.mesh_vert[start:start + model.mesh_vertnum[mesh]]
    else:
      half = model.geom_aabb[g, 3:]
      local = geometry.box_corners(-half, half) + model.geom_aabb[g, :3]
    return data.geom_xpos[g] + local @ data.geom_xmat[g].reshape(3, 3).T

  def tcp(self):
    """(position, approach axis) of the tool-centre point in the scratch state."""
    return self.data.site_xpos[self.tcp_site], self.data.site_xmat[self.tcp_site].reshape(3, 3)[:, 2]


def fingertip_reach(robot, physics, arm, samples=13):
  """How far the fingertips reach beyond the tool-centre point along the approach axis (m).

  Read from the compiled model with the arm in its present pose, over the fingers'
  whole stroke (FingerPoser): the farthest point of any finger collision geom
  (FingerPoser.points), relative to the TCP. Slide fingers reach equally far at every
  opening; curling ones (the Jaco's hinged fingers) reach farthest part way closed,
  and that depth is what must stay clear of the floor while they close.
  """
  poser = FingerPoser(robot, physics, arm)
  farthest = 0.0
  for fraction in np.linspace(0.0, 1.0, samples):
    poser.set(fraction)
    tcp_pos, approach = poser.tcp()
    for g in poser.geoms:
      farthest = max(farthest, float(((poser.points(g) - tcp_pos) @ approach).max()))
  return farthest


def hold_command(gripper, short_of_closed):
  """The gripper action that aims the fingers `short_of_closed` rad before their closed
  limit (the action maps -1..1 onto open..squeeze, past the closed limit by force / kp).

  For a hand that closes one finger against two (closes_against_pair): squeezed past
  the limit, the pair bottom out on it and the single finger presses the part onto their tips,
  whose faces slope out of the hand; the part crept 0.5 mm/s out and fell during the
  carry (Jaco, stool_round_frosta: 18 mm leg, 4.5 -> 11 mm in 8 s). Aimed short of the
  limit, the pair stay off it, all three pads meet the part and it crept 1.5 mm in the
  same 8 s. Over ten stool_round_frosta episodes: aimed at the limit itself 3 complete,
  0.05 rad short 5, 0.08 short none (too weak: the leg fell as it was lifted).
  """
  open_, closed = np.asarray(gripper.open_qpos), np.asarray(gripper.closed_qpos)
  target = closed - short_of_closed * np.sign(closed - open_)
  fraction = (target - open_) / (np.asarray(gripper.squeeze_qpos) - open_)
  return float(2.0 * fraction.mean() - 1.0)


def closes_against_pair(robot, physics, arm):
  """True for a hand that closes one finger against several (the Jaco's thumb against two,
  each finger with the same force limit): the pair push twice as hard, and squeezed past
  their closed limit they bottom out on it and shove the part towards the thumb (see
  hold_command). A parallel gripper's two equal fingers centre it."""
  return len(set(FingerPoser(robot, physics, arm).finger_of_geom.values())) > 2


def closing_axis(robot, physics, arm):
  """The fingers' closing direction in the tool frame (unit, horizontal when pointing down):
  from the first finger to the middle of the others, i.e. across a parallel gripper's two,
  from the thumb to the opposing pair of a three-finger hand."""
  fingers = robot.finger_positions(physics, arm)
  _, rot = robot.tcp_pose(physics, arm)
  axis = rot.T @ (fingers[1:].mean(axis=0) - fingers[0])
  axis[2] = 0.0
  return axis / np.linalg.norm(axis)


def tool_rotation(approach, closing, closing_local):
  """Tool rotation whose z axis is `approach` and whose finger axis (`closing_local`) is `closing`."""
  local_b = np.cross([0.0, 0.0, 1.0], closing_local)
  world_b = np.cross(approach, closing)
  local = np.column_stack([closing_local, local_b, [0.0, 0.0, 1.0]])
  world = np.column_stack([closing, world_b, approach])
  return world @ local.T


class PoseServo:
  """Task-space actions that bring one arm's tool to a goal pose without hunting.

  The action moves the robot's own target (which it integrates from the deltas)
  straight to the goal, so the target never winds up while the arm lags behind
  it; feeding the measured error back each step instead is an integrator with a
  delay and oscillates wherever the arm is slow (measured: +-5 cm limit cycles at
  the edge of the Sawyer's reach). A slow integral of the measured
  error, gathered only near a goal that holds still, removes steady offsets
  such as a held load's sag; it starts afresh whenever the goal moves on, so an
  unreachable goal's wound-up offset never carries over to the next.
  """

  def __init__(self, ki=0.15, near=0.03, max_offset=0.04, max_rot_offset=0.15, new_goal=0.005):
    self._ki, self._near, self._new_goal = ki, near, new_goal
    self._max_offset, self._max_rot_offset = max_offset, max_rot_offset
    self.reset()

  def reset(self):
    self._offset, self._rot_offset = np.zeros(3), np.zeros(3)
    self._goal = None

  def __call__(self, robot, physics, arm, goal_pos, goal_rot, gain=1.0, max_turn=1.0,
               max_speed=1.0):
    """Task-space action entries (6) for this control step; `max_turn` and `max_speed` cap
    the turn and the move as fractions of the robot's largest per-step ones."""
    pos, rot = robot.tcp_pose(physics, arm)
    target_pos, target_rot = robot.task_space_target(arm)
    if self._goal is None or np.linalg.norm(goal_pos - self._goal) > self._new_goal:
      self._offset, self._rot_offset = np.zeros(3), np.zeros(3)
    self._goal = np.array(goal_pos, dtype=float)
    error = goal_pos - pos
    rot_error = geometry.mat_to_axis_angle(goal_rot @ rot.T)
    if np.linalg.norm(error) < self._near:   # gather the integral only close to the goal
      self._offset = _clip_norm(self._offset + self._ki * error, self._max_offset)
      self._rot_offset = _clip_norm(self._rot_offset + self._ki * rot_error, self._max_rot_offset)
    aim = geometry.axis_angle_to_mat(self._rot_offset) @ goal_rot
    return delta_action(robot, target_pos, target_rot, goal_pos + self._offset, aim, gain,
                        max_turn, max_speed)


def delta_action(robot, target_pos, target_rot, goal_pos, goal_rot, gain=1.0, max_turn=1.0,
                 max_speed=1.0):
  """Task-space action entries (6) that move the robot's target (target_pos, target_rot)
  straight towards the goal, `gain` of the way, at most `max_speed` and `max_turn` of the
  robot's largest per-step move and turn."""
  move = gain * (goal_pos - target_pos) / robot.max_translation
  turn = gain * geometry.mat_to_axis_angle(goal_rot @ target_rot.T) / robot.max_rotation
  move /= max(1.0, np.abs(move).max())
  move *= min(1.0, max_speed / max(np.abs(move).max(), 1e-12))   # exactly 1 at full speed
  turn *= max_turn / max(max_turn, np.abs(turn).max())
  return np.concatenate([move, turn])


class Unwinder:
  """Task-space actions that bring one arm back to its home joint configuration.

  The tool follows the poses of a straight joint-space path from the present joints to
  home, computed by forward kinematics: each lies next to where the arm already is, so
  the differential IK tracks them from any configuration. A straight tool path home does
  not: from an arm folded against its limits the IK stays folded (Sawyer: shoulder,
  elbow and wrist pinned, home 0.57 m out of reach, the same far part stalled every
  reach for the rest of the episode).
  """

  def __init__(self, max_joint_step=0.15, steps_per_waypoint=6):
    self._max_joint_step, self._steps_per_waypoint = max_joint_step, steps_per_waypoint
    self._servo = PoseServo()
    self.waypoints, self._counter = [], 0
    self._budgets = []   # control steps each waypoint is waited for before moving on
    self._caps = (1.0, 1.0)   # (max_turn, max_speed) of the servo

  @staticmethod
  def _travel(robot, physics, arm):
    """(IK joint vector now, the arm's indices in it, their angles (rad) to home)."""
    q = robot.arm_qpos(physics)
    index = robot.ik.qpos_index[robot.ik_joint_indices(arm)]
    return q, index, robot.ik.posture_near(q)[index] - q[index]

  @classmethod
  def distance_from_home(cls, robot, physics, arm):
    """Largest angle (rad) of any of the arm's joints from its home angle."""
    return float(np.abs(cls._travel(robot, physics, arm)[2]).max())

  def start(self, robot, physics, arm, keep_clear=None):
    """Plans the path from the present joints; then call until `done`. `keep_clear` (a
    position -> position callable) moves each waypoint but the last clear of what the arm
    must not strike: beside a chair just turned over, the straight joint path swung the
    fingers 0.2 m down into it and the rising hand flipped it (chair_back_pine_high)."""
    q, index, travel = self._travel(robot, physics, arm)
    count = max(1, int(np.ceil(np.abs(travel).max() / self._max_joint_step)))
    base_pos, base_rot = robot.base_pose
    self.waypoints = []
    for k in range(1, count + 1):
      path_q = q.copy()
      path_q[index] += travel * (k / count)
      pos, rot = robot.ik.tcp_poses(path_q)[arm]
      pos = base_rot @ pos + base_pos
      if keep_clear is not None and k < count:
        pos = keep_clear(pos)
      self.waypoints.append((pos, base_rot @ rot))
    self._budgets = [self._steps_per_waypoint] * len(self.waypoints)
    self._caps = (1.0, 1.0)
    self._servo.reset()
    self._counter = 0

  def follow(self, robot, arm, path, max_turn=1.0, max_speed=1.0):
    """Follows a planned joint path instead (IK joint vectors, every arm, the first the
    present joints: joint_planner.JointPath.q), turning and moving the tool at most
    `max_turn` and `max_speed` of the robot's top speeds; then call until `done`. Each
    waypoint is waited for as many control steps as the tool's move to it takes at those
    speeds, plus two: a held part carried at a slower speed than the unwinding's lagged
    further behind each waypoint."""
    base_pos, base_rot = robot.base_pose
    self.waypoints, self._budgets = [], []
    pos, rot = robot.ik.tcp_poses(path[0])[arm]
    for q in path[1:]:
      last = pos, rot
      pos, rot = robot.ik.tcp_poses(q)[arm]
      move = np.linalg.norm(pos - last[0]) / (max_speed * robot.max_translation)
      turn = np.linalg.norm(geometry.mat_to_axis_angle(rot @ last[1].T)) / (
          max_turn * robot.max_rotation)
      self.waypoints.append((base_rot @ pos + base_pos, base_rot @ rot))
      self._budgets.append(int(np.ceil(max(move, turn))) + 2)
    self._caps = (max_turn, max_speed)
    self._servo.reset()
    self._counter = 0

  @property
  def done(self):
    return not self.waypoints

  def __call__(self, robot, physics, arm):
    """Task-space action entries (6) for this control step, towards the next waypoint."""
    goal = self.waypoints[0]
    max_turn, max_speed = self._caps
    action = self._servo(robot, physics, arm, *goal, max_turn=max_turn, max_speed=max_speed)
    self._counter += 1
    distance, angle = pose_error(robot, physics, arm, *goal)
    last = len(self.waypoints) == 1
    # On when there, or after a few steps (the last waypoint is waited for longer).
    if ((distance < 0.02 and angle < 0.05)
        or (self._counter >= self._budgets[0] and not last)
        or self._counter >= 4 * self._budgets[0]):
      self.waypoints.pop(0)
      self._budgets.pop(0)
      self._counter = 0
    return action


def hand_reach(robot, physics, arm, rot, direction):
  """How far (m) the hand (every collision geom fixed to the tool) reaches from the tool
  centre along the unit world `direction`, with the tool turned to world rotation `rot`."""
  model, data = physics.model, physics.data
  site = physics.bind(robot.arms[arm].gripper.tcp_site).element_id
  tcp, tcp_rot = data.site_xpos[site], data.site_xmat[site].reshape(3, 3)
  rigid = model.body_weldid[model.site_bodyid[site]]
  farthest = 0.0
  for geom in np.flatnonzero(model.body_weldid[model.geom_bodyid] == rigid):
    if not (model.geom_contype[geom] or model.geom_conaffinity[geom]):
      continue
    geom_rot = rot @ tcp_rot.T @ data.geom_xmat[geom].reshape(3, 3)   # as the tool turns
    centre = rot @ tcp_rot.T @ (data.geom_xpos[geom] - tcp) + geom_rot @ model.geom_aabb[geom, :3]
    farthest = max(farthest, centre @ direction
                   + np.abs(direction @ geom_rot) @ model.geom_aabb[geom, 3:])
  return farthest


def hand_below_tool(robot, physics, arm, rot):
  """How far (m) the hand reaches below the tool centre with the tool turned to world
  rotation `rot`: pointing sideways, the Panda's last link struck the floor with the tool
  centre 8.5 cm above it."""
  return hand_reach(robot, physics, arm, rot, np.array([0.0, 0.0, -1.0]))


# The carry turns a held part at this fraction of the arm's top turning speed: turning
# slowly, a held part does not swing out.
CARRY_TURN = 0.3

# Metres from the tool centre back along its axis to the wrist, as the planners reckon it.
WRIST_BACK = 0.25


def cramped(base_pos, tool_pos, tool_axis):
  """How far (m) the wrist, WRIST_BACK along the tool axis, lies inside 0.45 m of the base
  (horizontally): a wrist folded in beside the base is cramped, and the differential IK
  stalls there."""
  wrist = tool_pos - WRIST_BACK * tool_axis
  return max(0.0, 0.45 - np.linalg.norm(wrist[:2] - base_pos[:2]))


def pinned(robot, physics, arm, within=0.02):
  """True when a joint of the arm is within `within` rad of a limit its IK keeps it in."""
  low, high = robot.ik.limits
  index = robot.ik.qpos_index[robot.ik_joint_indices(arm)]
  q = robot.arm_qpos(physics)
  return np.minimum(q[index] - low[index], high[index] - q[index]).min() < within


class ProgressWatch:
  """Says when a servoed tool has stopped closing on its goal: `window` control steps
  without `min_gain` less error (metres, plus 0.2 m per radian of orientation error)."""

  def __init__(self, window=40, min_gain=0.01):
    self._window, self._min_gain = window, min_gain
    self.reset()

  def reset(self):
    self._best, self._since = np.inf, 0

  def stalled(self, distance, angle):
    error = distance + 0.2 * angle
    if error < self._best - self._min_gain:
      self._best, self._since = error, 0
    else:
      self._since += 1
    return self._since > self._window


def _clip_norm(vector, limit):
  norm = np.linalg.norm(vector)
  return vector if norm <= limit else vector * (limit / norm)


def pose_error(robot, physics, arm, goal_pos, goal_rot):
  pos, rot = robot.tcp_pose(physics, arm)
  return np.linalg.norm(goal_pos - pos), np.linalg.norm(geometry.mat_to_axis_angle(goal_rot @ rot.T))


def servo_path_end(robot, arm, q, goal_pos, goal_rot, dt, max_turn=1.0, max_steps=200,
                   near=0.02):
  """(joints, metres and radians from the goal) at which one arm stops, from joints `q`
  (an arm_qpos vector), as PoseServo (gain 1, turning at `max_turn`) brings its tool to
  the world pose (goal_pos, goal_rot) on the arc around the base (arc_waypoint): a copy
  of the robot's task-space targets takes the same delta actions, and the joints follow
  the differential IK step by step (control steps of `dt` s), on the IK's own model;
  nothing collides, nothing lags.

  A converged IK solve (Manipulator.reach_check) finds a pose by whatever path: it
  reached a trestle's mate from a wrist 0.3 rad short of its limit by turning it back,
  where the carry, turning the tool the short way round as the arm swung, drove it into
  that limit and stalled 15 cm short (Sawyer, desk_trestle_w120_white).
  """
  ik = robot.ik
  base_pos, base_rot = robot.base_pose
  heading = np.arctan2(base_rot[1, 0], base_rot[0, 0])

  def tool(q):
    pos, rot = ik.tcp_poses(q)[arm]
    return base_rot @ pos + base_pos, base_rot @ rot

  q, failures = np.array(q, dtype=float), ik.failures
  targets = robot.replay_targets()
  poses = list(zip(targets.pos, targets.rot))
  poses[arm] = tool(q)
  targets.reset(poses)
  actions = np.zeros((len(poses), 6))   # the other arms' targets stay where they are
  for _ in range(max_steps + 1):
    pos, rot = tool(q)
    distance = float(np.linalg.norm(goal_pos - pos))
    angle = float(np.linalg.norm(geometry.mat_to_axis_angle(goal_rot @ rot.T)))
    if distance < near and angle < 0.05:
      break
    target_pos, target_rot = targets.pos[arm], targets.rot[arm]
    actions[arm] = delta_action(robot, target_pos, target_rot,
                                arc_waypoint(base_pos, pos, goal_pos, heading=heading), goal_rot,
                                max_turn=max_turn)
    tools = targets.pos
    tools[arm] = pos
    targets.apply_deltas(actions, tools)
    goals = list(ik.tcp_poses(q))
    goals[arm] = (base_rot.T @ (targets.pos[arm] - base_pos), base_rot.T @ targets.rot[arm])
    q = ik.step(q, goals, dt)
  ik.failures = failures   # it counts the arm's own steps, not these
  return q, distance, angle


def arc_waypoint(base, pos, goal, heading=0.0, max_turn=0.25, max_step=0.1):
  """A point from the tool position `pos` towards `goal` on an arc around the robot base
  `base` (at most `max_turn` rad and `max_step` m per call), so a carried part never
  sweeps across the base. The arc always passes in front of the base (the side its
  `heading` faces): the short way round behind it winds the joints into their limits."""
  here, there = pos[:2] - base[:2], goal[:2] - base[:2]
  radius, target_radius = np.linalg.norm(here), np.linalg.norm(there)
  front = lambda v: np.angle(np.exp(1j * (np.arctan2(v[1], v[0]) - heading)))
  angle = front(here)
  angle += np.clip(front(there) - angle, -max_turn, max_turn)
  radius += np.clip(target_radius - radius, -max_step, max_step)
  z = pos[2] + np.clip(goal[2] - pos[2], -max_step, max_step)
  return np.array([base[0] + radius * np.cos(angle + heading),
                   base[1] + radius * np.sin(angle + heading), z])
