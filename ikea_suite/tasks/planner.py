"""Suggests the next connection: grow one assembly from a root part, pair by pair."""

import numpy as np


def root_part(spec):
  """The part everything is built onto: most connectors, then largest, then first."""
  counts = [sum(c.part == p.name for c in spec.connectors) for p in spec.parts]
  volumes = [np.prod(p.bounds[1] - p.bounds[0]) for p in spec.parts]
  return max(range(len(spec.parts)), key=lambda i: (counts[i], volumes[i], -i))


def open_pairs(table, state):
  """Mask of candidate pairs still possible: both connectors free, parts apart."""
  part_a, part_b = table.part[table.pair_a], table.part[table.pair_b]
  groups = state.group_labels()
  return (~state.connector_used[table.pair_a] & ~state.connector_used[table.pair_b]
          & (groups[part_a] != groups[part_b]))


def next_pair(table, state, root):
  """(pair index, moving part, target part) of the suggested connection, or None when done.

  The target part is in the root's group; the moving part joins it. Pairs that
  do not touch the root's group are suggested only if none does.
  """
  open_mask = open_pairs(table, state)
  if not open_mask.any():
    return None
  groups = state.group_labels()
  root_group = groups[root]
  part_a, part_b = table.part[table.pair_a], table.part[table.pair_b]
  touches = (groups[part_a] == root_group) | (groups[part_b] == root_group)
  candidates = np.flatnonzero(open_mask & touches)
  if not len(candidates):
    candidates = np.flatnonzero(open_mask)
  pair = int(candidates[0])
  a, b = int(part_a[pair]), int(part_b[pair])
  if groups[a] == root_group:
    return pair, b, a
  return pair, a, b
