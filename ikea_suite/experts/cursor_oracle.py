"""A scripted Cursor policy that assembles any furniture from privileged state.

The base cursor lifts the root part to its assembled pose (raised by `lift`) and
holds it there. The other cursor brings the other parts in the order of an assembly
sequence found by disassembly (ikea_suite.assembly.sequence): grab a part,
raise it, carry it round the outside of the furniture while turning it to its
assembled orientation, then follow the part's free insertion path in and
issue connect. It emits the same 15-number action a learning agent does;
nothing is moved by hand.
"""

import enum

import numpy as np

from ikea_suite import geometry
from ikea_suite.assembly import sequence
from ikea_suite.experts import part_geometry
from ikea_suite.robots import cursor as cursor_lib
from ikea_suite.tasks import planner

_PER_CURSOR = len(cursor_lib.PER_CURSOR_ACTIONS)   # entries per cursor; select is the last
_TRAVEL_TOL = 0.05     # metres: pass a travel point this close
_PATH_TOL = (0.012, 0.04)   # metres, radians: reach insertion-path points this close
_SLENDER = 0.1         # smallest / largest principal inertia below which a part is slender
_INTEGRAL = 0.05       # per step: how fast a held part's standing error is taken out
_MAX_BIAS = (0.08, 0.4)    # metres, radians: the most sag the integral term takes out
_STANDOFF = 0.005      # metres short of the goal along the insertion path
_PIVOT_TILT = 0.03     # radians: how far the goal turns about the preferred connector
_GRAB_RANGE = 0.02     # metres from the grasp point at which a cursor selects
LIFT = sequence.HOLD_LIFT   # the assembly is held this high: parts on the floor pass beneath
_FLOOR_CLEARANCE = 0.25   # metres above the floor parts are carried (lying parts are lower)
_STUCK_STEPS = 80      # steps without progress at one target before backing off
# Hung from a light bracket, a heavy assembly swings or sags in the grip's soft weld; hung
# from a slender post, it turns about the post's axis, which the grip barely turns. Either
# way it never settles in place. When the part the base cursor holds weighs less than
# _LIGHT_HOLD of its assembly or is slender, and the assembly, in place, stays turned more
# than _SAG from its pose for _SAG_STEPS steps while the other cursor is free, the base
# cursor moves its grip to the assembly's heaviest part.
_LIGHT_HOLD = 0.25
_SAG = 0.15          # radians
_SAG_STEPS = 5


class Phase(enum.Enum):
  REACH = "reach"       # fly the empty cursor to the part's grasp point
  RAISE = "raise"       # hold the part and lift it clear of the floor
  TRAVEL = "travel"     # carry it round the furniture, turning it, to its insertion path
  INSERT = "insert"     # follow the insertion path in and connect


