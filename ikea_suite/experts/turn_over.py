"""Turning the assembly over, for furniture whose root has mates on both faces.

A chair's seat lies upside down for its legs to go in from above; its back
slot then faces the floor. A mate whose part would sit below the surface
waits (`under_support`), and once only such mates are left, one arm turns
the assembly over (`TurnOver`): it takes a standing leg from the side, at
the height of the seat, lifts the assembly clear, rolls it half a turn about
the hand's own axis (the arm's last joint), sets it down on its legs and
lets go. Everything goes through the same task-space actions a learning
agent sends; privileged state only says where the parts are.
"""

import enum

import numpy as np

from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import arm_skill
from ikea_suite.experts import part_geometry
from ikea_suite.experts import sensing
from ikea_suite.tasks import planner

# A part mated this far (m) or more below the surface would sit in it: its mate waits.
BELOW = 0.01
# The hand takes the handle this far (m) above the top of the root (the fingers reach
# past the leg over the seat), and holds this far (m) off the surface
# the lowest point of the assembly as it rolls, and as it is let go onto its legs.
OVER_SEAT, ROLL_CLEARANCE, DROP = 0.03, 0.04, 0.01
# The hand, pointing sideways, passes this far (m) over the surface.
HAND_CLEARANCE = 0.015
# Weight (per m) of the waiting mates' distance from the base, once turned over, away
# from that of the assembly's centre before.
SLOT_OUT = 2.0
# The hand comes in along its axis from this far (m) out, and leaves the same way.
STANDOFF = 0.12
# The hand passes this far (m) over the assembly on its way to the standoff.
OVER_CLEARANCE = 0.08
# The grasp rises this far (m) at a time up a leg the arm, taking it lower, would touch
# the floor or the assembly at; a handle touched at every height costs COLLIDES more
# (metres of pose error, as the reach checks count them), and a raised grasp RAISED per
# metre raised: taken higher, the chair hangs farther below the roll's axis and twists
# harder in the fingers as it rolls, so a leg the arm takes low without touching
# anything comes first.
RAISE, COLLIDES, RAISED = 0.03, 1.0, 10.0
# A leg the hand, going in, has pushed this far (m) is given up: the hand followed the
# leg it pushed and slid the chair 0.55 m out, beyond the reach the back needs
# (chair_back_dark_bar, chair_back_white_round, chair_frame_back_black_tall).
PUSHED = 0.02
# The hand backing out empty (_WATCHED) that comes no nearer its goal for this many
# control steps has stalled, as past the step budget: the Sawyer's, pressed against the
# floor beside the chair, stood 4 cm from where it backed out to for the whole budget of
# 250, and as long again going up. The way in is left its budget: the Panda's hand crept
# the last centimetres to its standoff for 96 steps and then took the chair over.
STALL_STEPS = 40

# Rad the hand rolls per control step (about 20 degrees a second at 20 Hz).
ROLL_STEP = 0.02
# A roll that stops this short (rad) of the half turn, the hand no longer following for
# ROLL_WAIT control steps, is done: the Panda's last joint met its limit at 3.0 rad
# (chair_back_dark_bar), and set down 8 degrees from level the chair lands on its
# legs, where let go from the lift height at the end of the step budget it fell on its side.
ROLL_SLACK, ROLL_WAIT = 0.35, 20


def _twist(table, pair):
  valid = table.twist_angles[pair][table.twist_valid[pair]]
  return 0.0 if table.any_twist[pair] or not len(valid) else float(valid[0])


def under_support(physics, furniture, pair, moving, surface):
  """Whether `moving`, mated at the pair onto the assembly as it lies, would reach BELOW
  or more into the surface (a chair's back under its upside-down seat)."""
  pos, rot, _ = part_geometry.mated_part_pose(physics, furniture, pair, moving,
                                              _twist(furniture.connectors, pair))
  corners = part_geometry.part_corners(furniture, moving, pos, rot)
  return bool(corners[:, 2].min() < surface - BELOW)


