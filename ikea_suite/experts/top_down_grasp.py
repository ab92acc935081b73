"""The top-down grasp of a scripted arm: where the tool goes to take a part lying on the
floor or a table (from above, fingers across the part's long axis, as low as the
fingertips allow, at a point where both open fingers land clear of other parts;
privileged state, nothing moves), and how fast and how close the hand comes down onto
it, closes on it and lowers what it holds (the speeds and gates below, each measured
where it was set)."""

import numpy as np

from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import below_work_scale
from ikea_suite.experts import finger_room
from ikea_suite.experts import part_geometry
from ikea_suite.tasks import hollow_parts
from ikea_suite.tasks import panel_placement

# A panel standing TALL or taller (in the rack, props/panel_rack.py) is taken by its
# top edge: the fingertips go EDGE_GRIP below it, across its thickness, and the hand stays
# above it. Legs, rails and blocks (every part of the catalog's stools and four-leg
# tables) are taken as low as the fingertips allow.
TALL = panel_placement.MIN_HEIGHT
EDGE_GRIP = 0.02
# A panel that lies flat once assembled (a carcass's far side, stood on its long edge in
# the rack: tasks/panel_placement.py) is turned flat on its way in and then juts sideways
# from the fingers, its weight twisting it about the gripped edge. The fingertips take it
# FLAT_EDGE_GRIP deep, past the whole pad (the Sawyer's pads are 33 mm long, its squeeze
# 22 N), and the carry goes at FLAT_CARRY_SPEED of the arm's top speed: held 20 mm deep, a
# 200 mm cabinet side (0.41 kg at scale 0.5) slipped out while turning, twice in one
# episode; held 35 mm deep at full speed, a bookcase side swung out of the Sawyer's grip
# on the way in 3 times in 5 (bookcase_shelf_unit_billy).
FLAT_EDGE_GRIP = 0.045
# ... but no deeper than FLAT_FINGER_ROOT (m) short of the fingers' length: the Panda's
# fingers (54 mm) taken 45 mm deep stopped 3 mm above the grasp point in each of its
# descents onto the panel (seed 1), and the reach stalled; 35 mm deep it was completed.
FLAT_FINGER_ROOT = 0.02
# Such a panel lands flat on the edges of standing parts (a bookcase's far side on its
# shelves), and a finger jutting below it would land on one: it is taken at the point of
# its long edge nearest the middle that lies FLAT_EDGE_CLEAR (m) along the edge from each
# of its connectors. Taken at the middle, over the middle shelf, the Panda's finger (26 mm
# wide) stood on that shelf 2.5 cm short of the mate in every insertion.
FLAT_EDGE_CLEAR = 0.03
FLAT_CARRY_SPEED = 0.5
# A hollow part (a drawer box, tasks/hollow_parts.py) is taken by the top edge of its
# highest wall, EDGE_GRIP deep at most and with the fingertips WALL_CLEAR (m) above the
# other walls' tops.
WALL_CLEAR = 0.003

# The open fingers go down to a part slowly: at full speed the hand swings sideways by
# up to 2.6 cm (Sawyer, 7 cm descent in 3 steps) and a finger lands on the part.
DESCEND_GAIN = 0.3
# A hand whose fingers curl below the tool centre closes only once it moves less than this
# per control step (m): 1 mm still let the Jaco's hand swing 1 cm while closing.
SETTLED_SPEED = 0.0005
# Such a hand (one finger against two) holds a lifted part with its fingers aimed this far
# (rad) short of their closed limit instead of past it; see arm_motion.hold_command.
HOLD_SHORT_OF_CLOSED = 0.05
# A panel held by its top edge (TopDownGrasp.by_top_edge) hangs from the fingers: it goes
# down onto its mate at this fraction of the arm's top speed (at 25 mm a step it swung
# as the arm stopped), and the fingers close on it only within EDGE_GATE (m): 6 mm off,
# as for a leg, one finger pushed a 6 mm box wall over in its slot, the hand held it
# askew on its top edge, and it pivoted out of the grip during the carry.
HANGING_SPEED, EDGE_GATE = 0.3, 0.0015
# The open fingers pass 2 cm either side of a racked panel (Sawyer): the descent onto its
# top edge starts only within EDGE_REACH (m) of the point above it, and goes down at
# HANGING_SPEED. Started 2 cm off (the REACH gate) with the tool lagging its target, and
# at full speed, a fingertip landed on the edge and pushed the panel out of the rack
# (Sawyer, desk_trestle_w100_birch, in 4 of 20 episodes).
EDGE_REACH = 0.006