class CursorOracle:
  """Call with a TimeStep; returns an action for `env` (an ikea_suite cursor environment)."""

  CONTROL_MODES = None   # the Cursor has no control modes

  def __init__(self, env, lift=LIFT, gain=1.0, tolerance=0.5, clearance=0.12):
    self._env = env
    self._lift, self._gain, self._clearance = lift, gain, clearance
    self._tolerance = tolerance   # fraction of each threshold to reach before connecting
    self.reset()

  def reset(self):
    self._phase = Phase.REACH
    self._base_phase = Phase.REACH
    # The cursor that holds the assembly; the other brings parts. Cursor 1, because the
    # robot updates cursor 0 first: in a hand-back (see `_hand_back`) cursor 0 lets go
    # and cursor 1 grabs within the same step, so the assembly never drops.
    self._base = 1
    self._grip_part = None   # the part the base cursor holds the assembly by; None: the root
    self._regripping = False
    self._sagging = 0        # steps the held assembly has sagged with the other cursor free
    self._plan = None
    self._pivot = None
    self._preferred = None   # name of the connector the part should be welded by
    self._anchor = None      # the joined part it is welded to
    self._part = None
    self._points, self._point = [], 0
    self._best, self._since_best = np.inf, 0
    self._bias = [(np.zeros(3), np.zeros(3)) for _ in range(2)]

  @property
  def subtask(self):
    """(phase name, part) the mover cursor is working on; part is None before the first."""
    return self._phase.value, self._part

  # -- low-level drives --------------------------------------------------------

  def _cursor(self, i):
    pos, rot = self._env.task.robot.cursor_pose(self._env.physics, i)
    return np.array(pos), rot

  def _move_to(self, action, i, target):
    robot = self._env.task.robot
    pos, _ = self._cursor(i)
    step = robot.move_speed * self._env.control_timestep()
    action[i * _PER_CURSOR:i * _PER_CURSOR + 3] = np.clip(self._gain * (target - pos) / step, -1, 1)

  def _drive_part(self, action, i, part, target_pos, target_rot, gain=None):
    """Cursor i moves and turns so that the part it holds reaches the target pose.

    The cursor is steered to the pose that puts its grip's target on the goal
    (feed-forward: the part trails the cursor through a soft weld, so servoing
    on the part itself would swing heavy parts). A slow integral term then
    takes out what gravity and contacts leave (the part sagging in the grip).
    """
    physics, robot, dt = self._env.physics, self._env.task.robot, self._env.control_timestep()
    part_pos, part_rot = part_geometry.part_pose(physics, self._env.task.furniture, part)
    error_pos = target_pos - part_pos
    error_rot = geometry.mat_to_axis_angle(target_rot @ part_rot.T)
    bias_pos, bias_rot = self._bias[i]
    if np.linalg.norm(error_pos) < _MAX_BIAS[0] and np.linalg.norm(error_rot) < _MAX_BIAS[1]:
      error_rot = self._without_spin(part, error_rot)
      bias_pos = np.clip(bias_pos + _INTEGRAL * error_pos, -_MAX_BIAS[0], _MAX_BIAS[0])
      bias_rot = np.clip(bias_rot + _INTEGRAL * error_rot, -_MAX_BIAS[1], _MAX_BIAS[1])
      self._bias[i] = (bias_pos, bias_rot)
    goal_rot = geometry.axis_angle_to_mat(bias_rot) @ target_rot @ robot.grip_offset(i)[1].T
    cursor_pos, cursor_rot = self._cursor(i)
    turn_cmd = np.clip(geometry.mat_to_axis_angle(goal_rot @ cursor_rot.T)
                       / (robot.rotate_speed * dt), -1, 1)
    next_rot = geometry.axis_angle_to_mat(turn_cmd * robot.rotate_speed * dt) @ cursor_rot
    goal_pos = target_pos + bias_pos - next_rot @ robot.grip_offset(i)[0]
    move = (goal_pos - cursor_pos) * (self._gain if gain is None else gain)
    base = i * _PER_CURSOR
    action[base:base + 3] = np.clip(move / (robot.move_speed * dt), -1, 1)
    action[base + 3:base + 6] = turn_cmd
    return np.linalg.norm(error_pos), np.linalg.norm(error_rot)

  def _slender(self, part):
    inertia = self._env.physics.model.body_inertia[self._env.task.furniture.body_ids[part]]
    return inertia.min() <= _SLENDER * inertia.max()

  def _without_spin(self, part, error_rot):
    """The rotation error less its part about a slender part's long axis: the grip barely
    turns a leg about its own axis, so integrating that error would only wind up."""
    physics = self._env.physics
    body = self._env.task.furniture.body_ids[part]
    inertia = physics.model.body_inertia[body]
    if not self._slender(part):
      return error_rot
    axis = physics.data.ximat[body].reshape(3, 3)[:, int(np.argmin(inertia))]
    return error_rot - axis * (axis @ error_rot)

  def _holds(self, i, part):
    held = self._env.task.robot.held_parts[i]
    return held >= 0 and self._env.task.state.same_group(held, part)

  def _fetch(self, action, i, part):
    """Flies cursor i to the part and grabs it; returns True once it holds `part`."""
    if self._holds(i, part):
      action[i * _PER_CURSOR + 6] = 1.0
      return True
    self._bias[i] = (np.zeros(3), np.zeros(3))
    if self._env.task.robot.held_parts[i] >= 0:
      return False   # select stays off this step: let go of the other part first
    point = part_geometry.grasp_point(self._env.physics, self._env.task.furniture, part)
    self._move_to(action, i, point)
    if np.linalg.norm(point - self._cursor(i)[0]) < _GRAB_RANGE:
      action[i * _PER_CURSOR + 6] = 1.0
    return False

  def _raise_height(self, part):
    """Carrying height: however the part turns, it stays above parts lying on the floor."""
    return part_geometry.part_radius(self._env.task.furniture, part) + _FLOOR_CLEARANCE

  # -- the base cursor: the root part -----------------------------------------

  def _base_target(self, part):
    """Where `part` of the held assembly goes: its assembled pose, raised by `lift`."""
    spec = self._env.task.furniture.spec.parts[part]
    return spec.pos + np.array([0.0, 0.0, self._lift]), spec.rot

  def _hold_base(self, action):
    """The base cursor fetches the root part, raises it and brings the assembly to its pose;
    returns True once it is there."""
    b, task = self._base, self._env.task
    root = task.root_part
    held = task.robot.held_parts[b]
    if held < 0 or not task.state.same_group(held, root):
      self._fetch(action, b, self._holding_part())
      self._base_phase = Phase.REACH
      return False
    action[b * _PER_CURSOR + 6] = 1.0
    pos, rot = part_geometry.part_pose(self._env.physics, task.furniture, held)
    target_pos, target_rot = self._base_target(held)
    if self._base_phase == Phase.REACH:
      # Straight back into place after a hand-back; from the floor, up first.
      near = np.linalg.norm(target_pos - pos) < 0.1
      self._base_phase = Phase.TRAVEL if near else Phase.RAISE
    if self._base_phase == Phase.RAISE:
      height = self._raise_height(held)
      self._drive_part(action, b, held, np.array([pos[0], pos[1], height]), rot)
      if pos[2] > height - 0.02:
        self._base_phase = Phase.TRAVEL
      return False
    distance = np.linalg.norm(target_pos - pos)
    angle = np.linalg.norm(geometry.mat_to_axis_angle(target_rot @ rot.T))
    # Parts go where the root actually is, so the base need only be roughly in place;
    # once there the cursor keeps still, as chasing a softly held heavy assembly rocks it.
    if self._base_phase == Phase.INSERT and distance < 0.1 and angle < 0.3:
      return True
    self._base_phase = Phase.TRAVEL
    self._drive_part(action, b, held, target_pos, target_rot)
    if distance < 0.03 and angle < 0.1:
      self._base_phase = Phase.INSERT
    return False

  # -- the mover cursor: the next part ------------------------------------------

  def _sequence(self):
    if self._plan is None:
      task = self._env.task
      self._plan = sequence.plan(task.furniture.spec, task.root_part, self._lift)
    return self._plan

  def _next_step(self):
    """The first planned insertion whose part is not yet joined to the root, or None."""
    state, root = self._env.task.state, self._env.task.root_part
    return next((s for s in self._sequence() if not state.same_group(s.part, root)), None)

  def _path_pose(self, step, k):
    """World pose of insertion-path point k of `step`, following its partner as it is now.

    At the goal the part stops `_STANDOFF` short and is turned a hair about its
    preferred connector's axis, so that connector is the nearest of all that meet
    and the task welds by it.
    """
    physics, task = self._env.physics, self._env.task
    # Placed relative to the partner it is welded to, not the root: a long chain of
    # soft welds sags, and the partner's slot is where the part must meet it.
    anchor = task.root_part if self._anchor is None else self._anchor
    goal_pos, goal_rot = part_geometry.assembled_pose(physics, task.furniture, anchor, step.part)
    rotation, _ = part_geometry.design_to_world(physics, task.furniture, anchor)
    pos = goal_pos + rotation @ np.asarray(step.waypoints[k])
    if k < len(step.waypoints) - 1:
      return pos, goal_rot
    # Stop a few millimetres short: pressing on the mating face would pin the part by
    # friction, and the task snaps the last gap closed anyway.
    back = rotation @ (np.asarray(step.waypoints[k - 1]) - np.asarray(step.waypoints[k]))
    pos = pos + _STANDOFF * back / max(np.linalg.norm(back), 1e-9)
    if self._pivot is not None:
      return part_geometry.tilt_about(pos, goal_rot, *self._pivot, _PIVOT_TILT)
    return pos, goal_rot

  def _plan_route(self, step):
    """Travel points (world position, rotation) and then the insertion path (its indices)."""
    physics, task = self._env.physics, self._env.task
    furniture, root = task.furniture, task.root_part
    joined = [p for p in range(len(furniture.parts)) if task.state.same_group(p, root)]
    preferred = part_geometry.preferred_connector(physics, furniture, step.part, joined)
    self._pivot, self._preferred, self._anchor = preferred if preferred else (None, None, root)
    entry, goal_rot = self._path_pose(step, 0)
    centre, radius = part_geometry.assembly_circle(physics, furniture, root)
    reach = radius + part_geometry.part_radius(furniture, step.part) + self._clearance
    start, start_rot = part_geometry.part_pose(physics, furniture, step.part)
    travel = part_geometry.route(start, entry, centre, reach, start[2])
    # Keep the part's orientation on the way out; turn it once outside the circle.
    points = [(travel[0], start_rot)] + [(p, goal_rot) for p in travel[1:-1]]
    return points + list(range(len(step.waypoints)))

  def _bring_part(self, action, step, base_ready):
    """The mover cursor carries the step's part along its route; True when it should connect."""
    physics, task = self._env.physics, self._env.task
    part = step.part
    if self._part != part:
      self._part, self._phase = part, Phase.REACH
    m = 1 - self._base
    if not self._fetch(action, m, part):
      self._phase = Phase.REACH
      return False
    action[m * _PER_CURSOR + 6] = 1.0
    pos, rot = part_geometry.part_pose(physics, task.furniture, part)
    if self._phase == Phase.REACH:
      self._phase = Phase.RAISE
    if self._phase == Phase.RAISE:
      height = self._raise_height(part)
      self._drive_part(action, m, part, np.array([pos[0], pos[1], height]), rot)
      if pos[2] > height - 0.02 and base_ready:
        self._points, self._point = self._plan_route(step), 0
        self._best, self._since_best = np.inf, 0
        self._phase = Phase.TRAVEL
      return False
    point = self._points[self._point]
    exact = isinstance(point, int)
    target, target_rot = self._path_pose(step, point) if exact else point
    distance, angle = self._drive_part(action, m, part, target, target_rot)
    last = self._point == len(self._points) - 1
    if last:
      return self._insert(action, part, distance)
    if exact:
      self._phase = Phase.INSERT
      if distance < _PATH_TOL[0] and angle < _PATH_TOL[1]:
        self._advance()
      else:
        self._watch(distance)
    elif distance < _TRAVEL_TOL:
      self._advance()
    return False

  def _advance(self):
    self._point += 1
    self._best, self._since_best = np.inf, 0

  def _watch(self, distance):
    """Backs off one point when the part has stopped getting closer (it is caught)."""
    if distance < self._best - 0.002:
      self._best, self._since_best = distance, 0
      return
    self._since_best += 1
    if self._since_best > _STUCK_STEPS and self._point > 0:
      self._point -= 1
      self._best, self._since_best = np.inf, 0

  def _insert(self, action, part, distance):
    """At the goal: connect once the preferred connector's pair is well aligned and is the
    pair the task would pick (the nearest attachable one); later, by any aligned pair."""
    task, physics = self._env.task, self._env.physics
    scores = task.alignment(physics)
    t = task.thresholds
    table = task.furniture.connectors
    involves = (table.part[table.pair_a] == part) | (table.part[table.pair_b] == part)
    ready = (involves & planner.open_pairs(table, task.state)
             & (scores.distance < self._tolerance * t.distance)
             & (scores.up_cos > 1 - self._tolerance * (1 - t.up_cos))
             & (scores.forward_cos > 1 - self._tolerance * (1 - t.forward_cos)))
    # Insist on the preferred pair only for a while: a sagging partner may never let it
    # be the nearest.
    if ready.any() and self._preferred is not None and self._since_best < _STUCK_STEPS // 2:
      attachable = np.flatnonzero(scores.attachable(t) & planner.open_pairs(table, task.state))
      nearest = attachable[np.argmin(scores.distance[attachable])]   # ready ones are in it
      names = (table.names[table.pair_a[nearest]], table.names[table.pair_b[nearest]])
      ready = ready if self._preferred in names else np.zeros_like(ready)
    if ready.any():
      return True
    self._watch(distance)
    return False

  def _holding_part(self):
    """The part the base cursor holds the assembly by: the root until a regrip."""
    return self._env.task.root_part if self._grip_part is None else self._grip_part

  def _sags(self, held):
    """Whether the assembly hangs sagging from the light part `held` (see _LIGHT_HOLD);
    then the part it should be held by instead, else None."""
    task, physics = self._env.task, self._env.physics
    mass = physics.model.body_mass[task.furniture.body_ids]
    group = [p for p in range(len(mass)) if task.state.same_group(p, held)]
    pos, rot = part_geometry.part_pose(physics, task.furniture, held)
    target_pos, target_rot = self._base_target(held)
    turned = np.linalg.norm(geometry.mat_to_axis_angle(target_rot @ rot.T))
    weak = mass[held] < _LIGHT_HOLD * mass[group].sum() or self._slender(held)
    sags = weak and turned > _SAG and np.linalg.norm(target_pos - pos) < 0.1
    self._sagging = self._sagging + 1 if sags else 0
    if self._sagging < _SAG_STEPS:
      return None
    return max(group, key=lambda p: mass[p])

  def _regrip(self, action):
    """Moves the base cursor's grip onto a heavier part when the assembly sags from the one
    it holds: the free cursor takes the assembly by that part (the base lets go a step
    before, as a cursor cannot take an assembly the other holds), and the hand-back
    returns it to the base cursor by the same part. True while this is under way."""
    task = self._env.task
    held, b, m = task.robot.held_parts, self._base, 1 - self._base
    if self._regripping and (held[m] >= 0 or held[b] == self._grip_part):
      self._regripping = False   # the free cursor has it (the hand-back follows), or done
    if not self._regripping:
      if held[b] < 0 or held[m] >= 0 or not task.state.same_group(held[b], task.root_part):
        self._sagging = 0
        return False
      heavier = self._sags(held[b])
      if heavier is None or heavier == held[b]:
        return False
      self._grip_part, self._regripping, self._sagging = heavier, True, 0
    point = part_geometry.grasp_point(self._env.physics, task.furniture, self._grip_part)
    self._move_to(action, m, point)
    if held[b] >= 0:   # let go once the free cursor is at the grip; it takes hold next step
      there = np.linalg.norm(point - self._cursor(m)[0]) < _GRAB_RANGE
      action[b * _PER_CURSOR + 6] = -1.0 if there else 1.0
    action[m * _PER_CURSOR + 6] = 1.0 if held[b] < 0 else -1.0
    self._base_phase = Phase.REACH
    return True

  def _hand_back(self, action):
    """After the first connection the task may move the root (the groups are equal) and
    make the base cursor let go; the assembly then hangs from the small part the other
    cursor holds. That cursor keeps still while the base cursor flies back to the root's
    grasp point, then lets go while the base cursor grabs the root again."""
    b, m = self._base, 1 - self._base
    point = part_geometry.grasp_point(self._env.physics, self._env.task.furniture,
                                      self._holding_part())
    self._move_to(action, b, point)
    there = np.linalg.norm(point - self._cursor(b)[0]) < _GRAB_RANGE
    action[m * _PER_CURSOR + 6] = -1.0 if there else 1.0
    action[b * _PER_CURSOR + 6] = 1.0 if there else -1.0   # grabs as soon as the other lets go
    self._base_phase = Phase.REACH

  def __call__(self, timestep=None):
    action = np.zeros(self._env.action_spec().shape)
    task = self._env.task
    held = task.robot.held_parts
    b = self._base
    if self._regrip(action):
      return action
    if (held[b] < 0 and held[1 - b] >= 0
        and task.state.same_group(held[1 - b], task.root_part)):
      self._hand_back(action)
      return action
    base_ready = self._hold_base(action)
    step = self._next_step()
    if step is None:
      return action
    if self._bring_part(action, step, base_ready):
      action[-1] = 1.0
    return action