def waiting(task, physics, surface):
  """Connectors of the root's group whose open mates wait for the assembly to be turned
  over (their parts would sit in the surface)."""
  table, labels = task.furniture.connectors, task.state.group_labels()
  root = labels[task.root_part]
  out = []
  for pair in np.flatnonzero(planner.open_pairs(table, task.state)):
    a, b = table.pair_a[pair], table.pair_b[pair]
    if (labels[table.part[a]] == root) != (labels[table.part[b]] == root):
      fixed, moving = (a, b) if labels[table.part[a]] == root else (b, a)
      if under_support(physics, task.furniture, pair, table.part[moving], surface):
        out.append(int(fixed))
  return out


def handles(physics, furniture, parts, root):
  """[(part, approach, closing)]: each standing rod of the group (a leg; the root itself
  when it is one, a round-post table's post stood on its end with the base on it: see
  stand_up), taken from outside the assembly along one of its side faces' normals
  (`approach`, unit, horizontal; any of them for the root, in the middle of the
  assembly), the fingers closing across it (`closing`, either way)."""
  centre = part_geometry.parts_corners(physics, furniture, parts)[:, :2].mean(axis=0)
  out = []
  for part in parts:
    pos, rot = part_geometry.part_pose(physics, furniture, part)
    lo, hi = furniture.spec.parts[part].bounds
    order = np.argsort(hi - lo)
    if abs(rot[2, order[2]]) < 0.95 or (hi - lo)[order[1]] > 0.3 * (hi - lo)[order[2]]:
      continue   # not a rod standing on end
    for axis in order[:2]:
      for sign in (1.0, -1.0):
        approach = sign * rot[:, axis]
        approach = approach - approach[2] * np.array([0.0, 0.0, 1.0])
        approach /= np.linalg.norm(approach)
        if part != root and approach[:2] @ (centre - pos[:2]) <= 0.0:   # from inside it
          continue
        closing = np.cross([0.0, 0.0, 1.0], approach)
        out += [(part, approach, closing), (part, approach, -closing)]   # either finger first
  return out


class Step(enum.Enum):
  OVER = "over"         # over the standoff, clear of the assembly, the hand pointing sideways
  STANDOFF = "standoff"  # level with the grasp, STANDOFF out along the approach
  IN = "in"             # along the approach to the handle, slowly: at full speed the hand
                        # swung 7 degrees and pushed the chair 2.4 cm
  CLOSE = "close"       # squeeze
  LIFT = "lift"         # up until the assembly rolls clear of the surface
  ROLL = "roll"         # half a turn about the approach axis
  LOWER = "lower"       # down until the legs are DROP above the surface
  OPEN = "open"         # let go
  OUT = "out"           # back along the approach
  UP = "up"             # up clear of the assembly: unwinding from low beside the chair
                        # just stood up, the arm knocked it over
  DONE = "done"


# The steps a stall ends early (STALL_STEPS): the empty hand's way out.
_WATCHED = (Step.OUT, Step.UP)


