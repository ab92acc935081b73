"""Part placement for fixed-base arms: the parts lie flat on the floor or table within reach.

The root part (the one everything is built onto) lies in front of the
robot, turned over when its mates attach from below (a table top is
assembled upside down, as people do), so its open connectors face up; a
carcass that would stand tall panels in the rack is built on its front or
back instead, its side standing on its long edge (root_rest). A hollow part
(a drawer box, tasks/hollow_parts.py) and a flat frame (a shelving ladder,
panel_placement.flat_frames) lie as they stand in the furniture built on the root
as the root lies, so that an arm takes the one by a wall's top edge and the other
by a bar, and carries each to its mate unturned. The
other parts are scattered without overlap in a sector around the base from
`min_distance` out to `reach`. Furniture too large for that band spills
outwards instead of failing, so every furniture loads with every robot.

The scene's placement options apply here too (README, "Part placement for
arms"): `yaw_range` bounds each part's random yaw, `preassembled` places
groups already joined (each keeps its assembled shape, upright), and
`spread` is the width of the band the parts are drawn from, which must fit
within the arm's reach (OptionValueError otherwise). The robot states its
reach (`reach_zone`); this module is the task's, so robots import no task code.

The arena states the surface the parts lie on (`arena.support`: the floor,
or a work table's top with its extent). On a table every part lies wholly on
the top; furniture too large for it raises EpisodeInitializationError.
"""

import numpy as np
from dm_control import composer

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.arenas import support as support_lib
from ikea_suite.tasks import hollow_parts
from ikea_suite.tasks import panel_placement
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner
from ikea_suite.tasks import resting

# A root whose farthest connector would lie beyond ROOT_FAR of the arm's reach, lying
# along the radius from the base, lies across it if that brings the farthest connector
# at least ROOT_GAIN (m) nearer: a trestle desk's far trestle slot, 0.76 m out, was at
# the edge of the Panda's reach (0.58 m across). A long table top's corner legs are
# about as far either way (0.09 m nearer for a 120 cm top, which the Sawyer completed
# on 17 of 20 fresh seeds lying along the radius and on 14 of 20 across it).
ROOT_FAR, ROOT_GAIN = 0.9, 0.1


# A carcass whose root lies on its face stands its shelves and back in the rack as tall as
# the carcass is wide: taller than TALL_PANEL (m), a panel held 20 mm by its top edge swings
# out of the grip as the carry speeds up, and its top lies beyond the Panda's reach (the
# open TV units' 0.58-0.78 m shelves at half scale). Such a root lies on its long edge
# instead (the carcass on its back or front) where that stands every racked panel lower
# and the root comes to rest standing so.
TALL_PANEL = 0.4


def _tallest_racked(spec, root, rest):
  """Height (m) of the tallest panel racked for the root lying at `rest` (0: none)."""
  return max((float(np.ptp((geometry.box_corners(*spec.parts[i].bounds) @ rot.T)[:, 2]))
              for i, rot in panel_placement.upright_panels(spec, root, rest)), default=0.0)


def _face_up(spec, table, root, rest):
  """`rest`, turned over when the root's mates would attach from below lying so."""
  return geometry.HALF_TURN_X @ rest if mates_from_below(spec, table, root, rest) else rest


def root_rest(spec, table, root):
  """How the root part lies while the furniture is built onto it, before its yaw.

  On its largest face (placement.resting_rotation), turned over when its mates attach from
  below. A carcass lying so that would rack a panel taller than TALL_PANEL lies instead on
  the root's long edge, the side its mates attach from up, when that racks every panel
  lower and the root stands at rest on that edge (a bookcase's or TV unit's side stands on
  its back or front edge, the shelves standing as tall as the carcass is deep). A root on
  its edge is turned a quarter turn about the vertical, so that the carcass, which grows
  along the root's thin axis, grows across the arm's heading rather than towards or away
  from its base.

  Args:
    spec: the FurnitureSpec.
    table: the furniture's connector table.
    root: the root part's index (planner.root_part).
  Returns:
    (rotation (3, 3), part to world; whether the root stands on its edge).
  """
  bounds = spec.parts[root].bounds
  rest = _face_up(spec, table, root, placement.resting_rotation(bounds))
  tallest = _tallest_racked(spec, root, rest)
  if tallest <= TALL_PANEL:
    return rest, False
  middle = int(np.argsort(bounds[1] - bounds[0])[1])
  edge = geometry.rot_z(np.pi / 2) @ _face_up(spec, table, root, placement.LIE_ON[middle])
  if (_tallest_racked(spec, root, edge) < tallest
      and resting.rests_on_support(spec, {root: edge})[root].position is None):
    return edge, True
  return rest, False


