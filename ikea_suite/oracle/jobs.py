"""Which part an arm brings next, from privileged state."""

import numpy as np

from ikea_suite.tasks import planner


def nearest_open_job(task, physics, base_pos, skip=()):
  """(connector pair, moving part) of the open pair joining the root's group whose fixed
  connector, and then whose loose part, is nearest the arm's base; None when no part is
  left (parts in `skip` are passed over: the arm could not reach or hold them)."""
  table, state = task.furniture.connectors, task.state
  groups = state.group_labels()
  root_group = groups[task.root_part]
  positions, rotations = task.furniture.part_poses(physics)
  cpos, _ = table.world_frames(positions, rotations)
  best = None
  for pair in np.flatnonzero(planner.open_pairs(table, state)):
    a, b = table.pair_a[pair], table.pair_b[pair]
    for fixed, moving in ((a, b), (b, a)):
      if groups[table.part[fixed]] != root_group or groups[table.part[moving]] == root_group:
        continue
      if table.part[moving] in skip:
        continue
      distance = (np.linalg.norm(cpos[fixed][:2] - base_pos[:2])
                  + np.linalg.norm(positions[table.part[moving]][:2] - base_pos[:2]))
      if best is None or distance < best[0]:
        best = (distance, int(pair), int(table.part[moving]))
  return None if best is None else best[1:]
