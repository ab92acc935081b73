"""Observations of one world, named and shaped as the CPU environment's state observations.

`next_pair` is `tasks/planner.next_pair` in array form: the first part of the
buildable order outside the root's group, by a free pair reaching the root's
group, preferring a pair on the part itself and one from the design.
"""

import jax.numpy as jnp

from ikea_suite.batch import rigid
from ikea_suite.batch import task_state


def next_pair(tables, state):
  """[moving part, target part] of the suggested connection, [-1, -1] when none is open."""
  pairs = tables.pairs
  part_a, part_b = pairs.part[pairs.pair_a], pairs.part[pairs.pair_b]
  group = state.group
  group_a, group_b = group[part_a], group[part_b]
  open_mask = (~state.connector_used[pairs.pair_a] & ~state.connector_used[pairs.pair_b]
               & (group_a != group_b))
  root = group[tables.order[0]]
  to_root = open_mask & ((group_a == root) | (group_b == root))
  part = tables.order[:, None]                                   # (p, 1)
  own = group[tables.order][:, None]
  joins = to_root[None] & ((group_a[None] == own) | (group_b[None] == own)) & (own != root)
  on_part = joins & ((part_a[None] == part) | (part_b[None] == part))
  design = tables.design_pair[None]
  levels = jnp.stack([on_part & design, on_part, joins & design, joins], axis=1)   # (p, 4, k)
  flat = levels.reshape(-1)
  k = jnp.where(flat.any(), jnp.argmax(flat) % open_mask.shape[0], jnp.argmax(open_mask))
  a, b = part_a[k], part_b[k]
  oriented = jnp.where(group[a] == root, jnp.stack([b, a]), jnp.stack([a, b]))
  return jnp.where(open_mask.any(), oriented, -1)


def observe(tables, state, qpos):
  """The state observations of one world (jax default float), under the CPU environment's
  vocabulary keys (ikea_suite.observations); the vector env gives them the CPU dtypes.

  Returns:
    dict: furniture/part_positions (p, 3), furniture/part_quaternions (p, 4),
    task/connections (p, p), task/connectors_used (c,), task/next_pair (2,),
    robot/tcp_positions (2, 3), robot/tcp_quaternions (2, 4), robot/held_parts (2,).
  """
  f32 = rigid.real
  return {
      **task_observations(tables, state, qpos),
      "robot/tcp_positions": f32(state.cursor_pos),
      "robot/tcp_quaternions": f32(state.cursor_quat),
      "robot/held_parts": f32(state.held),
  }


def task_observations(tables, state, qpos):
  """The `furniture/` and `task/` observations of one world, whatever the robot.

  Returns:
    dict: furniture/part_positions (p, 3), furniture/part_quaternions (p, 4),
    task/connections (p, p), task/connectors_used (c,), task/next_pair (2,).
  """
  pos, rot = task_state.part_poses(tables, qpos)
  f32 = rigid.real
  return {
      "furniture/part_positions": f32(pos),
      "furniture/part_quaternions": f32(rigid.mat_to_quat(rot)),
      "task/connections": f32(state.adjacency),
      "task/connectors_used": f32(state.connector_used),
      "task/next_pair": f32(next_pair(tables, state)),
  }
