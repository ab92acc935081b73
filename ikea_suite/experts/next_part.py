"""Which part an arm brings next, from privileged state."""

import numpy as np

from ikea_suite.experts import part_geometry
from ikea_suite.experts import turn_over
from ikea_suite.tasks import panel_placement
from ikea_suite.tasks import planner

# A part must reach more than this fraction of the connect distance above another's open
# mate to stand in its way: a bookcase's shelves end 1.5 mm under the far side's mates
# (scale 0.5) and leave its way in clear.
_ABOVE_FRACTION = 0.1
# ... and the other part must land higher by more than the connect distance: mates the
# same height in the design (a box base's slots, a table top's) differ by millimetres
# where the root lies tilted, and only a clear difference orders two parts.
_HIGHER_FRACTION = 1.0
# Steps of the search for the point of the line above a mate nearest a part's box (the
# distance is convex along the line; each step keeps two thirds of the interval).
_SEARCH_STEPS = 60


def stands_over(task, physics, part, mate_pos, hand):
  """Whether `part`, in its assembled place (laid out from the root as it lies now),
  reaches above the world point `mate_pos` (a connector another part will land on)
  within `hand` (m) of the vertical line through it: it would stand in the way of that
  part coming down onto it, and of the hand that brings it, which reaches `hand` in from
  the edge it holds.

  Args:
    task: the arm task (its furniture, root part and thresholds).
    physics: the simulation, for the root's present pose.
    part: index of the part that may stand in the way.
    mate_pos: world position (3,) of the open connector.
    hand: how far (m) beside the line the hand reaches.

  Returns:
    True when some point of the line above the mate, higher than a tenth of the connect
    distance over it, lies within `hand` of the part's assembled collision box.
  """
  furniture = task.furniture
  pos, rot = part_geometry.assembled_pose(physics, furniture, task.root_part, part)
  low, high = furniture.spec.parts[part].bounds
  top = part_geometry.part_corners(furniture, part, pos, rot)[:, 2].max()
  bottom = mate_pos[2] + _ABOVE_FRACTION * task.thresholds.distance
  if top <= bottom:
    return False
  def gap(height):
    local = (np.array([mate_pos[0], mate_pos[1], height]) - pos) @ rot
    return float(np.linalg.norm(local - np.clip(local, low, high)))

  for _ in range(_SEARCH_STEPS):
    third = (top - bottom) / 3.0
    if gap(bottom + third) <= gap(top - third):
      top -= third
    else:
      bottom += third
  return gap(0.5 * (bottom + top)) <= hand


def must_wait(task, physics, jobs, hand):
  """The parts among `jobs` that must wait for another: a part that would stand over an
  open mate (stands_over) of another part landing higher waits until that part is in,
  whose way in it would block (the assembly-by-disassembly test on the assembled poses).
  A cabinet's door, hinged to the root side lying flat, stands 15 mm (scale 1) above the
  far side's mates, in front of its edge, where the hand holding that edge comes down.
  Since a part only waits for one landing higher (by more than the connect distance),
  some part never waits.

  Args:
    task: the arm task.
    physics: the simulation.
    jobs: {moving part: world positions (n, 3) of the assembly's connectors it can mate
      with now}.
    hand: how far (m) the hand reaches in from the edge of a part it holds.

  Returns:
    The set of moving parts that wait.
  """
  landing = {part: float(points[:, 2].min()) for part, points in jobs.items()}
  tolerance = _HIGHER_FRACTION * task.thresholds.distance
  waiting = set()
  for part in jobs:
    for other, points in jobs.items():
      if other != part and landing[other] > landing[part] + tolerance and any(
          stands_over(task, physics, part, point, hand) for point in points):
        waiting.add(part)
        break
  return waiting


# A lid covers a part whose footprint reaches up to this far (m) beyond its own: a
# drawer's front stands 10 mm proud of a nightstand's sides at scale 0.5.
LID_MARGIN = 0.02


