"""Routes for a scripted arm's hand that keep it clear of the growing assembly.

At the arms' work scale (0.5) the assembly weighs a few hundred grams: a hand
or held part that strikes a leg already standing on the root drags the whole
assembly out of reach, or tips it over. The routes here pass over it, rise
straight up from beside it, and swing around the base rather than across it.
"""

import numpy as np

from ikea_suite.experts import arm_motion
from ikea_suite.experts import part_geometry


class AssemblyClearance:
  """Waypoints for one arm of `env`'s robot; `surface` is the height the parts lie on."""

  def __init__(self, env, arm, surface):
    self._env, self._robot, self._arm, self._surface = env, env.task.robot, arm, surface
    self.pad_below = None   # how far the open fingertips reach below the tool centre (m)
    self.reset()

  def reset(self):
    self._rise_from = None   # (x, y) a rise clear of the assembly started from
    self._carry_rise_from = None   # (x, y) a held part's rise (rise_first) started from
    self._fence = None   # (part, along, floor, across, low, high): rack_exit, outside_rack

  def assembly_top(self):
    """Height of the highest corner of the parts joined to the root (or of the surface)."""
    task, physics = self._env.task, self._env.physics
    return max(self._surface, part_geometry.parts_corners(
        physics, task.furniture, part_geometry.root_group(task))[:, 2].max())

  def safe_height(self, clearance=0.08):
    """Tool height at which the open fingers pass `clearance` over the assembly."""
    return self.assembly_top() + clearance + (self.pad_below or 0.0)

  def over_assembly(self, goal, near=0.06, clearance=0.08):
    """`goal`, raised to pass over the assembly until the tool is above the goal; from
    below that height beside the assembly, straight up first.

    Travelling low, the hand sweeps into legs already standing on the root; rising while
    moving sideways, the hand and forearm still struck them (Sawyer).
    """
    pos, _ = self._robot.tcp_pose(self._env.physics, self._arm)
    if np.linalg.norm(goal[:2] - pos[:2]) < near:
      self._rise_from = None
      return goal
    task, physics = self._env.task, self._env.physics
    safe = self.safe_height(clearance)
    centre, radius = part_geometry.assembly_circle(physics, task.furniture, task.root_part)
    if pos[2] < safe - 0.02 and np.linalg.norm(pos[:2] - centre) < radius + 0.15:
      # Up from where the rise began: re-aimed from the present position each step,
      # the hand drifted sideways into the leg beside it as it rose (Panda).
      if self._rise_from is None:
        self._rise_from = pos[:2].copy()
      return np.array([*self._rise_from, safe])
    self._rise_from = None
    return np.array([goal[0], goal[1], max(goal[2], safe)])

  def rise_first(self, waypoint, part, top, clearance=0.03, margin=0.03):
    """The carry's `waypoint`, or straight up from where the rise began while the held
    `part`, moved as the waypoint would move it sideways, would come over a part of the
    assembly (footprints `margin` apart) whose top it does not yet clear by `clearance`.
    Only where the carry's height `top` (tool z) clears that part: otherwise the carry
    could never get past it. Rising while swinging sideways from the floor, a stretcher's
    end struck a standing trestle and toppled it (Panda, table_trestle_l120_white)."""
    task, physics = self._env.task, self._env.physics
    furniture = task.furniture
    pos, _ = self._robot.tcp_pose(physics, self._arm)
    positions, rotations = furniture.part_poses(physics)
    held = part_geometry.part_corners(furniture, part, positions[part], rotations[part])
    shifted = held[:, :2] + (waypoint[:2] - pos[:2])
    low, high = shifted.min(0) - margin, shifted.max(0) + margin
    bottom, blocking = held[:, 2].min(), -np.inf
    for other in part_geometry.root_group(task):
      corners = part_geometry.part_corners(furniture, other, positions[other], rotations[other])
      if (corners[:, 2].max() + clearance > bottom
          and (corners[:, :2].max(0) > low).all() and (corners[:, :2].min(0) < high).all()):
        blocking = max(blocking, corners[:, 2].max())
    rise = blocking + clearance - bottom
    if not 0.0 < rise <= top - pos[2]:
      self._carry_rise_from = None
      return waypoint
    if self._carry_rise_from is None:
      self._carry_rise_from = pos[:2].copy()
    return np.array([*self._carry_rise_from, waypoint[2]])

  def rack_exit(self, part, pair, grasp, closing, carry_z, clearance=0.03, margin=0.03):
    """How far (a horizontal move, m) the tool slides `part`, a panel standing in a rack
    and taken by its top edge with the tool at `grasp` (fingers closing along the
    horizontal `closing`), once it is lifted, before it is carried to its mate on
    connector pair `pair`: along the panel's own plane, towards the base, until its
    footprint lies `margin` beyond those of the other loose panels in its rack that stand
    on the mate's side of it (along `closing`, the row of slots) and whose tops it would
    not clear by `clearance` with the tool at the carry's height `carry_z`. None when
    there is no such panel, or `part` stands in no rack. The carry then keeps out of
    their row (outside_rack) until the next rack_exit.

    The lift raises a panel only `lift` clear of the rack, and the carry swings the hand
    round the base, across the panel's thickness: along the row of slots. A panel so tall
    that it hangs below its neighbours' tops even at the carry's height was swept into
    those between it and its mate (a dresser's 0.38 m shelves and plinth, a cabinet's
    shelf into its 0.41 m back, Panda, scale 0.5), pivoted about the closing axis and fell
    out of the fingers. Slid out along its plane it passes no neighbour.
    """
    self._fence = None
    task, physics = self._env.task, self._env.physics
    furniture, table = task.furniture, task.furniture.connectors
    rack = next((group for group in task.initializer.rack_groups if part in group), None)
    if rack is None:
      return None
    positions, rotations = furniture.part_poses(physics)
    a, b = table.pair_a[pair], table.pair_b[pair]
    mate = table.world_frames(positions, rotations)[0][b if table.part[a] == part else a]
    across = np.array([closing[0], closing[1], 0.0]) / np.linalg.norm(closing[:2])
    held = part_geometry.part_corners(furniture, part, positions[part], rotations[part])
    middle = held.mean(axis=0)
    side = np.sign((mate - middle) @ across)
    bottom = held[:, 2].min() + carry_z - grasp[2]
    joined = set(part_geometry.root_group(task))
    blocking = []
    for other in rack:
      if other == part or other in joined:
        continue
      corners = part_geometry.part_corners(furniture, other, positions[other], rotations[other])
      if (corners[:, 2].max() + clearance > bottom
          and (corners.mean(axis=0) - middle) @ across * side > 0.0):
        blocking.append(corners)
    if not blocking:
      return None
    along = np.array([-across[1], across[0], 0.0])
    toward_base = self._robot.base_pose[0] - grasp
    if along[:2] @ toward_base[:2] < 0.0:
      along = -along
    blocking = np.concatenate(blocking)
    slide = (blocking @ along).max() - (held @ along).min() + margin
    if slide <= 0.0:
      return None
    # The tool, where the held footprint reaches the row: the row's span across, widened
    # by the held panel's reach either side of the tool.
    held_across = held @ across - grasp @ across
    self._fence = (part, along, grasp @ along + slide, across,
                   (blocking @ across).min() - held_across.max() - margin,
                   (blocking @ across).max() - held_across.min() + margin)
    return slide * along

  def outside_rack(self, waypoint, part):
    """The carry's `waypoint` for `part`, moved along the slide of the part's last
    rack_exit to where that slide ended, wherever it would bring the panel back over the
    row it slid out of. Carried round the base from there, the hand's arc bowed back over
    the rack's edge and swept a nightstand's plinth and a cabinet's shelf into the back
    standing in it (Panda)."""
    if self._fence is None or self._fence[0] != part:
      return waypoint
    _, along, floor, across, low, high = self._fence
    if not low < waypoint @ across < high or waypoint @ along >= floor:
      return waypoint
    return waypoint + (floor - waypoint @ along) * along

  def above_assembly(self, pos, margin=0.15, clearance=0.08):
    """`pos` raised to safe_height where it lies within `margin` of the assembly's
    footprint circle; elsewhere unchanged."""
    task, physics = self._env.task, self._env.physics
    centre, radius = part_geometry.assembly_circle(physics, task.furniture, task.root_part)
    if np.linalg.norm(pos[:2] - centre) >= radius + margin:
      return pos
    return np.array([pos[0], pos[1], max(pos[2], self.safe_height(clearance))])

  def carry_floor(self, goal, part, part_pos, part_rot, clearance=0.03):
    """Lowest tool height (m) over the tool goal `goal` at which `part`, held as it will sit
    at (part_pos, part_rot), passes `clearance` over the assembly."""
    corners = part_geometry.part_corners(self._env.task.furniture, part, part_pos, part_rot)
    return self.assembly_top() + clearance + goal[2] - corners[:, 2].min()

  def reachable_carry(self, goal, rot, top, floor, step=0.02):
    """The carry height (tool z) over the tool goal `goal`: `top`, or lower until the arm
    reaches it with its tool at `rot` (IK miss under 1 cm), but not below `floor`
    (carry_floor). Half a metre over the table, a box's far wall lay 0.77 m out, beyond
    the Jaco's reach, and the carry stalled there until the episode ended."""
    robot, physics = self._robot, self._env.physics
    z = top
    while z > floor and robot.reach_check(physics, self._arm, np.array(
        [goal[0], goal[1], z]), rot)[0] > 0.01:
      z -= step
    return max(z, floor)

  def arc_waypoint(self, goal):
    """A point on an arc around the base towards `goal`: carrying never sweeps across the base."""
    base, base_rot = self._robot.base_pose
    pos, _ = self._robot.tcp_pose(self._env.physics, self._arm)
    return arm_motion.arc_waypoint(base, pos, goal, heading=np.arctan2(base_rot[1, 0], base_rot[0, 0]))


