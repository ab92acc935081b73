"""Which part an arm brings next, from privileged state."""

import numpy as np

from ikea_suite.experts import part_geometry
from ikea_suite.experts import turn_over
from ikea_suite.tasks import panel_placement
from ikea_suite.tasks import planner


# A lid covers a part whose footprint reaches up to this far (m) beyond its own: a
# drawer's front stands 10 mm proud of a nightstand's sides at scale 0.5.
LID_MARGIN = 0.02


def nearest_open_job(task, physics, base_pos, skip=()):
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
  seat). None, too, while the part chosen would cover (`covers`) a part in `skip`: the
  caller then tries the parts it passed over again."""
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
  best = None
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
      if best is None or key < best[0]:
        best = (key, int(pair), int(table.part[moving]))
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