def assembled_footprint(spec, root, rest):
  """Where the assembled furniture lies around its root lying at `rest` (3, 3): (its
  footprint's centre (2,) less the root's, horizontal, m; its footprint's radius, m)."""
  design_to_world = rest @ spec.parts[root].rot.T

  def flat(corners):
    return corners @ design_to_world.T

  every = flat(np.concatenate([p.assembled_corners() for p in spec.parts]))[:, :2]
  centre = (every.max(0) + every.min(0)) / 2
  own = flat(spec.parts[root].assembled_corners())[:, :2]
  return centre - (own.max(0) + own.min(0)) / 2, float(np.linalg.norm(every - centre,
                                                                      axis=1).max())


def mates_from_below(spec, table, root, rest):
  """Whether, in the assembled furniture, the root's mates lie mostly below its connectors,
  the root lying at `rest` (part to world rotation). Heights count along the part axis
  `rest` stands up: along its own z, a bookcase side's shelves (all on one face) averaged
  to nothing, and the side was laid with that face down at random."""
  by_name = spec.parts
  up = rest.T @ np.array([0.0, 0.0, 1.0])
  heights = []
  for a, b in zip(table.pair_a, table.pair_b):
    for mine, other in ((a, b), (b, a)):
      if table.part[mine] == root and table.part[other] != root:
        local = by_name[root].rot.T @ (by_name[table.part[other]].pos - by_name[root].pos)
        heights.append(up @ (local - table.local_pos[mine]))
  return bool(heights) and float(np.mean(heights)) < 0


