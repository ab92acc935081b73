"""Standing the root part up, for furniture that stands on a root lying on its side.

A pedestal stool's pedestal (post and base disc, one part) lies on its side, the seat's
connector at the end of the post level with the floor: the seat would sit in the floor
(turn_over.under_support), so no part can go in, and there is no leg to turn the
assembly over by. One arm stands the root up (`StandUp`): it takes the root from above,
across its standing axis, lifts it clear, turns it about the fingers' closing axis until
it stands (`standing_axis`), sets it down on its foot, lets go and backs out
along the hand's axis. Everything goes through the same task-space actions a learning
agent sends; privileged state only says where the part is.
"""

import enum

import numpy as np

from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import arm_skill
from ikea_suite.experts import part_geometry
from ikea_suite.experts import sensing
from ikea_suite.experts import turn_over

# The hand takes the root this fraction of its height up from its foot (a pedestal's post,
# clear of the base disc), but no lower than its body, pointing sideways once the root
# stands, passes HAND_CLEARANCE (m) over the surface, nor nearer its top than TOP_ROOM (m).
GRIP_ALONG, HAND_CLEARANCE, TOP_ROOM = 0.7, 0.015, 0.01
# The fingertips close this far (m) over the surface where the root lies low.
TIP_CLEARANCE = 0.003
# Lifted, every corner of the root, swinging about the tool centre, clears the surface by
# TURN_CLEARANCE (m); set down, it is let go DROP (m) over the surface.
TURN_CLEARANCE, DROP = 0.04, 0.005
# ... and the lift raises it by at least LIFT (m).
LIFT = 0.05
# The open hand comes down to the grasp from HOVER (m) over it, and backs out STANDOFF (m)
# along its axis once the root stands.
HOVER, STANDOFF = 0.12, 0.12
# Headings (rad, about the vertical) the standing root's grasp may face: the hand turns
# the root upright about the closing axis and may turn it about the vertical on the way,
# so the hand ends pointing sideways in whichever heading the arm reaches best.
HEADINGS = np.radians(np.arange(0, 360, 45))
# The hand has lost the root once it has slid this far (m) from where the fingers took it.
SLIP = 0.03
# Rad the standing axis of a root lying on its side may lean from the horizontal (lying at
# rest it is horizontal).
LYING = np.radians(45.0)


def upright_axis(spec, part):
  """The part-frame unit axis that points up in the assembled furniture."""
  return spec.parts[part].rot.T @ np.array([0.0, 0.0, 1.0])


def standing_axis(spec, root):
  """The part-frame unit axis that points up once the root stands alone for the other
  parts to go in from above; None when it cannot stand so.

  The furniture's up axis when the rest of the furniture stands on the root (a pedestal
  stool's seat on its pedestal); the axis down when parts lie below the root too (a
  round-post table's post stands on its top end: its base goes in first, and the table
  is turned over before its top goes in, turn_over.TurnOver). None when a part reaches
  past the root's middle (a bench's other end frame, beside the first; an armrest
  chair's side frames, reaching below the seat).
  """
  middle = spec.parts[root].assembled_corners()[:, 2].mean()
  below = False
  for i, part in enumerate(spec.parts):
    heights = part.assembled_corners()[:, 2]
    if i == root or heights.min() >= middle:
      continue
    if heights.max() > middle:
      return None
    below = True
  up = upright_axis(spec, root)
  return -up if below else up


def needed(task, physics, surface):
  """Whether the root, alone and lying on its side (its standing axis, `standing_axis`,
  within LYING of the horizontal), must stand up before any part can go in: every open
  mate waits in the surface (turn_over.waiting). A root upside down is no stand-up's: the
  turn about a horizontal axis has no one axis to take then (turn_over's case)."""
  root = task.root_part
  if len(part_geometry.root_group(task)) > 1:
    return False
  axis = standing_axis(task.furniture.spec, root)
  if axis is None:
    return False
  _, rot = part_geometry.part_pose(physics, task.furniture, root)
  up = rot @ axis
  return bool(abs(up[2]) < np.sin(LYING) and turn_over.waiting(task, physics, surface))


