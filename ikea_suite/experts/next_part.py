"""Which part an arm brings next, from privileged state."""

import numpy as np

from ikea_suite.experts import part_geometry
from ikea_suite.experts import turn_over
from ikea_suite.tasks import planner


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
  seat)."""
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
               part_geometry.nearer_another_rack(task, physics, table.part[moving],
                                                 cpos[fixed]),
               -round(float(np.linalg.norm(cpos[fixed][:2] - racks[table.part[moving]])), 2),
               np.linalg.norm(here - cpos[fixed][:2]))
      else:
        key = (table.part[fixed] != task.root_part, False, 0.0,
               np.linalg.norm(cpos[fixed][:2] - base_pos[:2]) + np.linalg.norm(here - base_pos[:2]))
      if best is None or key < best[0]:
        best = (key, int(pair), int(table.part[moving]))
  return None if best is None else best[1:]
