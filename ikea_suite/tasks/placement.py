"""Initial placement: every part lies flat on the floor, scattered around the assembly area.

A part lies on its largest face (`resting_rotation`) and lands from just above the floor,
unless it would not come to rest so: then it starts in the pose it rests in
(tasks/resting.py).
"""

import abc

import numpy as np
from dm_control import composer

from ikea_suite import geometry
from ikea_suite.assembly import graph
from ikea_suite.tasks import planner
from ikea_suite.tasks import resting

CLEARANCE = 0.15   # m from the assembled furniture's radius to the ring parts lie in
GAP = 0.03         # m, least gap between two placed parts
# part axis -> a rotation turning that axis of the part to world z
LIE_ON = {0: np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]]),   # part x axis to world z
          1: np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),   # part y axis to world z
          2: np.eye(3)}


def resting_rotation(bounds):
  """Rotation laying a part on its largest face: its thinnest extent becomes vertical."""
  return LIE_ON[int(np.argmin(bounds[1] - bounds[0]))]


def lying_rests(spec):
  """part index -> resting.Rest of every part laid on its largest face on a flat support."""
  return resting.rests_on_support(
      spec, {i: resting_rotation(p.bounds) for i, p in enumerate(spec.parts)})


def lift(item, corners, rests, height=0.0):
  """Height (m) to raise an item (a list of (part, rotation, position) placed together)
  by, on a support `height` high: to its rest height for a single part that starts at
  rest (resting.Rest.position), else its lowest corner (`corners`, (n, 3), as placed
  before the lift) resting.LANDING above the support."""
  if len(item) == 1 and rests[item[0][0]].position is not None:
    return height + rests[item[0][0]].position[2]
  return height - corners[:, 2].min() + resting.LANDING


def assembled_radius(spec):
  """Horizontal radius of the assembled furniture around the origin."""
  return max(np.linalg.norm(p.assembled_corners()[:, :2], axis=1).max() for p in spec.parts)


class PartInitializer(composer.Initializer, abc.ABC):
  """Places the furniture's parts at the start of an episode (the task's `initializer`).

  Besides posing parts it says which connector pairs it placed already
  mated, so the task welds them before the first step (the curriculum).
  """

  @property
  @abc.abstractmethod
  def preassembled_pairs(self):
    """Indices into the furniture's connector-pair table placed mated this episode; may be empty."""

  @property
  def fixtures(self):
    """Static entities the placement needs in the scene (the task attaches them); none here."""
    return []


class PartGroups:
  """What an initializer places each episode: single parts lying flat and, for the
  curriculum, groups of parts already connected.

  `preassembled` is an inclusive (low, high) range of connection counts drawn each
  episode, capped at parts - 2 so at least one connection remains. Below the cap the
  connections are a random forest of the connections of the assembled design. At the
  cap (the last-part start: every part but one joined) one part is left loose, drawn
  among those whose removal leaves the rest of the design connected, the root
  (planner.root_part, the part everything is built onto) excepted, and the rest is joined
  by a random spanning tree of its design connections: for a design whose connections
  form a cycle (a bench's seat, ends and stretcher) a forest could leave two groups of
  two parts. Each resulting group keeps its assembled shape, upright. The chosen
  connector pairs are left in `preassembled_pairs` for the task to weld.
  """

  def __init__(self, furniture, preassembled):
    self._furniture = furniture
    self._preassembled = tuple(preassembled)
    self._design_pairs = design_pairs(furniture.spec, furniture.connectors)
    self._preassembled_pairs = []
    self._rests = lying_rests(furniture.spec)

  @property
  def rests(self):
    """part index -> resting.Rest of each part lying alone (see draw_items)."""
    return self._rests

  @property
  def preassembled_pairs(self):
    """Connector pairs (indices into the furniture's table) placed mated this episode."""
    return list(self._preassembled_pairs)

  def _spec(self, index):
    return self._furniture.spec.parts[index]

  def draw_items(self, random_state):
    """Draws this episode's preassembled groups (see `preassembled_pairs`) and returns them.

    Args:
      random_state: numpy RandomState.
    Returns:
      Lists of (part index, rotation (3, 3), position (3,) in m) to place rigidly
      together, largest first: a single part lying at rest (`rests`), or a group in
      its assembled pose relative to the furniture origin.
    """
    groups = self._choose_groups(random_state)
    items = []
    for group in groups:
      if len(group) == 1:
        items.append([(group[0], self._rests[group[0]].rotation, np.zeros(3))])
      else:
        items.append([(i, self._spec(i).rot, self._spec(i).pos) for i in group])
    def extent(item):
      return np.ptp(np.concatenate([geometry.box_corners(*self._spec(i).bounds) @ rot.T + pos
                                    for i, rot, pos in item]), axis=0).max()
    return sorted(items, key=lambda item: -extent(item))

  def _choose_groups(self, random_state):
    num_parts = len(self._furniture.parts)
    self._preassembled_pairs = []
    low, high = self._preassembled
    if high == 0:
      return [[i] for i in range(num_parts)]
    count = min(int(random_state.randint(low, high + 1)), max(num_parts - 2, 0))
    table = self._furniture.connectors
    order = random_state.permutation(self._design_pairs)
    loose = None
    if num_parts >= 2 and count == num_parts - 2:
      choices = last_part_choices(self._furniture.spec, table, self._design_pairs)
      if choices:
        loose = choices[int(random_state.randint(len(choices)))]
    group = list(range(num_parts))
    for pair in order:
      if len(self._preassembled_pairs) >= count:
        break
      part_a, part_b = int(table.part[table.pair_a[pair]]), int(table.part[table.pair_b[pair]])
      a, b = group[part_a], group[part_b]
      if a != b and loose not in (part_a, part_b):
        group = [a if g == b else g for g in group]
        self._preassembled_pairs.append(int(pair))
    return [[i for i in range(num_parts) if group[i] == g] for g in sorted(set(group))]