class ReachableParts(placement.PartInitializer):
  """Root part in front of the base, the rest in a band around it; random yaw and position.

  Args:
    furniture: the Furniture prop.
    base_xy, base_rot: the arm base's world position (2,) and rotation (3, 3).
    reach: metres from the base that parts may lie at.
    min_distance: nearest (m) to the base a part's centre may lie (the arm's inner distance).
    root_distance: nearest (m) to the base the root part's centre lies.
    sector: half-angle (rad) either side of the base's heading that parts lie within.
    spread: width of the band (m) parts are drawn from; None: from min_distance to reach.
    yaw_range: largest |yaw| (rad) of a part about its resting pose.
    preassembled: the (low, high) range of connections made before the episode.
    support: the arenas.support.Support the parts lie on (default: the floor).
    arms: the robot's arms; with two, the loose parts alternate between the halves of the
      sector either side of the heading (the first half drawn at random), so each arm
      has parts on its own side to bring, and the racked panels stand in two racks, one
      in each half (tasks/panel_placement.split_by_side).
    side_reach: (bearing, metres): beyond that bearing from the heading, loose parts lie
      out to that distance instead of `reach`; None: `reach` at every bearing.
    home_footprint: the robot at its home pose seen from above (base.ReachZone's: per
      collision geom, (x low, y low, x high, y high) in the base frame and its lowest
      world z); every part's footprint, and the rack's, keeps `gap` clear of each box
      whose lowest point is less than `gap` above the part's top. None: none.
  Raises:
    OptionValueError: spread wider than the reach allows, or a root part wider than the support.
  """

  def __init__(self, furniture, base_xy, base_rot, reach, min_distance, root_distance, sector,
               spread, yaw_range, preassembled, support=support_lib.FLOOR, arms=1,
               side_reach=None, home_footprint=None, inner=0.2, gap=0.03,
               root_jitter=(0.03, np.radians(15)), max_attempts=200):
    self._furniture = furniture
    self._footprint = (np.zeros((0, 5)) if home_footprint is None
                       else np.asarray(home_footprint, dtype=float).reshape(-1, 5))
    self._base_rot = np.asarray(base_rot, dtype=float)
    self._arms, self._side_reach = arms, side_reach
    self._support = support
    self._base_xy = np.asarray(base_xy, dtype=float)
    self._heading = np.arctan2(base_rot[1, 0], base_rot[0, 0])
    # inner: clearance around the base; min_distance: nearest a part centre may lie
    # to the base (an arm pointing down cannot reach right beside itself).
    self._reach, self._inner, self._gap = reach, inner, gap
    self._min_distance = min_distance
    self._root_distance = root_distance
    self._root_jitter, self._sector, self._max_attempts = root_jitter, sector, max_attempts
    if spread is not None:
      room = reach - min_distance
      if spread > room + 1e-9:
        raise errors.OptionValueError(
            f"spread {spread!r} m is wider than this arm can reach: parts lie {min_distance} to "
            f"{reach} m from its base, so spread must be at most {room:.2f} m")
      self._reach = min_distance + spread
    self._yaw_range = float(yaw_range)
    self._groups = placement.PartGroups(furniture, preassembled)
    spec = furniture.spec
    self._root = planner.root_part(spec)
    rest, on_edge = root_rest(spec, furniture.connectors, self._root)
    # A root on its edge grows a carcass beside it: the carcass, not the root, is centred
    # where the root would lie, and its whole footprint is kept clear of the other parts.
    self._root_rest = rest if on_edge else self._across_if_far(furniture.connectors, rest,
                                                               reach)
    self._build_footprint = (assembled_footprint(spec, self._root, rest) if on_edge
                             else None)
    # Any yaw of the lying root fits within the disc of its half-diagonal.
    root_radius = np.linalg.norm(np.ptp(
        geometry.box_corners(*spec.parts[self._root].bounds) @ self._root_rest.T, axis=0)[:2]) / 2
    if support.bounded and not (np.asarray(support.half_size) > root_radius).all():
      raise errors.OptionValueError(
          f"{furniture.name}'s root part {spec.parts[self._root].name!r} ({2 * root_radius:.2f} m "
          f"across) does not fit on the work table ({2 * min(support.half_size):.2f} m); "
          f"use a smaller scale")
    self._racked = panel_placement.RackedPanels(spec, self._root, self._root_rest)
    # [(side, RackedPanels)]: one rack, on a side drawn at random (side None), or for two
    # arms one each side of the heading (tasks/panel_placement.split_by_side).
    self._racks = [(None, self._racked)] if self._racked.rack is not None else []
    if arms == 2 and len(self._racked.parts) > 1:
      self._racks = [
          (side, panel_placement.RackedPanels(
              spec, self._root, self._root_rest, only=parts,
              name="panel_rack_" + ("left" if side > 0 else "right")))
          for side, parts in panel_placement.split_by_side(
              spec, self._root, self._root_rest, self._racked.parts)]
    # Where the parts start: lying parts as ScatteredParts lays them, the root as it lies
    # here.
    self._rests = dict(self._groups.rests)
    self._rests.update(resting.rests_on_support(spec, {self._root: self._root_rest}))
    # A loose part that lies as it stands in the furniture built on the root as it lies
    # here: a flat frame (a shelving ladder, panel_placement.flat_frames) and a hollow part
    # (a drawer box, tasks/hollow_parts.py).
    self._as_assembled = dict(panel_placement.flat_frames(spec, self._root, self._root_rest))
    self._as_assembled.update({i: hollow_parts.assembled_rest(spec, self._root, self._root_rest, i)
                               for i, part in enumerate(spec.parts)
                               if i != self._root and hollow_parts.is_hollow(part)})
    if self._as_assembled:
      self._rests.update(resting.rests_on_support(spec, self._as_assembled))

  def _across_if_far(self, table, rest, reach):
    """The root's resting rotation `rest`, turned a quarter turn about the vertical when,
    lying as `rest` has it (its yaw unjittered), a connector of it would lie beyond ROOT_FAR
    of `reach` from the base and the turn brings the farthest one ROOT_GAIN nearer."""
    local = table.local_pos[table.part == self._root]

    def farthest(rotation):   # in the heading's frame, the root centred as __call__ places it
      _, centre, radius = self._item_footprint([(self._root, rotation, np.zeros(3))], np.eye(3))
      out = [self._root_out(radius), 0.0]
      return np.linalg.norm((local @ rotation.T)[:, :2] - centre + out, axis=1).max()

    turned = geometry.rot_z(np.pi / 2) @ rest
    far = farthest(rest) if local.size else 0.0
    if far > ROOT_FAR * reach and farthest(turned) < far - ROOT_GAIN:
      return turned
    return rest

  @property
  def fixtures(self):
    """Static entities the task attaches to the arena: the panel racks, if any panel stands."""
    return [racked.rack for _, racked in self._racks]

  @property
  def racked_parts(self):
    """Indices of the parts that stand in a panel rack (when not preassembled)."""
    return self._racked.parts

  @property
  def rack_groups(self):
    """The racked parts (indices) of each rack, one list per rack, in `fixtures`' order."""
    return [racked.parts for _, racked in self._racks]

  @property
  def root_part(self):
    """Index of the part placed in front of the base (the one everything is built onto)."""
    return self._root

  @property
  def preassembled_pairs(self):
    """Connector pairs (indices into the furniture's table) placed mated this episode."""
    return self._groups.preassembled_pairs

  def _root_out(self, radius):
    """How far (m) from the base the root's centre lies, its footprint `radius` across."""
    return max(self._inner + radius, self._root_distance)

  def _item_footprint(self, item, yaw_rot):
    """World-aligned corners, centre and radius of a group of (part, rot, pos) turned by yaw_rot."""
    corners = np.concatenate([geometry.box_corners(*self._furniture.spec.parts[i].bounds)
                              @ (yaw_rot @ rot).T
                              + yaw_rot @ pos for i, rot, pos in item])
    centre = (corners[:, :2].max(0) + corners[:, :2].min(0)) / 2
    return corners, centre, np.linalg.norm(corners[:, :2] - centre, axis=1).max()

  @staticmethod
  def _item_top(corners):
    """Height (m) above the support of the top of a group laid with these corners."""
    return float(np.ptp(corners[:, 2])) + resting.LANDING

  def _place(self, physics, item, yaw_rot, xy):
    corners, centre, _ = self._item_footprint(item, yaw_rot)
    shift = np.array([*(xy - centre),
                      placement.lift(item, corners, self._rests, self._support.height)])
    for index, rot, pos in item:
      part = self._furniture.parts[index]
      part.set_pose(physics, position=yaw_rot @ pos + shift,
                    quaternion=geometry.mat_to_quat(yaw_rot @ rot))
      part.set_velocity(physics, velocity=np.zeros(3), angular_velocity=np.zeros(3))

  def __call__(self, physics, random_state):
    items = self._groups.draw_items(random_state)   # single parts lie flat; joined groups upright
    items = [[(item[0][0], self._rests[item[0][0]].rotation, item[0][2])]
             if len(item) == 1 and item[0][0] in self._as_assembled else item for item in items]
    root_item = next(item for item in items if any(i == self._root for i, _, _ in item))
    if len(root_item) == 1:   # the root alone: turned over when its mates attach from below
      root_item = [(self._root, self._rests[self._root].rotation, np.zeros(3))]
    offset, yaw_jitter = self._root_jitter
    yaw_rot = geometry.rot_z(self._heading + random_state.uniform(-yaw_jitter, yaw_jitter))
    corners, _, radius = self._item_footprint(root_item, yaw_rot)
    top = self._item_top(corners)
    forward = np.array([np.cos(self._heading), np.sin(self._heading)])
    distance = self._root_out(radius)
    xy = self._base_xy + forward * distance + random_state.uniform(-offset, offset, 2)
    # A wide root moves out along the heading until it lies on the table, clear of the robot.
    while not self._support.contains(xy, radius) or not self._clear_of_robot(xy, radius, top):
      distance += 0.02
      xy = self._base_xy + forward * distance
      if distance > self._support.farthest_from(self._base_xy):
        raise composer.EpisodeInitializationError(
            f"the root part (radius {radius:.2f} m) does not fit on the work table")
    placed = [(xy, radius)]
    if self._build_footprint is not None and len(root_item) == 1:
      shift, build_radius = self._build_footprint
      placed = [(xy, build_radius)]
      xy = xy - yaw_rot[:2, :2] @ shift
    self._place(physics, root_item, yaw_rot, xy)
    racked = set(self.racked_parts) & {item[0][0] for item in items if len(item) == 1}
    for side, racked_panels in self._racks:   # each across a radius from the base, in the band
      radius = racked_panels.radius
      xy = self._sample_xy(random_state, radius, placed, racked_panels.height, reach=np.sqrt(max(
          0.0, (self._reach - panel_placement.RACK_SPARE) ** 2
          - racked_panels.farthest_slot ** 2)), side=side)
      away = xy - self._base_xy
      racked_panels.place(physics, self._furniture, xy, np.arctan2(away[1], away[0]) + np.pi / 2,
                          self._support.height, random_state,
                          skip=set(self.racked_parts) - racked)
      placed.append((xy, radius))
    # Drawn at random, all of a stool's legs lay on one side of Baxter's torso in 1 of
    # 8 episodes, and one arm did all the work.
    side = (1.0 if random_state.uniform() < 0.5 else -1.0) if self._arms == 2 else None
    for item in items:
      if any(i == self._root for i, _, _ in item) or (len(item) == 1 and item[0][0] in racked):
        continue
      yaw_rot = geometry.rot_z(random_state.uniform(-self._yaw_range, self._yaw_range))
      corners, _, radius = self._item_footprint(item, yaw_rot)
      xy = self._sample_xy(random_state, radius, placed, self._item_top(corners), side=side)
      side = None if side is None else -side
      self._place(physics, item, yaw_rot, xy)
      placed.append((xy, radius))

  def _clear_of_robot(self, xy, radius, top):
    """Whether a footprint of `radius` about `xy`, `top` (m) high above the support, keeps
    `gap` clear of the robot at its home pose: of every box of its home footprint whose
    lowest point is less than `gap` above that top. The Baxter's torso is 0.67 m wide (a
    0.8 m bed rail drawn beside it, its centre 0.62 m out, lay against it and was pushed);
    its arms hang at home over the band where parts lie, their grippers 0.35 m above it."""
    low = self._footprint[:, 4] - self._support.height < top + self._gap
    if not low.any():
      return True
    boxes = self._footprint[low]
    local = self._base_rot[:2, :2].T @ (np.asarray(xy) - self._base_xy)
    outside = np.maximum(np.maximum(boxes[:, 0:2] - local, local - boxes[:, 2:4]), 0.0)
    return bool((np.linalg.norm(outside, axis=1) >= radius + self._gap).all())

  def _sample_xy(self, random_state, radius, placed, top, reach=None, side=None):
    """A free xy for an item of `radius`, `top` (m) high, between the nearest distance
    allowed and `reach` (default the band's outer edge; given, it may leave a band only
    1 cm wide); with `side` (+1 left, -1 right of the heading), in that half of the
    sector if it has room within reach, else in the other half."""
    nearest = max(self._min_distance, self._inner + radius)
    outer = max(self._reach, nearest + 0.1) if reach is None else max(reach, nearest + 0.01)
    # A wide table top leaves one half room for a single leg: its second one spilled out
    # of reach in 31 of 40 Baxter episodes of table_four_leg_w120_white.
    halves = [None] if side is None else [side, -side]
    further = 0.0   # how much further out the band reaches at the sides, once needed
    while True:
      for half in halves:
        for _ in range(self._max_attempts):
          distance = random_state.uniform(nearest, outer)
          turn = random_state.uniform(-self._sector, self._sector)
          # At the sides the band reaches `further` out: the draw is stretched to it rather
          # than drawn again, so placements that never need it keep their random draws.
          if further and abs(turn) >= self._side_reach[0]:
            distance = nearest + (distance - nearest) * (outer + further - nearest) / (
                outer - nearest)
          angle = self._heading + (turn if half is None else half * abs(turn))
          xy = self._base_xy + distance * np.array([np.cos(angle), np.sin(angle)])
          if (all(np.linalg.norm(xy - other) > radius + other_r + self._gap
                  for other, other_r in placed) and self._support.contains(xy, radius)
              and self._clear_of_robot(xy, radius, top)):
            return xy
      if self._side_reach and reach is None and not further:
        further = self._side_reach[1] - self._reach   # out at the sides, still within reach
        continue
      outer += 0.25   # out of room within reach: spill outwards rather than fail
      if outer > min(10.0, self._support.farthest_from(self._base_xy) + 0.25):
        where = " on the work table" if self._support.bounded else ""
        raise composer.EpisodeInitializationError(
            f"no room{where} for a part of radius {radius:.2f} m; use a smaller scale")


def for_reach_zone(furniture, reach_zone, support, spread, yaw_range, preassembled):
  """ReachableParts for an arm's `reach_zone` (robots.base.ReachZone), on `support`, with
  the placement options of a config.TaskConfig (spread None: the whole band)."""
  return ReachableParts(furniture, reach_zone.base_xy, reach_zone.base_rot, reach_zone.reach,
                        reach_zone.min_distance, reach_zone.root_distance, reach_zone.sector,
                        spread=spread, yaw_range=yaw_range, preassembled=preassembled,
                        support=support, arms=reach_zone.arms, side_reach=reach_zone.side_reach,
                        home_footprint=reach_zone.home_footprint)