def _turn_upright(up):
  """The rotation that turns the world axis `up` to the vertical about a horizontal axis."""
  axis = np.cross(up, [0.0, 0.0, 1.0])
  if np.linalg.norm(axis) < 1e-9:
    return np.eye(3)
  angle = np.arccos(np.clip(up[2], -1.0, 1.0))
  return geometry.axis_angle_to_mat(angle * axis / np.linalg.norm(axis))


class Step(enum.Enum):
  OVER = "over"     # open, HOVER over the grasp, pointing down
  DOWN = "down"     # down to the grasp, slowly
  CLOSE = "close"   # squeeze
  LIFT = "lift"     # straight up until the root can turn clear of the surface
  TURN = "turn"     # turn the root upright (and to its heading) at that height
  LOWER = "lower"   # down until its foot is DROP over the surface
  OPEN = "open"     # let go
  OUT = "out"       # back along the hand's axis
  UP = "up"         # up clear of the standing root
  DONE = "done"


class StandUp(arm_skill.SteppedSkill):
  """One arm's stand-up of the root part: call `start`, then each control step `__call__`
  for the task-space action; `step` says where it is, `failed` whether it gave up.

  Args:
    env: the environment.
    arm: the arm's index.
    surface: height (m) of the surface the parts lie on.
    route: the arm's clearance.AssemblyClearance (its fingertips' reach below the tool).
    close_steps: control steps the fingers take to close.
    open_steps: control steps the fingers take to open.
    step_budget: control steps a step may take before the stand-up gives up.
  """

  STEPS = Step

  def reset(self):
    """Forgets the episode's stand-ups."""
    self.step, self.failed = Step.DONE, False
    self._failed_grasps = set()   # (closing sign, heading index) that slipped or stalled
    # The present stand-up, chosen by `start`: the grasp's tool position and rotation, the
    # tool height the root turns at, the part's target rotation standing, the tool pose
    # set down, and the choice (closing sign, heading index).
    self._grasp = self._rot = self._standing = self._set = self._choice = None
    self._closing_local = None
    self._height = 0.0
    self._count = 0
    self._out = self._let_go = None   # where the hand backs out to; where it let go
    self._grip = self._grip_rot = None   # the tool pose in the root's frame as the lift began

  def _root(self):
    task = self._env.task
    return task.root_part, task.furniture

  def _grasp_now(self, closing_local, sign, heading):
    """(grasp position, grasp rotation, turn height, part rotation standing, tool pose set
    down) for one grasp and heading, the root where it lies now."""
    env, robot = self._env, self._env.task.robot
    physics, arm = env.physics, self._arm
    root, furniture = self._root()
    pos, rot = part_geometry.part_pose(physics, furniture, root)
    lo, hi = furniture.spec.parts[root].bounds
    up_local = standing_axis(furniture.spec, root)
    local = geometry.box_corners(lo, hi)
    along = local @ up_local
    up = rot @ up_local
    flat = np.array([up[0], up[1], 0.0]) / np.linalg.norm(up[:2])
    closing = sign * np.cross([0.0, 0.0, 1.0], flat)
    grasp_rot = arm_motion.tool_rotation(np.array([0.0, 0.0, -1.0]), closing, closing_local)
    standing = geometry.axis_angle_to_mat(np.array([0.0, 0.0, heading])) @ _turn_upright(up) @ rot
    turned_rot = standing @ rot.T @ grasp_rot
    below = arm_motion.hand_below_tool(robot, physics, arm, turned_rot)
    foot, top = along.min(), along.max()
    s = min(max(foot + GRIP_ALONG * (top - foot), foot + below + HAND_CLEARANCE),
            top - TOP_ROOM)
    centre = 0.5 * (lo + hi)
    point = pos + rot @ (centre + (s - centre @ up_local) * up_local)
    pad_below = self._route.pad_below or 0.0
    point[2] = max(point[2], self._surface + pad_below + TIP_CLEARANCE)
    grip_pos, grip_rot = rot.T @ (point - pos), rot.T @ grasp_rot
    # Standing where it was taken, its foot DROP over the surface.
    standing_corners = local @ standing.T
    part_at = np.array([*(point[:2] - (standing @ grip_pos)[:2]),
                        self._surface + DROP - standing_corners[:, 2].min()])
    set_pos, set_rot = part_at + standing @ grip_pos, standing @ grip_rot
    reach = np.linalg.norm(local @ rot.T + pos - point, axis=1).max()
    height = max(point[2] + LIFT, self._surface + TURN_CLEARANCE + reach)
    return point, grasp_rot, height, standing, (set_pos, set_rot)

  def _plan(self, closing_local, sign, heading):
    """(cost, grasp position, grasp rotation, turn height, part rotation standing, tool
    pose set down) for one grasp and heading: how far the arm's reach falls short along
    the way, and how near it comes to its joint limits."""
    robot, physics, arm = self._env.task.robot, self._env.physics, self._arm
    grasp = self._grasp_now(closing_local, sign, heading)
    point, grasp_rot, height, _, (set_pos, set_rot) = grasp
    poses = [(point + [0.0, 0.0, HOVER], grasp_rot), (point, grasp_rot),
             (np.array([*point[:2], height]), grasp_rot),
             (np.array([*set_pos[:2], height]), set_rot), (set_pos, set_rot),
             (set_pos - STANDOFF * set_rot[:, 2], set_rot)]
    base, _ = robot.base_pose
    cost = 2.0 * arm_motion.cramped(base, set_pos, set_rot[:, 2])
    for goal in poses:
      miss, margin, _ = robot.reach_check(physics, arm, *goal)
      cost += miss + np.maximum(0.0, 0.2 - margin).sum()
    # The servo's own path through the turn: each end reachable, the Panda's turn between
    # them stalled with a joint at its limit and the hand wandered 0.3 m off.
    q, dt = robot.arm_qpos(physics), self._env.control_timestep()
    for goal, turn in zip(poses[:4], (1.0, 1.0, 1.0, arm_motion.CARRY_TURN)):
      q, distance, angle = arm_motion.servo_path_end(robot, arm, q, *goal, dt, max_turn=turn)
    return (cost + distance + 0.2 * angle, *grasp)

  def start(self, closing_local):
    """Chooses the grasp and heading the arm reaches best, `closing_local` being the
    fingers' closing direction in the tool frame, passing over those that failed this
    episode until every one has; returns True (the stand-up has begun)."""
    if self._route.pad_below is None:   # measured with the arm at home, as the grasps do
      self._route.pad_below = arm_motion.fingertip_reach(
          self._env.task.robot, self._env.physics, self._arm)
    options = [(sign, k) for sign in (1.0, -1.0) for k in range(len(HEADINGS))
               if (sign, k) not in self._failed_grasps]
    if not options:   # every one has failed once: try them all again
      self._failed_grasps = set()
      options = [(sign, k) for sign in (1.0, -1.0) for k in range(len(HEADINGS))]
    best = None
    for sign, k in options:
      plan = self._plan(closing_local, sign, HEADINGS[k])
      if best is None or plan[0] < best[0][0]:
        best = (plan, (sign, k))
    (_, self._grasp, self._rot, self._height, self._standing, self._set), self._choice = best
    self._closing_local = closing_local
    self.step, self.failed, self._count = Step.OVER, False, 0
    return True

  def gripper(self):
    """+1 to close, -1 to open, for this step."""
    return 1.0 if self.step in (Step.CLOSE, Step.LIFT, Step.TURN, Step.LOWER) else -1.0

  def _held_goal(self, height=None):
    """The tool pose that puts the held root standing, the tool at `height` (or set down):
    turned by the grip the lift began with, and as high as the grip measured now puts the
    foot DROP over the surface. Turned by the grip as measured, the goal chased the post
    as it swung in the Panda's fingers, and the hand wandered 0.3 m off."""
    env = self._env
    root, furniture = self._root()
    pos, rot = part_geometry.part_pose(env.physics, furniture, root)
    tcp, _ = env.task.robot.tcp_pose(env.physics, self._arm)
    grip_pos = rot.T @ (tcp - pos)
    goal_rot = self._standing @ self._grip_rot
    local = geometry.box_corners(*furniture.spec.parts[root].bounds) @ self._standing.T
    goal = np.array([*self._set[0][:2], 0.0])
    goal[2] = self._surface + DROP - local[:, 2].min() + (self._standing @ grip_pos)[2]
    if height is not None:
      goal[2] = max(goal[2], height)
    return goal, goal_rot

  def _goal(self):
    tcp, tcp_rot = self._env.task.robot.tcp_pose(self._env.physics, self._arm)
    if self.step == Step.OVER:
      return self._grasp + [0.0, 0.0, HOVER], self._rot
    if self.step in (Step.DOWN, Step.CLOSE):
      return self._grasp, self._rot
    if self.step == Step.LIFT:
      return np.array([*self._grasp[:2], self._height]), self._rot
    if self.step == Step.TURN:
      return self._held_goal(self._height)
    if self.step == Step.LOWER:
      return self._held_goal()
    if self.step == Step.UP:
      return np.array([*self._out[:2], self._route.safe_height()]), tcp_rot
    if self.step == Step.OPEN:   # held still: backing out while the fingers opened, they
      return self._let_go         # dragged a post stood on its end over
    return self._out, tcp_rot

  def __call__(self, servo):
    """The task-space action entries (6) for this control step, from `servo` (an
    arm_motion.PoseServo); advances the steps."""
    env, robot = self._env, self._env.task.robot
    physics, arm = env.physics, self._arm
    root, furniture = self._root()
    if self.step in (Step.OVER, Step.DOWN, Step.CLOSE):   # to the root where it lies now
      sign, k = self._choice
      (self._grasp, self._rot, self._height, self._standing,
       self._set) = self._grasp_now(self._closing_local, sign, HEADINGS[k])
    goal = self._goal()
    slow = self.step in (Step.DOWN, Step.LOWER)
    waypoint = (self._route.arc_waypoint(self._route.over_assembly(goal[0]))
                if self.step == Step.OVER else goal[0])
    action = servo(robot, physics, arm, waypoint, goal[1], gain=0.3 if slow else 1.0,
                   max_turn=arm_motion.CARRY_TURN if self.step == Step.TURN else 1.0,
                   max_speed=0.3 if self.step in (Step.DOWN, Step.LIFT, Step.LOWER) else 1.0)
    distance, angle = arm_motion.pose_error(robot, physics, arm, *goal)
    self._count += 1
    if self.step in (Step.LIFT, Step.TURN, Step.LOWER) and not self._holding():   # slipped: let go, out, and try another way
      self._give_up()
      self.step, self._count = Step.OPEN, 0
      self._set_out()
      return action
    near = distance < (0.006 if slow else 0.02) and angle < 0.05
    if self.step in (Step.CLOSE, Step.OPEN):
      near = self._fingers_done()
    if near:
      self._next()
    elif self._count > self._budget:
      if self.step in (Step.OVER, Step.DOWN):
        self._give_up()
        self.step = Step.UP
        self._set_out()
      elif self.step in (Step.LIFT, Step.TURN):   # set down as it is, not dropped
        self._give_up()
        self.step = Step.LOWER
      else:
        self.step = Step.DONE if self.step in (Step.OUT, Step.UP) else Step.OPEN
        self._set_out()
      self._count = 0
    return action

  def _holding(self):
    """The root is squeezed (sensing.holding's test of the fingers) and has not slid
    SLIP (m) from where the fingers took it."""
    env = self._env
    root, furniture = self._root()
    pos, rot = part_geometry.part_pose(env.physics, furniture, root)
    tcp, _ = env.task.robot.tcp_pose(env.physics, self._arm)
    if np.linalg.norm(rot.T @ (tcp - pos) - self._grip) > SLIP:
      return False
    return sensing.squeezed(env.physics, env.task.robot, self._arm, furniture, root)

  def _give_up(self):
    self._failed_grasps.add(self._choice)
    self.failed = True

  def _set_out(self):
    tcp, rot = self._env.task.robot.tcp_pose(self._env.physics, self._arm)
    self._out, self._let_go = tcp - STANDOFF * rot[:, 2], (tcp, rot)

  def _next(self):
    super()._next()
    if self.step == Step.LIFT:   # where the fingers took it, in its own frame
      env = self._env
      root, furniture = self._root()
      pos, rot = part_geometry.part_pose(env.physics, furniture, root)
      tcp, tcp_rot = env.task.robot.tcp_pose(env.physics, self._arm)
      self._grip, self._grip_rot = rot.T @ (tcp - pos), rot.T @ tcp_rot