class TurnOver(arm_skill.SteppedSkill):
  """One arm's turn-over of the root's group: call `start`, then each control step
  `__call__` for the tool goal; `step` says where it is, `failed` whether it gave up.

  Args:
    env: the environment.
    arm: the arm's index.
    surface: height (m) of the surface the assembly stands on.
    route: the arm's clearance.AssemblyClearance (the way over the assembly to the handle).
    close_steps: control steps the fingers take to close.
  """

  STEPS = Step

  def reset(self):
    """Forgets the episode's turn-overs."""
    self.step, self.failed = Step.DONE, False
    self._failed_handles = set()   # (part, approach) that slipped or stalled, this episode
    # The present turn-over, chosen by `start`: the fingers' closing direction in the tool
    # frame, the leg taken, the approach axis, grasp position and rotation, lift height
    # and which way the roll turns.
    self._closing_local = None
    self._part = self._approach = self._point = self._rot = None
    self._lift, self._sign = 0.0, 1.0
    self._count = 0   # control steps in the present step
    self._rolled, self._roll_idle = 0.0, 0   # rad rolled so far; steps the hand lagged the roll
    self._out = None   # where the hand backs out to, along the approach
    self._leg_at = None   # (x, y) of the leg as the hand went in (PUSHED)
    self._watch = arm_motion.ProgressWatch(window=STALL_STEPS)
    self._watched = None   # the step _watch follows

  def _group(self):
    return part_geometry.root_group(self._env.task)

  def _plan(self, part, approach, closing, q):
    """(grasp position, grasp rotation, lift height, cost of the way there) for a handle,
    the arm's joints at `q` now, or None when the legs are too short to hold above the rest
    of the assembly (the root handle is taken as low as the hand allows). The grasp rises
    up the leg by RAISE until the arm's links, following the servo's own path over the
    assembly, out to the standoff and in to the leg, touch nothing there
    (Manipulator.contacts_at); the cost is RAISED per metre raised, and COLLIDES more
    where they touch something at every height."""
    physics, furniture = self._env.physics, self._env.task.furniture
    robot, root = self._env.task.robot, self._env.task.root_part
    pos, _ = part_geometry.part_pose(physics, furniture, part)
    rot = arm_motion.tool_rotation(approach, closing, self._closing_local)
    handle_top = part_geometry.parts_corners(physics, furniture, [part])[:, 2].max()
    height = self._surface + HAND_CLEARANCE + arm_motion.hand_below_tool(
        robot, physics, self._arm, rot)
    if part != root:
      height = max(height,
                   part_geometry.parts_corners(physics, furniture, [root])[:, 2].max() + OVER_SEAT)
    if height > handle_top - 0.02:
      return None
    # The arm's links, not the hand (its clearance is HAND_CLEARANCE and OVER_SEAT):
    # followed along the servo's path, from here over the chair to the standoff, then in,
    # and judged where the path ends at its goal. One that ends short says nothing of
    # where the arm will be: from the Panda's home it wound the first two joints to their
    # limits 0.17 m short, with the forearm in the legs, where the arm itself took that
    # leg well (chair_back_ivar). What counts is the floor, the fixtures and the assembly;
    # brushing a loose part (the back in its rack) did not stop the Panda.
    group = set(self._group())
    loose = {int(furniture.body_ids[p]) for p in range(len(furniture.spec.parts))
             if p not in group}
    dt = self._env.control_timestep()
    standoff = pos[:2] - STANDOFF * approach[:2]
    q, _, _ = arm_motion.servo_path_end(robot, self._arm, q, np.array(
        [*standoff, self._over_height(rot)]), rot, dt)
    best, lowest = None, height
    for height in np.arange(lowest, handle_top - 0.02 + 1e-9, RAISE):
      point = np.array([pos[0], pos[1], height])
      at, cost = q, RAISED * (height - lowest)
      for goal in (point - STANDOFF * approach, point):
        at, distance, angle = arm_motion.servo_path_end(robot, self._arm, at, goal, rot, dt)
        if distance < 0.02 and angle < 0.05 and any(
            body not in loose for _, body, _ in robot.contacts_at(physics, at, hand=False)):
          cost += COLLIDES
      if best is None or cost < best[0]:
        best = (cost, point)
      if cost < COLLIDES:   # touches nothing: no higher
        break
    cost, point = best
    # Lifted by `lift`, every corner swings about the approach axis through the grasp
    # point at most `reach` from it, and clears the surface by ROLL_CLEARANCE.
    corners = part_geometry.parts_corners(physics, furniture, self._group()) - point
    across = corners - np.outer(corners @ approach, approach)
    reach = np.linalg.norm(across, axis=1).max()
    lift = max(0.0, self._surface + ROLL_CLEARANCE + reach - point[2])
    return point, rot, lift, cost

  def start(self, closing_local):
    """Chooses the handle and grasp the arm reaches best (grasp, lifted, half-rolled and
    rolled poses), `closing_local` being the fingers' closing direction in the tool
    frame; False when there is none."""
    self._closing_local = closing_local
    env, robot = self._env, self._env.task.robot
    physics, task = env.physics, env.task
    base, _ = robot.base_pose
    cpos, _ = task.furniture.connectors.world_frames(*task.furniture.part_poses(physics))
    slots = cpos[waiting(task, physics, self._surface)]
    centre = part_geometry.parts_corners(physics, task.furniture, self._group()).mean(axis=0)
    best = None
    every = handles(physics, task.furniture, self._group(), task.root_part)
    options = [h for h in every if (h[0], tuple(np.round(h[1], 1))) not in self._failed_handles]
    if not options:   # every one has failed once: try them all again
      self._failed_handles, options = set(), every
    q = robot.arm_qpos(physics)
    for part, approach, closing in options:
      plan = self._plan(part, approach, closing, q)
      if plan is None:
        continue
      point, rot, lift, way = plan
      for sign in (1.0, -1.0):
        up = point + [0.0, 0.0, lift]
        poses = [(point - STANDOFF * approach, rot), (point, rot), (up, rot),
                 (up, geometry.axis_angle_to_mat(sign * np.pi / 2 * approach) @ rot),
                 (up, geometry.axis_angle_to_mat(sign * 0.95 * np.pi * approach) @ rot)]
        # Turned over, the waiting mates (a chair's back slot) had best lie as far from
        # the base as the assembly's centre does now, where the root was placed for the
        # arm: rolled in to 0.27-0.32 m of the base, the back's carry stalled with the
        # elbow at its limit; on the far side of the seat, with the wrist at its limit.
        rolled = point + (slots - point) @ geometry.axis_angle_to_mat(np.pi * approach).T
        cost = way + SLOT_OUT * np.abs(np.linalg.norm(rolled[:, :2] - base[:2], axis=1)
                                 - np.linalg.norm(centre[:2] - base[:2])).mean()
        cost += 2.0 * arm_motion.cramped(base, point, approach)
        # The waiting part then goes in from above: rolled over a near leg, the back's slot
        # lay 0.26 m from the Panda's base, where its tool, pointing down 0.5 m up, could
        # not reach, and both twists stalled (chair_back_ivar, chair_back_black_wide).
        cost += 2.0 * np.mean([arm_motion.cramped(base, slot, np.array([0.0, 0.0, -1.0]))
                               for slot in rolled])
        for goal in poses:
          miss, margin, _ = robot.reach_check(physics, self._arm, *goal)
          cost += miss + np.maximum(0.0, 0.2 - margin).sum()
        if best is None or cost < best[0]:
          best = (cost, part, approach, point, rot, lift, sign)
    if best is None:
      self.failed = True
      return False
    _, self._part, self._approach, self._point, self._rot, self._lift, self._sign = best
    self.step, self.failed, self._count, self._rolled = Step.OVER, False, 0, 0.0
    self._roll_idle = 0
    return True

  @property
  def part(self):
    """The leg the hand takes."""
    return self._part

  def gripper(self):
    """+1 to close, -1 to open, for this step."""
    return 1.0 if self.step in (Step.CLOSE, Step.LIFT, Step.ROLL, Step.LOWER) else -1.0

  def _goal(self):
    standoff = self._point - STANDOFF * self._approach
    up = self._point + [0.0, 0.0, self._lift]
    if self.step == Step.OVER:
      return np.array([*standoff[:2], self._over_height()]), self._rot
    if self.step == Step.STANDOFF:
      return standoff, self._rot
    if self.step in (Step.IN, Step.CLOSE):   # to the leg where it stands now
      pos, _ = part_geometry.part_pose(self._env.physics, self._env.task.furniture, self._part)
      self._point[:2] = pos[:2]
      return self._point, self._rot
    if self.step == Step.LIFT:
      return up, self._rot
    rolled = geometry.axis_angle_to_mat(self._sign * self._rolled * self._approach) @ self._rot
    if self.step == Step.ROLL:
      return up, rolled
    tcp, _ = self._env.task.robot.tcp_pose(self._env.physics, self._arm)
    if self.step == Step.LOWER:
      lowest = part_geometry.parts_corners(self._env.physics, self._env.task.furniture,
                                           self._group())[:, 2].min()
      return tcp - [0.0, 0.0, lowest - self._surface - DROP], rolled
    if self.step == Step.UP:
      return np.array([*self._out[:2], self._route.safe_height()]), rolled
    return self._out, rolled   # OPEN, OUT

  def __call__(self, servo):
    """The task-space action entries (6) for this control step, from `servo` (an
    arm_motion.PoseServo); advances the steps."""
    env, robot = self._env, self._env.task.robot
    physics, arm = env.physics, self._arm
    goal = self._goal()
    slow = self.step in (Step.IN, Step.LOWER)
    waypoint = (self._route.arc_waypoint(self._route.over_assembly(goal[0]))
                if self.step == Step.OVER else goal[0])
    action = servo(robot, physics, arm, waypoint, goal[1], gain=0.3 if slow else 1.0,
                   max_turn=0.3 if self.step == Step.ROLL else 1.0,
                   max_speed=0.3 if self.step in (Step.IN, Step.LIFT, Step.LOWER) else 1.0)
    distance, angle = arm_motion.pose_error(robot, physics, arm, *goal)
    self._count += 1
    pushed = self.step == Step.IN and np.linalg.norm(part_geometry.part_pose(
        physics, env.task.furniture, self._part)[0][:2] - self._leg_at) > PUSHED
    slipped = self.step in (Step.LIFT, Step.ROLL, Step.LOWER) and not sensing.holding(
        physics, robot, arm, env.task.furniture, self._part)
    if pushed or slipped:   # pushing the chair along, or it slipped: let go, out
      self._give_up()
      self.step, self._count = Step.OPEN, 0
      self._set_out()
      return action
    near = distance < (0.005 if self.step in (Step.IN, Step.LOWER) else 0.02) and angle < (
        0.02 if self.step == Step.STANDOFF else 0.05)   # squared up before it goes in
    if self.step == Step.ROLL:
      self._roll_idle = 0 if angle < 0.1 else self._roll_idle + 1
      if angle < 0.1:
        self._rolled = min(np.pi, self._rolled + ROLL_STEP)
      near = self._rolled >= np.pi and angle < 0.05
      if not near and self._roll_idle > ROLL_WAIT and self._rolled >= np.pi - ROLL_SLACK:
        self._rolled, near = self._measured_roll(), True   # set down as far as it turned
    if self.step in (Step.CLOSE, Step.OPEN):
      near = self._fingers_done()
    if self.step != self._watched:
      self._watched = self.step
      self._watch.reset()
    stalled = self.step in _WATCHED and self._watch.stalled(distance, angle)
    if near:
      self._next()
    elif self._count > self._budget or stalled:
      if self.step not in (Step.OPEN, Step.OUT, Step.UP):
        self._give_up()
      if self.step in (Step.LIFT, Step.ROLL):   # set down, not dropped from the lift height
        self.step, self._rolled = Step.LOWER, self._measured_roll()
      elif self.step == Step.OUT:   # up from where it stopped, not home from low beside
        self.step = Step.UP         # the chair: unwinding from there knocked it over
      else:
        self.step = Step.DONE if self.step == Step.UP else Step.OPEN
        self._set_out()
      self._count = 0
    return action

  def _measured_roll(self):
    """How far (rad, 0 to pi) the hand has turned about the approach axis, the roll's way."""
    _, rot = self._env.task.robot.tcp_pose(self._env.physics, self._arm)
    turned = geometry.mat_to_axis_angle(rot @ self._rot.T) @ self._approach
    return float(np.clip(self._sign * turned, 0.0, np.pi))

  def _over_height(self, rot=None):
    """Tool height at which the hand, pointing sideways, passes OVER_CLEARANCE over the
    assembly: at the open fingers' safe height its body reached 9 cm lower and struck the
    upturned legs; the chair moved 3-21 cm in 52 of 226 such moves (twenty episodes)."""
    env = self._env
    below = arm_motion.hand_below_tool(env.task.robot, env.physics, self._arm,
                                       self._rot if rot is None else rot)
    return max(self._route.safe_height(OVER_CLEARANCE),
               self._route.assembly_top() + OVER_CLEARANCE + below)

  def _give_up(self):
    self._failed_handles.add((self._part, tuple(np.round(self._approach, 1))))
    self.failed = True

  def _set_out(self):
    tcp, rot = self._env.task.robot.tcp_pose(self._env.physics, self._arm)
    self._out = tcp - STANDOFF * rot[:, 2]

  def _next(self):
    super()._next()
    if self.step == Step.IN:
      self._leg_at = part_geometry.part_pose(self._env.physics, self._env.task.furniture,
                                             self._part)[0][:2].copy()
