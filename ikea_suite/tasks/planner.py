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


def next_pair(table, state, order, design_pairs=()):
  """(pair index, moving part, target part) of the suggested connection, or None when done.

  `order` lists part indices in a buildable assembly order, root first. The
  suggestion brings in the first part of that order not yet joined to the
  root's group, by a free pair between its group and the root's group,
  preferring a pair on the part itself and one that coincides in the design
  (`design_pairs`). It follows the state, so connections made in another order
  are taken into account. When no pair reaches the root's group, any open
  pair is suggested.
  """
  open_mask = open_pairs(table, state)
  if not open_mask.any():
    return None
  groups = state.group_labels()
  root_group = groups[order[0]]
  part_a, part_b = table.part[table.pair_a], table.part[table.pair_b]
  group_a, group_b = groups[part_a], groups[part_b]
  to_root = open_mask & ((group_a == root_group) | (group_b == root_group))
  in_design = np.zeros(len(open_mask), dtype=bool)
  in_design[np.asarray(design_pairs, dtype=int)] = True
  for part in order:
    group = groups[part]
    if group == root_group:
      continue
    joins = to_root & ((group_a == group) | (group_b == group))
    on_part = joins & ((part_a == part) | (part_b == part))
    for mask in (on_part & in_design, on_part, joins & in_design, joins):
      if mask.any():
        return _oriented(int(np.flatnonzero(mask)[0]), part_a, part_b, groups, root_group)
  return _oriented(int(np.flatnonzero(open_mask)[0]), part_a, part_b, groups, root_group)


def _oriented(pair, part_a, part_b, groups, root_group):
  a, b = int(part_a[pair]), int(part_b[pair])
  if groups[a] == root_group:
    return pair, b, a
  return pair, a, b
