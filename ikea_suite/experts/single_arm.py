"""The single-arm expert: a scripted task-space controller for one arm with a gripper (the
Sawyer, Panda and Jaco, and each of the Baxter's arms).

With privileged state it picks the planner's next part, grasps it by
friction, turns it so its connector meets the mate on the assembly, and
issues connect, through the same action vector a learning agent sends
(task_space or impedance mode: move, rotate, gripper, connect). It then lets go, backs
off, and moves on to the next pair until the furniture is whole.
"""

import dataclasses
import enum

import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import clearance
from ikea_suite.experts import joint_planner
from ikea_suite.experts import mating
from ikea_suite.experts import next_part
from ikea_suite.experts import part_geometry
from ikea_suite.experts import sensing
from ikea_suite.experts import stand_up
from ikea_suite.experts import top_down_grasp
from ikea_suite.experts import turn_over
from ikea_suite.robots import control_modes

# Rad of any joint from home beyond which the arm goes home in joint space between parts.
UNWIND_FROM = 1.0
# Mates (pair, twist) a stalled carry plans a joint path to before the part is put back.
_PLANNED_MATES = 3


class Phase(enum.Enum):
  REACH = "reach"       # open gripper above the part's grasp point
  DESCEND = "descend"   # down to the grasp point
  CLOSE = "close"       # squeeze; the part is held by contact friction only
  LIFT = "lift"         # raise the part clear of the floor
  ALIGN = "align"       # carry and turn it to just short of its mating pose
  INSERT = "insert"     # close the last gap and connect
  RELEASE = "release"   # open the gripper on the joined part
  RETREAT = "retreat"   # back off before the next part
  PUT_BACK = "put_back"   # set a part down where it was taken, to take it another way
  PLANNED_CARRY = "planned_carry"   # along a planned joint path to the approach pose
  UNWIND = "unwind"     # back to the home joint configuration along a joint-space path
  TURN_OVER = "turn_over"   # roll the assembly onto its other face (turn_over.TurnOver)
  STAND_UP = "stand_up"     # stand the lying root up on its foot (stand_up.StandUp)


# Phases in which the fingers close on, or hold, a part.
_HOLDING = (Phase.CLOSE, Phase.LIFT, Phase.ALIGN, Phase.INSERT, Phase.PUT_BACK,
            Phase.PLANNED_CARRY)
# Phases that go on with no part chosen.
_WITHOUT_A_PART = (Phase.RELEASE, Phase.RETREAT, Phase.UNWIND, Phase.TURN_OVER, Phase.STAND_UP)
# Phases another skill drives from start to end, choosing no part meanwhile.
_OWN_SKILL = (Phase.TURN_OVER, Phase.STAND_UP)


@dataclasses.dataclass(frozen=True)
class _Command:
  """One control step's action, as the phase methods fill in this arm's part of it."""
  action: np.ndarray   # the whole action vector (connect is its last entry)
  tool: np.ndarray     # this arm's six task-space entries, a view into `action`
  grip: int            # index of this arm's gripper entry in `action`