class TopDownGrasp:
  """Tool poses for one arm's top-down grasps.

  Args:
    env: the environment.
    arm: the arm's index.
    surface: height (m) of the surface the parts lie on.
    route: the arm's clearance.AssemblyClearance, which keeps the fingertips' reach
      below the tool centre (`pad_below`, measured here at the first grasp).
  """

  def __init__(self, env, arm, surface, route):
    self._env, self._robot, self._arm = env, env.task.robot, arm
    self._surface, self._route = surface, route
    self._finger_points = None   # the open fingers in the tool frame (finger_room)
    self._room_shifts = {}   # (part, grasp sign): finger_room's shift, for the present reach
    self._frames = {}   # part: whether it is a frame of bars (panel_placement.is_frame)

  def new_reach(self):
    """Forgets the grasp points chosen for the last reach."""
    self._room_shifts = {}

  def closing_local(self):
    """The fingers' closing direction in the tool frame (unit, horizontal when pointing down)."""
    return arm_motion.closing_axis(self._robot, self._env.physics, self._arm)

  def pose(self, part, sign):
    """Tool pose at the part's grasp point: pointing down, fingers across its long axis,
    closing along +-1 (`sign`: which of the two symmetric grasps)."""
    physics, furniture = self._env.physics, self._env.task.furniture
    point = part_geometry.grasp_point(physics, furniture, part)
    part_pos, part_rot = part_geometry.part_pose(physics, furniture, part)
    bounds = furniture.spec.parts[part].bounds
    corners = geometry.box_corners(*bounds) @ part_rot.T + part_pos
    # As low as the fingertips allow (3 mm above the part's underside), so the pads
    # cover as much of a thin part's height as they can. A part thinner than that
    # clearance is still gripped at its widest (the pads reach down past the tool
    # centre); aiming lower pressed the fingertips into the floor, and a 13 mm leg's
    # 6.5 mm centre stayed 7.5 mm short of the descent's 6 mm gate.
    # The box's lowest corner, not below the surface it lies on: a part lying rolled about
    # its long axis has box corners below the floor, and fingertips aimed 3 mm above such a
    # corner pressed on the floor and could not close (Baxter, table_four_leg_side_oak).
    route = self._route
    if route.pad_below is None:   # measured at the first grasp, with the arm at home
      route.pad_below = arm_motion.fingertip_reach(self._robot, physics, self._arm)
    point, tip_clearance = point.copy(), 0.003
    if below_work_scale.active(self._env):   # held away from its connectors: the hand stays high
      shift = below_work_scale.grip_shift(furniture, part)
      if shift.any():
        point = part_pos + part_rot @ shift
      tip_clearance = below_work_scale.TIP_CLEARANCE
    point[2] = max(corners[:, 2].min(), self._surface) + route.pad_below + tip_clearance
    wall = hollow_parts.top_wall(furniture.spec.parts[part], part_rot)
    if wall is not None:   # a hollow part: by the middle of its highest wall's top edge
      point, closing = self._wall_grip(part_pos, part_rot, wall)
    elif self.by_top_edge(part):   # at the middle of its top edge, which a lean moves aside
      up = int(np.argmax(np.abs(part_rot[2])))
      face = np.mean(bounds, axis=0)
      face[up] = bounds[int(part_rot[2, up] > 0)][up]
      flat = self.turns_flat(part)
      if flat:
        face = self._clear_of_connectors(
            part, face, ({0, 1, 2} - {up, int(np.argmin(bounds[1] - bounds[0]))}).pop())
      point = part_pos + part_rot @ face
      point[2] += route.pad_below - (self._flat_grip_depth() if flat else EDGE_GRIP)
    elif self._is_frame(part):   # along its longest bar, clear of the mates under it
      long_axis = int(np.argmax(bounds[1] - bounds[0]))
      base = part_rot.T @ (self._robot.base_pose[0] - part_pos)
      face = self._clear_of_connectors(part, part_rot.T @ (self._nearest_bar(part) - part_pos),
                                       long_axis, toward=base[long_axis])
      point = np.array([*(part_pos + part_rot @ face)[:2], point[2]])
    if wall is None:
      closing = part_geometry.across_long_axis(part_rot, bounds)
    closing = closing * sign
    rot = arm_motion.tool_rotation(np.array([0.0, 0.0, -1.0]), closing, self.closing_local())
    if not below_work_scale.active(self._env):   # (small parts are held near one end already)
      point = point + part_rot @ self._room_shift(part, sign, point, rot)
    return point, rot

  def _wall_grip(self, part_pos, part_rot, wall):
    """(the grasp point, the horizontal closing direction) that take a hollow part by the
    middle of the top edge of its highest wall (`wall`: hollow_parts.top_wall), across
    the wall's thickness, EDGE_GRIP deep or less: the fingers stay WALL_CLEAR above the
    other walls' tops, between which and the wall the inner finger has no room (a
    drawer's front stands 13 mm above its box at scale 0.5, 6 mm before its sides)."""
    (centre, box_rot, size), above_others = wall
    axes = part_rot @ box_rot
    up = int(np.argmax(np.abs(axes[2])))
    top = part_pos + part_rot @ centre + axes[:, up] * size[up] * np.sign(axes[2, up])
    depth = min(EDGE_GRIP, above_others - WALL_CLEAR)
    point = top + [0.0, 0.0, self._route.pad_below - depth]
    thin = min((k for k in range(3) if k != up), key=lambda k: size[k])
    closing = axes[:, thin].copy()
    closing[2] = 0.0
    return point, closing / np.linalg.norm(closing)

  def by_wall(self, part):
    """Whether `part` is hollow (tasks/hollow_parts.py), taken by a wall's top edge."""
    return hollow_parts.is_hollow(self._env.task.furniture.spec.parts[part])

  def by_top_edge(self, part):
    """Whether `part`, as it stands now, is taken by its top edge: a panel
    (tasks/panel_placement.is_panel) standing TALL or taller, as in the rack, or a hollow
    part by its highest wall's (tasks/hollow_parts.py). It will hang from the fingers
    like a pendulum. Legs, rails and blocks are taken as low as the fingertips allow
    however they lie."""
    physics, furniture = self._env.physics, self._env.task.furniture
    if self.by_wall(part):
      return True
    _, part_rot = part_geometry.part_pose(physics, furniture, part)
    bounds = furniture.spec.parts[part].bounds
    height = np.ptp((geometry.box_corners(*bounds) @ part_rot.T)[:, 2])
    return bool(height >= TALL and panel_placement.is_panel(bounds[1] - bounds[0]))

  def turns_flat(self, part):
    """Whether `part`, a panel, lies flat (its thin axis vertical) in its assembled place on
    the root as the root lies now, so that the arm turns it flat from standing."""
    physics, furniture = self._env.physics, self._env.task.furniture
    if self.by_wall(part):   # lies as it goes in
      return False
    bounds = furniture.spec.parts[part].bounds
    _, rot = part_geometry.assembled_pose(physics, furniture, self._env.task.root_part, part)
    return bool(abs(rot[2, int(np.argmin(bounds[1] - bounds[0]))]) > 0.5)

  def _flat_grip_depth(self):
    """How deep (m) the fingertips take a panel turned flat: FLAT_EDGE_GRIP, or
    FLAT_FINGER_ROOT short of the open fingers' length along the tool axis."""
    if self._finger_points is None:
      self._finger_points = finger_room.finger_points(self._robot, self._env.physics, self._arm)
    return min(FLAT_EDGE_GRIP, np.ptp(self._finger_points[:, 2]) - FLAT_FINGER_ROOT)

  def _is_frame(self, part):
    """panel_placement.is_frame of `part`, read once per part."""
    if part not in self._frames:
      self._frames[part] = panel_placement.is_frame(self._env.task.furniture.spec.parts[part])
    return self._frames[part]

  def _nearest_bar(self, part):
    """World centre of the frame's largest collision geom nearest the robot's base, of those
    that tie (a shelving ladder's two posts): the first of them, taken whichever lay
    nearer, put the far post of a ladder lying at the band's edge 0.84 m from the Panda's
    base, beyond its 0.8 m reach, and every reach stalled."""
    physics, furniture = self._env.physics, self._env.task.furniture
    model, data = physics.model, physics.data
    ids, owner = furniture.collision_geoms
    geoms = ids[owner == part]
    sizes = np.array([np.prod(model.geom_aabb[g, 3:]) for g in geoms])
    base, _ = self._robot.base_pose
    centres = [data.geom_xpos[g] + data.geom_xmat[g].reshape(3, 3) @ model.geom_aabb[g, :3]
               for g in geoms[sizes > 0.99 * sizes.max()]]
    return min(centres, key=lambda centre: np.linalg.norm(centre[:2] - base[:2]))

  def _clear_of_connectors(self, part, face, axis, toward=None):
    """`face` (part frame: the middle of a racked panel's top edge, or the middle of a
    frame's longest bar) moved along the part axis `axis` to the nearest point
    FLAT_EDGE_CLEAR from each of its connectors (unmoved with none such); of two about as
    near, the one nearer `toward` (a coordinate along `axis`), if given. A racked panel's
    top edge runs along the part axis that is neither its thickness nor the one standing
    up: a round seat's two longest axes tie, and moved along the vertical one the grasp
    went 3 cm down into the seat, the fingers landing on it. Taken at its middle, a
    shelving ladder's post is gripped where the middle shelf's end meets it."""
    furniture = self._env.task.furniture
    bounds = furniture.spec.parts[part].bounds
    table = furniture.connectors
    along = table.local_pos[table.part == part][:, axis]
    candidates = np.arange(bounds[0][axis] + FLAT_EDGE_CLEAR,
                           bounds[1][axis] - FLAT_EDGE_CLEAR, 0.001)
    clear = candidates[(np.abs(candidates[:, None] - along[None, :]) >= FLAT_EDGE_CLEAR).all(1)]
    if clear.size:
      face = face.copy()
      off = np.abs(clear - face[axis])
      if toward is not None:   # of the nearest two, either side of the middle, that one
        clear = clear[off < off.min() + 0.0015]
        off = np.abs(clear - toward)
      face[axis] = clear[np.argmin(off)]
    return face

  def _room_shift(self, part, sign, point, rot):
    """finger_room's shift of the grasp point (part frame), chosen once per reach for each
    part and grasp: re-chosen every step, it jumped as the hand nudged the part beside."""
    key = (part, sign)
    if key not in self._room_shifts:
      physics, furniture = self._env.physics, self._env.task.furniture
      if self._finger_points is None:
        self._finger_points = finger_room.finger_points(self._robot, physics, self._arm)
      shift = finger_room.clear_shift(physics, furniture, part, point, rot,
                                      self._finger_points, below_work_scale.PAD_ROOM)
      self._room_shifts[key] = part_geometry.part_pose(physics, furniture, part)[1].T @ shift
    return self._room_shifts[key]