def last_part_choices(spec, table, pairs):
  """Parts that may be the last one in a last-part start: those whose removal leaves the
  other parts connected by the design's connections (`pairs`, indices into `table`'s
  candidate pairs), the root (planner.root_part) excepted.

  Returns:
    Sorted part indices; empty when the design's connections do not join every part.
  """
  num_parts = len(spec.parts)
  edges = [(int(table.part[table.pair_a[k]]), int(table.part[table.pair_b[k]])) for k in pairs]
  if not graph.connected(num_parts, edges):
    return []
  root = planner.root_part(spec)
  return [i for i in range(num_parts)
          if i != root and graph.connected(set(range(num_parts)) - {i}, edges)]


class ScatteredParts(PartInitializer):
  """Places parts lying flat, random yaw, in a ring around the origin without overlap.

  The ring starts CLEARANCE beyond the assembled furniture's radius and is
  `spread` metres wide (wider when too crowded to fit every part); `yaw` is
  a dm_control distribution (radians). `preassembled`: the (low, high) range of
  connections made before the episode (PartGroups); each group is scattered like a part.
  """

  def __init__(self, furniture, spread, preassembled, yaw, max_attempts=500):
    self._furniture = furniture
    self._spread, self._gap, self._yaw = spread, GAP, yaw
    self._inner = assembled_radius(furniture.spec) + CLEARANCE
    self._max_attempts = max_attempts
    self._groups = PartGroups(furniture, preassembled)

  @property
  def preassembled_pairs(self):
    """Connector pairs (indices into the furniture's table) placed mated this episode."""
    return self._groups.preassembled_pairs

  def __call__(self, physics, random_state):
    placed = []   # (xy, radius)
    for item in self._groups.draw_items(random_state):
      yaw_rot = geometry.rot_z(self._yaw(random_state=random_state))
      rots = [yaw_rot @ rot for _, rot, _ in item]
      offsets = [yaw_rot @ pos for _, _, pos in item]
      corners = np.concatenate([geometry.box_corners(*self._spec(i).bounds) @ rot.T + offset
                                for (i, _, _), rot, offset in zip(item, rots, offsets)])
      center_xy = (corners[:, :2].max(0) + corners[:, :2].min(0)) / 2
      radius = np.linalg.norm(corners[:, :2] - center_xy, axis=1).max()
      xy = self._sample_xy(random_state, radius, placed)
      placed.append((xy, radius))
      shift = np.array([*(xy - center_xy), lift(item, corners, self._groups.rests)])
      for (index, _, _), rot, offset in zip(item, rots, offsets):
        self._furniture.set_part_pose(physics, index, offset + shift, geometry.mat_to_quat(rot))

  def _spec(self, index):
    return self._furniture.spec.parts[index]

  def _sample_xy(self, random_state, radius, placed):
    centres = np.array([xy for xy, _ in placed]).reshape(-1, 2)
    radii = np.array([r for _, r in placed])
    for attempt in range(0, self._max_attempts, _BATCH):
      # A crowded ring widens by one part width every 100 failed draws.
      width = self._spread + (attempt // 100) * (2 * radius + self._gap)
      r = random_state.uniform(self._inner + radius, self._inner + radius + width, size=_BATCH)
      angle = random_state.uniform(-np.pi, np.pi, size=_BATCH)
      xy = r[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)
      gaps = np.linalg.norm(xy[:, None] - centres[None], axis=2) - radii - radius - self._gap
      free = np.flatnonzero((gaps > 0).all(axis=1))
      if len(free):
        return xy[free[0]]
    raise composer.EpisodeInitializationError(
        f"could not place a part of radius {radius:.2f} m without overlap; raise `spread`")


_BATCH = 100   # candidate positions drawn at once; the ring widens after each batch


def design_pairs(spec, table):
  """Indices into `table`'s candidate pairs of those that coincide in the assembled design."""
  assembled = set(spec.assembled_connector_pairs())
  return np.array([k for k, pair in enumerate(zip(table.pair_a, table.pair_b))
                   if tuple(int(c) for c in pair) in assembled], dtype=int)