class ArmAssemblyController:
  """Call with a TimeStep (or nothing); returns the action for `env`, whose arm moves in
  one of CONTROL_MODES.

  Each control step first notes a new connection (on to RELEASE) and chooses the next
  part when it needs one; then the present phase's method (_PHASES: one small method per
  Phase) fills in the arm's six task-space entries and moves the phase on. Everything
  an episode changes is set in reset().

  Args:
    env: the environment.
    arm: the arm's index (Baxter: 0 right, 1 left).
    hover: height (m) over the grasp point the reach makes for before the descent.
    lift: height (m) the part is lifted by after the grasp.
    carry: carry height (m) over the surface the parts lie on.
    approach: distance (m) short of the mating pose from which the part goes in.
    tolerance: fraction of the task's thresholds the pair must reach before connecting.
    close_steps: control steps the fingers take to close (more for a slower hand).
    release_steps: control steps the fingers take to open.
    stall_steps: control steps a reach may take before the part is given up.
    insert_steps: control steps an insertion may take before the mate is given up.
    edge_lift_speed: fraction of the arm's top speed at which a panel held by its top edge
      is lifted (1: full speed, as every part).

  Raises:
    IkeaSuiteError: the robot's control mode is not one of CONTROL_MODES.
  """

  # The expert sends task-space moves: the modes whose actions move the tool by deltas.
  CONTROL_MODES = control_modes.DELTA_TARGETS

  def __init__(self, env, arm=0, hover=0.12, lift=0.12, carry=0.5, approach=0.08, tolerance=0.9,
               close_steps=8, release_steps=6, stall_steps=150, insert_steps=40,
               edge_lift_speed=1.0):
    robot = env.task.robot
    if robot.control_mode not in self.CONTROL_MODES:
      raise errors.IkeaSuiteError(
          f"the {robot.mjcf_model.model} expert drives the arm by task-space moves, in "
          f"control_mode {' or '.join(map(repr, self.CONTROL_MODES))}, got "
          f"control_mode={robot.control_mode!r}")
    self._env, self._robot, self._arm = env, robot, arm
    self._hover, self._lift, self._approach = hover, lift, approach
    self._tolerance = tolerance
    # A hand slower than `close_steps` (the Jaco's, 1.2 s) gets its own closing time.
    close_steps = max(close_steps, int(np.ceil(
        robot.arms[arm].gripper.close_time / env.control_timestep())))
    self._close_steps, self._release_steps = close_steps, release_steps
    self._stall_steps, self._insert_steps = stall_steps, insert_steps
    self._edge_lift_speed = edge_lift_speed
    # Carry and clearance heights count from the surface the parts lie on (floor or table top).
    self._surface = env.task.arena.support.height
    self._clearance = clearance.AssemblyClearance(env, arm, self._surface)
    self._carry_height = clearance.CarryHeight(self._clearance, self._surface + carry)
    self._grasps = top_down_grasp.TopDownGrasp(env, arm, self._surface, self._clearance)
    self._servo = arm_motion.PoseServo()
    self._unwinder = arm_motion.Unwinder()
    self._carry_watch = arm_motion.ProgressWatch(window=80)
    self._uneven = None   # the hand closes one finger against two (_against_pair)
    self._hold_command = arm_motion.hold_command(robot.arms[arm].gripper,
                                                 top_down_grasp.HOLD_SHORT_OF_CLOSED)
    self._turn_over = turn_over.TurnOver(env, arm, self._surface, self._clearance, close_steps)
    self._stand_up = stand_up.StandUp(env, arm, self._surface, self._clearance, close_steps)
    self.reset()

  def reset(self):
    """Forgets the episode: call after env.reset()."""
    self._servo.reset()
    self._clearance.reset()
    self._turn_over.reset()
    self._stand_up.reset()
    self._grasps.new_reach()
    self._carry_watch.reset()
    self._carry_height.reset()
    self.phase = Phase.REACH
    self._counter = 0
    self._connections = 0
    self._job = None   # (pair, moving part)
    self._grasp = None   # (position, rotation) of the tool at the grasp
    self._hanging = False   # the part is held by its top edge (top_down_grasp.by_top_edge)
    self._turning_flat = False   # ... and is turned flat on its way (top_down_grasp.turns_flat)
    self._plan = None   # (pair, twist) the held part is brought to
    self._grasp_sign = 1.0   # which of the two symmetric grasps
    self._unreachable = set()   # parts the arm stalled on; skipped until the next connection
    self._stalled_grasps = set()   # (part, grasp sign) the reach stalled on, till then too
    self._failed_plans = set()   # (pair, twist) the arm stalled on while carrying
    self._carry_stalls = {}   # part: carries that stalled, till the next connection
    self._stalled = 0
    self._inserting = 0   # control steps in the present INSERT
    self._last_tcp = None
    self._carrying = False   # the held part is on its way over its mate at carry height
    self._root_at_plan = None   # where the root part was when the present plan was made
    self._put_back_path = []   # tool positions _put_back lays, the last one down
    self._lift_path = []   # (tool position, speed) of the lift's legs still to go

  @property
  def job(self):
    """(connector pair, moving part) being worked on, or None."""
    return self._job

  @property
  def subtask(self):
    """(phase name, part being brought in; None between parts)."""
    return self.phase.value, None if self._job is None else self._job[1]

  @property
  def job_just_chosen(self):
    """True on the step a new part was chosen, before the arm moves towards it."""
    return self.phase == Phase.REACH and self._counter == 1

  def take_over(self):
    """Starts afresh from the present assembly (another arm made connections), still
    avoiding the grasps it stalled on: forgetting them, a Baxter arm retried one a dozen
    times."""
    connections = len(self._env.task.state.connections)
    stalled = self._stalled_grasps if connections == self._connections else set()
    self.reset()
    self._connections, self._stalled_grasps = connections, stalled

  # -- choosing work -----------------------------------------------------------------

  def _choose_job(self):
    base, _ = self._robot.base_pose
    return next_part.nearest_open_job(self._env.task, self._env.physics, base, self._unreachable)

  # -- geometry from privileged state -----------------------------------------------

  def closing_local(self):
    """The fingers' closing direction in the tool frame (unit, horizontal when pointing down)."""
    return self._grasps.closing_local()

  def _grasp_pose(self, part, sign=None):
    """Tool pose at the part's grasp point (top_down_grasp.TopDownGrasp), with the present grasp
    or the one of `sign`."""
    return self._grasps.pose(part, self._grasp_sign if sign is None else sign)

  def _against_pair(self):
    """arm_motion.closes_against_pair for this hand, read once the model is compiled."""
    if self._uneven is None:
      self._uneven = arm_motion.closes_against_pair(self._robot, self._env.physics, self._arm)
    return self._uneven

  def _holding(self, part):
    return sensing.holding(self._env.physics, self._robot, self._arm,
                           self._env.task.furniture, part)

  # -- the policy ------------------------------------------------------------------------

  def __call__(self, timestep=None):
    """The action for this control step (privileged state; `timestep` may be None)."""
    env, robot = self._env, self._robot
    action = np.zeros(env.action_spec().shape)
    if len(env.task.state.connections) != self._connections:
      self._after_connection()
    if (self._job is None and self.phase not in _OWN_SKILL
        or self.phase == Phase.REACH and self._counter == 0):
      self._choose_work()
    if self._job is None and self.phase not in _WITHOUT_A_PART:
      return action
    base = self._arm * robot.actions_per_arm
    command = _Command(action, action[base:base + 6], base + 6)
    action[command.grip] = self._gripper_command()
    self._PHASES[self.phase](self, command, None if self._job is None else self._job[1])
    return action

  def _after_connection(self):
    """A connection was made (by this arm or another): let go, and forget what stalled."""
    self._connections = len(self._env.task.state.connections)
    self.phase, self._counter, self._stalled = Phase.RELEASE, 0, 0
    self._unreachable, self._failed_plans, self._stalled_grasps = set(), set(), set()
    self._carry_stalls = {}

  def _choose_work(self):
    """The next part and its grasp; with no part left to bring, a stand-up of the root or
    a turn-over if mates wait for one."""
    env, task = self._env, self._env.task
    self._job = self._choose_job()
    if self._job is None and self._unreachable and not task.state.complete:
      self._unreachable = set()   # every part skipped once: try them all again
      self._job = self._choose_job()
    self._counter, self._stalled = 1, 0
    self._grasps.new_reach()
    if self._job is not None:
      self._grasp_sign = mating.choose_grasp_sign(
          env, self._arm, self._job[1], self._grasp_pose, self._hover, self._approach,
          self._failed_plans, self._stalled_grasps, self._carry_height.nominal)
    elif self.phase != Phase.UNWIND and stand_up.needed(task, env.physics, self._surface):
      self._stand_up.start(self.closing_local())
      self.phase = Phase.STAND_UP
    elif self.phase != Phase.UNWIND and turn_over.waiting(
        task, env.physics, self._surface) and self._turn_over.start(self.closing_local()):
      self.phase = Phase.TURN_OVER

  def _gripper_command(self):
    """Closed while the hand holds a part, else open; a hand that closes one finger against
    two holds short of its closed limit (arm_motion.hold_command), but a panel held by its
    edge is squeezed fully: 0.05 rad short opens the fingers off a 6 mm wall."""
    if self.phase not in _HOLDING:
      return -1.0
    if self.phase != Phase.CLOSE and self._against_pair() and not self._hanging:
      return self._hold_command
    return 1.0

  # -- the phases: each fills in this arm's part of the action and moves the phase on ----

  def _on_reach(self, command, moving):
    """Open, to `hover` over the grasp point, over the assembly and round the base."""
    point, rot = self._grasp_pose(moving)
    goal = point + [0.0, 0.0, self._hover]
    route = self._clearance
    edge = self._grasps.by_top_edge(moving)
    command.tool[:] = self._servo(self._robot, self._env.physics, self._arm,
                                  route.arc_waypoint(route.over_assembly(goal)), rot)
    distance, angle = arm_motion.pose_error(self._robot, self._env.physics, self._arm, goal, rot)
    self._settled()   # the hand's last position, for the descent's test
    if self._reach_stalled(moving):
      return
    if angle < 0.05 and distance < (top_down_grasp.EDGE_REACH if edge else 0.02):
      self.phase, self._stalled = Phase.DESCEND, 0

  def _on_descend(self, command, moving):
    """Straight down to the grasp point, slowly; close once there and at rest."""
    goal, rot = self._grasp_pose(moving)
    edge = self._grasps.by_top_edge(moving)
    command.tool[:] = self._servo(
        self._robot, self._env.physics, self._arm, goal, rot, gain=top_down_grasp.DESCEND_GAIN,
        max_speed=top_down_grasp.HANGING_SPEED if edge else 1.0)
    distance, angle = arm_motion.pose_error(self._robot, self._env.physics, self._arm, goal, rot)
    settled = self._settled()
    if self._reach_stalled(moving):
      return
    if angle < 0.05 and settled and distance < (
        top_down_grasp.EDGE_GATE if edge else 0.006):
      self.phase, self._counter, self._stalled = Phase.CLOSE, 0, 0
      self._grasp, self._hanging = (goal, rot), edge
      self._turning_flat = edge and self._grasps.turns_flat(moving)

  def _reach_stalled(self, moving):
    """Counts a step of the reach or descent; past `stall_steps` the arm cannot get there:
    home, and another part (True)."""
    self._stalled += 1
    if self._stalled <= self._stall_steps:
      return False
    self._unreachable.add(moving)
    self._stalled_grasps.add((moving, self._grasp_sign))
    self._unwind()   # home before the next part
    if len(self._unreachable) >= len(self._env.task.furniture.parts):
      self._unreachable = set()
    return True

  def _on_close(self, command, moving):
    """Squeeze for `close_steps`, the tool held at the grasp."""
    command.tool[:] = self._servo(self._robot, self._env.physics, self._arm, *self._grasp)
    self._counter += 1
    if self._counter >= self._close_steps:
      self.phase = Phase.LIFT
      top = self._grasp[0] + [0.0, 0.0, self._lift]
      self._lift_path = [(top, self._edge_lift_speed if self._hanging else 1.0)]
      if self._hanging:   # then out of its rack along its plane, if it would strike
        slide = self._clearance.rack_exit(
            moving, self._job[0], self._grasp[0], self._grasp[1] @ self.closing_local(),
            self._carry_height.nominal)
        if slide is not None:
          self._lift_path.append((top + slide, top_down_grasp.HANGING_SPEED))

  def _on_lift(self, command, moving):
    """Up by `lift`, only clear of the floor: the carry rises further on its way in, since
    straight up is out of reach for a part at the edge of the work area. A panel that
    would strike its rack's neighbours on the carry then slides out of the rack along its
    plane (clearance.rack_exit), at HANGING_SPEED."""
    robot, physics, arm = self._robot, self._env.physics, self._arm
    goal, speed = self._lift_path[0]
    command.tool[:] = self._servo(robot, physics, arm, goal, self._grasp[1], max_speed=speed)
    self._counter += 1
    if (arm_motion.pose_error(robot, physics, arm, goal, self._grasp[1])[0] < 0.03
        or self._counter > self._close_steps + 40):   # as high or far as it goes: on
      self._lift_path.pop(0)
      self._counter = self._close_steps
      if not self._lift_path:
        self.phase = Phase.ALIGN

  def _on_align(self, command, moving):
    """Carry the part over its mate at carry height, then down to `approach` short of it,
    turned to its mating pose; a carry stalled with a joint at its limit replans."""
    plan = self._held_plan(moving)
    if plan is None:
      return
    pair, twist = plan
    part_pos, part_rot, goal = self._mate_goal(moving, pair, twist, self._approach)
    if self._carrying:
      self._carry(command, moving, pair, twist, part_pos, part_rot, goal)
      return
    # The last centimetres slowly: at gain 0.6 the arm hunted +-1 cm about the goal.
    distance, angle = self._servo_held(command, moving, part_pos, part_rot, goal, gain=0.6)
    # A hanging panel goes down between standing walls with 3 mm to spare (half scale).
    if distance < (0.003 if self._hanging else 0.01) and angle < 0.03:
      self.phase = Phase.INSERT
    elif self._carry_watch.stalled(distance, angle) and (
        arm_motion.pinned(self._robot, self._env.physics, self._arm)):
      self._carry_stalled(moving, pair, twist)

  def _on_insert(self, command, moving):
    """Close the last gap and connect once the pair is well aligned. The part stops 0.4 of
    the connect distance short (4 mm at scale 0.5), which shrinks with the furniture: a
    fixed 4 mm lay outside scale 0.22's 0.9 x 4.4 mm tolerance."""
    plan = self._held_plan(moving)
    if plan is None:
      return
    pair, twist = plan
    task = self._env.task
    part_pos, part_rot, goal = self._mate_goal(moving, pair, twist,
                                               0.4 * task.thresholds.distance)
    if self._carrying:
      self._carry(command, moving, pair, twist, part_pos, part_rot, goal)
      return
    self._servo_held(command, moving, part_pos, part_rot, goal, gain=0.3)
    if sensing.attachable(task, self._env.physics, pair, self._tolerance):
      self._plan = None
      command.action[-1] = 1.0

  def _held_plan(self, moving):
    """The (pair, twist) the held part is brought to, planned afresh when there is none;
    None (the phase moved on) when the part was dropped, has no mate left, or the plan
    failed.

    A mate out of reach stalls the carry; an insertion that has not attached within
    `insert_steps` (they take 8-12 steps), or a held part that has moved the root by 3 cm
    on its way down, pushes the light, scaled assembly out of reach (checked only after
    the carry: aborting carries dropped legs of tall tables on the assembly). The arm then
    lifts clear and plans another mate or twist.
    """
    env, task = self._env, self._env.task
    if not self._holding(moving):
      # Dropped, or never held: start over with the other grasp (a leg slipped from the
      # same grasp for a whole Baxter episode), and with another part once both failed.
      self._stalled_grasps.add((moving, self._grasp_sign))
      if (moving, -self._grasp_sign) in self._stalled_grasps:
        self._unreachable.add(moving)
      self._plan = None
      self._to_next_reach()
      return None
    if self._plan is None:
      self._plan, self._carrying = mating.plan_mating(
          env, self._arm, moving, self._approach, self._failed_plans,
          carry_top=self._carry_height.nominal), True
      self._carry_watch.reset()
      self._carry_height.reset()
      if self._plan is None:
        self._no_mate_left(moving)
        return None
      self._plan = self._plan[1:]
      self._root_at_plan = part_geometry.part_pose(env.physics, task.furniture,
                                                   task.root_part)[0]
    pair, twist = self._plan
    self._stalled += 1
    self._inserting = self._inserting + 1 if self.phase == Phase.INSERT else 0
    pushed = not self._carrying and np.linalg.norm(part_geometry.part_pose(
        env.physics, task.furniture, task.root_part)[0] - self._root_at_plan) > 0.03
    if self._stalled > 2 * self._stall_steps or self._inserting > self._insert_steps or pushed:
      self._failed_plans.add((pair, twist))
      self._plan, self._stalled, self._inserting = None, 0, 0
      self.phase = Phase.ALIGN
      return None
    return pair, twist

  def _mate_goal(self, moving, pair, twist, offset):
    """(part position `offset` back from its mating pose along the side it comes in from,
    part rotation there, the tool pose that puts it there)."""
    env = self._env
    part_pos, part_rot, side = mating.mate_pose(env, pair, moving, twist)
    part_pos = part_pos + offset * side
    return part_pos, part_rot, mating.tool_goal_for_part(env, self._arm, moving, part_pos,
                                                         part_rot)

  def _carry(self, command, moving, pair, twist, part_pos, part_rot, goal):
    """Over the tool goal at carry height (rising clear of the assembly first, round the
    base); there, on to the goal below. Stalled up there, the carry comes lower, or with a
    joint at its limit the arm replans."""
    robot, physics, arm = self._robot, self._env.physics, self._arm
    high = self._carry_height.waypoint(goal, moving, part_pos, part_rot, self._hanging)
    waypoint = self._clearance.rise_first(self._clearance.arc_waypoint(high), moving, high[2])
    waypoint = self._clearance.outside_rack(waypoint, moving)
    command.tool[:] = self._servo(robot, physics, arm, waypoint, goal[1],
                                  max_turn=arm_motion.CARRY_TURN,
                                  max_speed=top_down_grasp.FLAT_CARRY_SPEED
                                  if self._turning_flat else 1.0)
    distance, angle = arm_motion.pose_error(robot, physics, arm, high, goal[1])
    self._carrying = not (distance < 0.03 and angle < 0.05)
    if not self._carrying:
      self._carry_watch.reset()   # on to the goal below
    elif self._carry_watch.stalled(distance, angle):   # out of reach up there?
      pinned = arm_motion.pinned(robot, physics, arm)
      if self._carry_height.lower(goal, pinned):
        self._carry_watch.reset()
      elif pinned:
        self._carry_stalled(moving, pair, twist)

  def _servo_held(self, command, moving, part_pos, part_rot, goal, gain):
    """The tool to `goal` at `gain` (slower with a hanging panel); returns the held part's
    distance (m) and angle (rad) from (part_pos, part_rot)."""
    physics, furniture = self._env.physics, self._env.task.furniture
    command.tool[:] = self._servo(
        self._robot, physics, self._arm, *goal, gain=gain,
        max_speed=top_down_grasp.HANGING_SPEED if self._hanging else 1.0)
    current, rot = part_geometry.part_pose(physics, furniture, moving)
    return (np.linalg.norm(part_pos - current),
            np.linalg.norm(geometry.mat_to_axis_angle(part_rot @ rot.T)))

  def _on_put_back(self, command, moving):
    """Along the path _put_back laid, down, then release."""
    if not self._holding(moving):
      self._to_next_reach()
      return
    robot, physics, arm = self._robot, self._env.physics, self._arm
    goal, rot = self._put_back_path[self._counter], self._grasp[1]
    lowering = self._counter == len(self._put_back_path) - 1
    waypoint = goal if lowering else self._clearance.arc_waypoint(goal)
    command.tool[:] = self._servo(robot, physics, arm, waypoint, rot, max_turn=0.3,
                                  gain=top_down_grasp.DESCEND_GAIN if lowering else 1.0)
    distance, angle = arm_motion.pose_error(robot, physics, arm, goal, rot)
    self._stalled += 1
    if distance < (0.01 if lowering else 0.03) and angle < 0.05:
      self._counter += 1
    if self._counter == len(self._put_back_path) or self._stalled > 2 * self._stall_steps:
      self.phase, self._counter = Phase.RELEASE, 0

  def _on_planned_carry(self, command, moving):
    """Along the joint path _plan_carry planned (arm_motion.Unwinder.follow); there, on
    to the approach pose and the insertion as after a carry."""
    if not self._holding(moving):
      self._stalled_grasps.add((moving, self._grasp_sign))
      self._plan = None
      self._to_next_reach()
      return
    command.tool[:] = self._unwinder(self._robot, self._env.physics, self._arm)
    if self._unwinder.done:
      self.phase, self._stalled = Phase.ALIGN, 0
      self._carry_watch.reset()
      task = self._env.task
      self._root_at_plan = part_geometry.part_pose(self._env.physics, task.furniture,
                                                   task.root_part)[0]

  def _on_release(self, command, moving):
    """Open for `release_steps`; then back off, and up clear of the assembly: a hand left
    low beside a standing leg strikes it when it turns down for the next part."""
    self._counter += 1
    if self._counter >= self._release_steps:
      self.phase, self._counter = Phase.RETREAT, 0
      pos, rot = self._robot.tcp_pose(self._env.physics, self._arm)
      back = pos - 0.1 * rot[:, 2] + [0.0, 0.0, 0.1]
      back[2] = max(back[2], self._clearance.safe_height())
      self._grasp = (back, rot)

  def _on_retreat(self, command, moving):
    """To the point the release chose, over the assembly; then the next reach."""
    robot, physics, arm = self._robot, self._env.physics, self._arm
    route = self._clearance
    command.tool[:] = self._servo(robot, physics, arm, route.arc_waypoint(route.over_assembly(
        self._grasp[0])), self._grasp[1])
    self._counter += 1
    if arm_motion.pose_error(robot, physics, arm, *self._grasp)[0] < 0.03 or self._counter > 40:
      self._to_next_reach()

  def _on_turn_over(self, command, moving):
    """The turn-over's own steps (turn_over.TurnOver), gripper included."""
    command.tool[:], command.action[command.grip] = (self._turn_over(self._servo),
                                                     self._turn_over.gripper())
    if self._turn_over.step == turn_over.Step.DONE:
      self._to_next_reach(keep_clear=True)

  def _on_stand_up(self, command, moving):
    """The stand-up's own steps (stand_up.StandUp), gripper included."""
    command.tool[:], command.action[command.grip] = (self._stand_up(self._servo),
                                                     self._stand_up.gripper())
    if self._stand_up.step == stand_up.Step.DONE:
      self._to_next_reach(keep_clear=True)

  def _on_unwind(self, command, moving):
    """Home along a joint-space path (arm_motion.Unwinder); then the next reach."""
    command.tool[:] = self._unwinder(self._robot, self._env.physics, self._arm)
    if self._unwinder.done:
      self.phase, self._counter, self._stalled = Phase.REACH, 0, 0

  _PHASES = {Phase.REACH: _on_reach, Phase.DESCEND: _on_descend, Phase.CLOSE: _on_close,
             Phase.LIFT: _on_lift, Phase.ALIGN: _on_align, Phase.INSERT: _on_insert,
             Phase.RELEASE: _on_release, Phase.RETREAT: _on_retreat,
             Phase.PUT_BACK: _on_put_back, Phase.UNWIND: _on_unwind,
             Phase.PLANNED_CARRY: _on_planned_carry,
             Phase.TURN_OVER: _on_turn_over, Phase.STAND_UP: _on_stand_up}

  # -- moving between phases -------------------------------------------------------------

  def _settled(self):
    """The hand has come to rest, where its fingers curl below the tool centre: the Jaco's,
    still moving at the descent's gate, dipped and swung 1 cm sideways while closing, and
    the tips struck the floor beside the part."""
    tcp, _ = self._robot.tcp_pose(self._env.physics, self._arm)
    last, self._last_tcp = self._last_tcp, tcp
    return (not self._against_pair() or
            last is not None and np.linalg.norm(tcp - last) < top_down_grasp.SETTLED_SPEED)

  def _unwind(self, keep_clear=False):
    self._unwinder.start(self._robot, self._env.physics, self._arm,
                         keep_clear=self._clearance.above_assembly if keep_clear else None)
    self.phase, self._counter, self._stalled = Phase.UNWIND, 0, 0

  def _to_next_reach(self, keep_clear=False):
    """On to the next reach, by way of home when the arm has wound far from it."""
    self.phase, self._counter = Phase.REACH, 0
    if self._unwinder.distance_from_home(self._robot, self._env.physics, self._arm) > UNWIND_FROM:
      self._unwind(keep_clear)

  def _carry_stalled(self, moving, pair, twist):
    """A carry that stopped short of its mating pose with a joint at its limit: another
    mate or twist first; stalled again, a planned joint-space path there (_plan_carry),
    or else set the part down and take it with its other grasp (the Panda's last joint
    was pinned at its limit after every replan). Other
    stalls keep the 2 * stall_steps budget (a slow approach may still get there)."""
    self._failed_plans.add((pair, twist))
    self._plan, self._stalled, self._inserting = None, 0, 0
    self._carry_stalls[moving] = self._carry_stalls.get(moving, 0) + 1
    if self._carry_stalls[moving] == 2:
      if self._plan_carry(moving, [(pair, twist)] + sorted(self._failed_plans - {(pair, twist)})):
        return
      self._stalled_grasps.add((moving, self._grasp_sign))
      self._failed_plans = set()   # those failed with the other grasp
      self._put_back()

  def _plan_carry(self, moving, plans):
    """A joint-space path (joint_planner.plan_to_pose: the arm and the held part clear of
    everything) to the approach pose of the first (pair, twist) in `plans` it finds one
    for, before the part is put back: the task-space carry stalls with a joint at its
    limit or the forearm on the assembly where a path round them exists (Panda, the last
    side of nightstand_drawer_white). True when the arm follows one (PLANNED_CARRY);
    False without OMPL or without a path."""
    if not joint_planner.AVAILABLE:
      return False
    furniture = self._env.task.furniture
    table, body = furniture.connectors, furniture.body_ids[moving]
    plans = [(pair, twist) for pair, twist in plans
             if moving in (table.part[table.pair_a[pair]], table.part[table.pair_b[pair]])]
    for pair, twist in plans[:_PLANNED_MATES]:
      _, _, goal = self._mate_goal(moving, pair, twist, self._approach)
      path = joint_planner.plan_to_pose(self._robot, self._env.physics, self._arm, *goal,
                                        held_body=body)
      if path is not None:
        self._failed_plans.discard((pair, twist))
        self._plan, self._carrying = (pair, twist), False
        self._unwinder.follow(self._robot, self._arm, path.q, max_turn=arm_motion.CARRY_TURN,
                              max_speed=top_down_grasp.FLAT_CARRY_SPEED
                              if self._turning_flat else 1.0)
        self.phase, self._counter, self._stalled, self._inserting = (
            Phase.PLANNED_CARRY, 0, 0, 0)
        return True
    return False

  def _no_mate_left(self, moving):
    """Every mate and twist of the held part has failed with this grasp. Dropped where it
    hung and taken the same way again, it looped 30 times (Sawyer,
    table_four_leg_kids_white). It is set down and taken with the other grasp, its failed
    mates forgotten; with both grasps spent, the other parts go first until the next
    connection."""
    self._stalled_grasps.add((moving, self._grasp_sign))
    if (moving, -self._grasp_sign) in self._stalled_grasps:
      self._unreachable.add(moving)
    self._failed_plans = set()
    self._put_back()

  def _put_back(self):
    """Over the spot the part was taken from at the height it stalled at (the way round is
    long: 2 * stall_steps), down, and let go; first straight up off the assembly if the
    part rests on it (a chair's back, dragged off the seat, knocked the chair over)."""
    tcp, _ = self._robot.tcp_pose(self._env.physics, self._arm)
    task, spot = self._env.task, self._grasp[0]
    self._put_back_path = [spot + [0.0, 0.0, z] for z in (tcp[2] - spot[2], self._lift, 0.008)]
    if sensing.touching(self._env.physics, task.furniture, self._job[1],
                        part_geometry.root_group(task)):
      self._put_back_path.insert(0, tcp + [0.0, 0.0, 0.05])
    self.phase, self._counter = Phase.PUT_BACK, 0