class CarryHeight:
  """The tool height a held part is carried at over its goal, chosen afresh for each plan.

  It is `nominal`, or for a panel hanging from its top edge at least high enough to pass
  3 cm over the assembly (`route.carry_floor`: a trestle held by its foot struck the one
  standing before it). After a stall (`lower`) it comes down within the arm's reach.
  """

  def __init__(self, route, nominal):
    self._route, self.nominal = route, nominal
    self.top = None   # chosen at the first step of a plan's carry
    self._floor = None

  def reset(self):
    """For the next plan."""
    self.top = None

  def waypoint(self, goal, part, part_pos, part_rot, hanging):
    """The point over the tool goal `goal` (position, rotation) the carry makes for, with
    `part` held as it will sit at (part_pos, part_rot)."""
    self._floor = self._route.carry_floor(goal[0], part, part_pos, part_rot)
    if self.top is None:
      self.top = max(self.nominal, self._floor if hanging else 0.0)
    return goal[0] + [0.0, 0.0, max(0.0, self.top - goal[0][2])]

  def lower(self, goal, pinned):
    """After a stall: a raised carry goes back to `nominal` (out of the Panda's reach over
    a trestle table, the raised carry stalled until time ran out); otherwise, unless a
    joint is `pinned` (the caller replans then), down to what the arm reaches, not
    below the floor (`route.reachable_carry`). True when the height came down."""
    top = self.nominal if self.top > self.nominal else self.top if pinned else (
        self._route.reachable_carry(goal[0], goal[1], self.top, self._floor))
    if top < self.top - 0.01:
      self.top = top
      return True
    return False