def nearest_open_job(task, physics, base_pos, skip=(), hand=0.0):
  """(connector pair, moving part) of the open pair joining the root's group whose fixed
  connector, and then whose loose part, is nearest the arm's base; None when no part is
  left (parts in `skip` are passed over: the arm could not reach or hold them). Mates on
  the root itself go first: a trestle desk's stretcher, joined to the first trestle
  before the second stood, left the second to go in over it, held high by its foot.
  Panels from a rack go to a mate on their rack's side first (a two-arm robot's racks,
  part_geometry.nearer_another_rack), and there to the mate farthest from their rack
  first, so that none is carried over another already standing (a trestle hung from the
  fingers struck the one before it), and the panel nearest that mate leaves first, so
  that none is carried past another still in the rack (a trestle 0.25 m wide knocked
  the next one out). A mate whose part would sit in the surface waits for the assembly
  to be turned over (turn_over.under_support: a chair's back, under its upside-down
  seat). A part that would stand in the way of another's coming in waits for it
  (must_wait, with the hand reaching `hand` m in from a held edge). None, too, while the
  part chosen would cover (`covers`) a part in `skip`: the caller then tries the parts it
  passed over again."""
  table, state = task.furniture.connectors, task.state
  groups = state.group_labels()
  root_group = groups[task.root_part]
  positions, rotations = task.furniture.part_poses(physics)
  cpos, _ = table.world_frames(positions, rotations)
  loose = [p for p in task.initializer.racked_parts if groups[p] != root_group]
  racks = {}   # each loose racked part: the middle of the loose panels in its rack
  for rack_parts in task.initializer.rack_groups:
    mine = [p for p in loose if p in rack_parts]
    for p in mine:
      racks[p] = positions[mine, :2].mean(axis=0)
  candidates = []   # (key, pair, moving part, fixed connector)
  for pair in np.flatnonzero(planner.open_pairs(table, state)):
    a, b = table.pair_a[pair], table.pair_b[pair]
    for fixed, moving in ((a, b), (b, a)):
      if groups[table.part[fixed]] != root_group or groups[table.part[moving]] == root_group:
        continue
      if table.part[moving] in skip or turn_over.under_support(
          physics, task.furniture, pair, table.part[moving], task.arena.support.height):
        continue
      here = positions[table.part[moving]][:2]
      if table.part[moving] in loose:
        key = (table.part[fixed] != task.root_part,
               waits_for_a_board(task, table.part[moving],
                                 [p for p in loose if p not in skip]),
               part_geometry.nearer_another_rack(task, physics, table.part[moving],
                                                 cpos[fixed]),
               -round(float(np.linalg.norm(cpos[fixed][:2] - racks[table.part[moving]])), 2),
               np.linalg.norm(here - cpos[fixed][:2]))
      else:
        key = (table.part[fixed] != task.root_part, False, False, 0.0,
               np.linalg.norm(cpos[fixed][:2] - base_pos[:2]) + np.linalg.norm(here - base_pos[:2]))
      candidates.append((key, int(pair), int(table.part[moving]), int(fixed)))
  jobs = {}
  for _, _, moving, fixed in candidates:
    jobs.setdefault(moving, []).append(cpos[fixed])
  waiting = must_wait(task, physics, {p: np.array(v) for p, v in jobs.items()}, hand)
  best = None
  for key, pair, moving, _ in candidates:
    if moving not in waiting and (best is None or key < best[0]):
      best = (key, pair, moving)
  if best is not None and any(covers(task, physics, best[2], other) for other in skip
                              if groups[other] != root_group):
    return None   # passed-over parts first: once covered, they could not go in
  return None if best is None else best[1:]


def waits_for_a_board(task, part, loose):
  """Whether `part`, racked, waits for a board (panel_placement.is_board: a plinth) among
  the `loose` racked parts to leave the rack first. Standing on its 18 x 8 mm end in a
  slot made for panels, a nightstand's plinth fell over when its neighbour was drawn
  out; and hanging from the fingers it came down 1.5 mm from the bottom shelf standing
  before it, caught on it and lifted the carcass."""
  spec = task.furniture.spec.parts

  def board(p):
    return panel_placement.is_board(spec[p].bounds[1] - spec[p].bounds[0])

  return not board(part) and any(board(p) for p in loose if p != part)


def covers(task, physics, part, other):
  """Whether `part`, in its assembled place on the root as the root lies now, lies over
  `other` in its own as a lid: its lowest corner above the middle of `other`, and
  `other`'s footprint within its own, grown by LID_MARGIN. A nightstand's far side, lying
  over its drawer, closes the way down to the drawer's mate; put in while the drawer was
  passed over, the drawer never went in."""
  furniture, root = task.furniture, task.root_part
  corners = [part_geometry.part_corners(furniture, p, *part_geometry.assembled_pose(
      physics, furniture, root, p)) for p in (part, other)]
  low, high = corners[0].min(0), corners[0].max(0)
  other_low, other_high = corners[1].min(0), corners[1].max(0)
  within = ((other_low[:2] > low[:2] - LID_MARGIN).all()
            and (other_high[:2] < high[:2] + LID_MARGIN).all())
  return bool(within and low[2] > 0.5 * (other_low[2] + other_high[2]))
