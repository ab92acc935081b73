"""Connect in one world: pick the nearest attachable pair, snap, weld, merge groups, close loops.

As `tasks/assembly.py`: among free mating pairs on parts of different groups
that pass the alignment test, the nearest whose snap keeps the moving group
out of the floor is joined; the smaller group moves so the two connector
frames coincide exactly at the twist slot; the declared weld of that (pair,
slot) is switched on; groups merge; then every free pair inside the new group
that is attachable is welded too (loop closures).

The snap check differs from the CPU task: with parts not colliding with one
another in the batch (see model.py) the only obstacle is the floor, and the
check is analytic, the lowest corner of the moving group's collision boxes
after the snap against SNAP_PENETRATION_TOL, for every candidate at once.
"""

import jax
import jax.numpy as jnp

from ikea_suite.batch import align
from ikea_suite.batch import cursor as cursor_lib
from ikea_suite.batch import rigid
from ikea_suite.batch import task_state
from ikea_suite.tasks import assembly

SNAP_PENETRATION_TOL = assembly.SNAP_PENETRATION_TOL
_CORNER_SIGNS = jnp.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0)
                           for z in (-1.0, 1.0)])


def _geom_corners(tables, part_pos, part_rot):
  """World corners (g, 8, 3) of every part collision box."""
  local = tables.geom_center[:, None] + _CORNER_SIGNS[None] * tables.geom_half[:, None]
  in_part = tables.geom_pos[:, None] + jnp.einsum("gij,gcj->gci", tables.geom_rot, local)
  rot = part_rot[tables.geom_part]
  return part_pos[tables.geom_part][:, None] + jnp.einsum("gij,gcj->gci", rot, in_part)


def _snaps(tables, scores, cpos, crot, group):
  """Per candidate pair: the rigid motion (delta rotation, from-point, to-point) that snaps
  the smaller group, and that group's label."""
  pairs = tables.pairs
  a, b = pairs.pair_a, pairs.pair_b
  part_a, part_b = pairs.part[a], pairs.part[b]
  sizes = jnp.sum(group[None, :] == group[:, None], axis=1)
  move_b = sizes[part_b] <= sizes[part_a]
  slot_twist = jnp.take_along_axis(pairs.slot_angles, scores.slot[:, None], axis=1)[:, 0]
  twist = jnp.where(move_b, slot_twist, -slot_twist)
  fixed_rot = jnp.where(move_b[:, None, None], crot[a], crot[b])
  moving_rot = jnp.where(move_b[:, None, None], crot[b], crot[a])
  delta = fixed_rot @ rigid.rot_z(twist) @ jnp.swapaxes(moving_rot, 1, 2)
  origin = jnp.where(move_b[:, None], cpos[b], cpos[a])
  target = jnp.where(move_b[:, None], cpos[a], cpos[b])
  label = jnp.where(move_b, group[part_b], group[part_a])
  return delta, origin, target, label


def _close_loops(tables, thresholds, state, eq_active, part_pos, part_rot):
  """Welds free attachable pairs inside one group, nearest first, one per connector."""
  pairs = tables.pairs
  cpos, crot = align.connector_frames(pairs, part_pos, part_rot)
  scores = align.align_pairs(pairs, cpos, crot)
  a, b = pairs.pair_a, pairs.pair_b
  part_a, part_b = pairs.part[a], pairs.part[b]
  inside = (state.group[part_a] == state.group[part_b]) & scores.attachable(thresholds)
  order = jnp.argsort(jnp.where(inside, scores.distance, jnp.inf))

  def body(i, carry):
    used, adjacency, eq_active = carry
    k = order[i]
    ok = inside[k] & ~used[a[k]] & ~used[b[k]]
    weld = ok & ~adjacency[part_a[k], part_b[k]]
    eq = tables.slot_eq[k, scores.slot[k]]
    eq_active = eq_active.at[eq].set(eq_active[eq] | weld)
    used = used.at[a[k]].set(used[a[k]] | ok).at[b[k]].set(used[b[k]] | ok)
    link = adjacency[part_a[k], part_b[k]] | ok
    adjacency = adjacency.at[part_a[k], part_b[k]].set(link).at[part_b[k], part_a[k]].set(link)
    return used, adjacency, eq_active

  used, adjacency, eq_active = jax.lax.fori_loop(
      0, len(order), body, (state.connector_used, state.adjacency, eq_active))
  return state._replace(connector_used=used, adjacency=adjacency), eq_active


def connect(tables, thresholds, state, qpos, qvel, eq_active, request):
  """Connects the nearest attachable pair when `request` is true.

  Args:
    tables: the furniture's Tables.
    thresholds: a tasks.alignment.Thresholds.
    state: TaskState.
    qpos, qvel, eq_active: the world's MuJoCo state.
    request: bool, the agent's connect action is on.

  Returns:
    (state, qpos, qvel, eq_active, connected) where connected is a bool. A cursor that
    lets go (see cursor.on_parts_moved) has its grip weld switched off.
  """
  pairs = tables.pairs
  part_pos, part_rot = task_state.part_poses(tables, qpos)
  cpos, crot = align.connector_frames(pairs, part_pos, part_rot)
  scores = align.align_pairs(pairs, cpos, crot)
  a, b = pairs.pair_a, pairs.pair_b
  part_a, part_b = pairs.part[a], pairs.part[b]
  group = state.group
  open_pairs = (~state.connector_used[a] & ~state.connector_used[b]
                & (group[part_a] != group[part_b]))
  delta, origin, target, label = _snaps(tables, scores, cpos, crot, group)
  # Lowest corner of the moving group after each candidate snap (floor at z = 0).
  corners = _geom_corners(tables, part_pos, part_rot)                     # (g, 8, 3)
  moved_z = target[:, None, None, 2] + jnp.einsum(
      "kj,kgcj->kgc", delta[:, 2, :], corners[None] - origin[:, None, None])
  in_group = group[tables.geom_part][None, :] == label[:, None]            # (k, g)
  lowest = jnp.min(jnp.where(in_group[:, :, None], moved_z, jnp.inf), axis=(1, 2))
  valid = scores.attachable(thresholds) & open_pairs & (lowest >= -SNAP_PENETRATION_TOL)
  k = jnp.argmin(jnp.where(valid, scores.distance, jnp.inf))
  connected = request & valid[k]
  # Snap the moving group of pair k.
  moving = connected & (group == label[k])
  new_rot = delta[k] @ part_rot
  new_pos = target[k] + rigid.apply(delta[k], part_pos - origin[k])
  part_pos = jnp.where(moving[:, None], new_pos, part_pos)
  part_rot = jnp.where(moving[:, None, None], new_rot, part_rot)
  qpos, qvel = task_state.write_part_poses(tables, qpos, qvel, part_pos, part_rot, moving)
  eq = tables.slot_eq[k, scores.slot[k]]
  eq_active = eq_active.at[eq].set(eq_active[eq] | connected)
  pa, pb = part_a[k], part_b[k]
  merged = jnp.where(group == group[pb], group[pa], group)
  used = state.connector_used.at[a[k]].set(True).at[b[k]].set(True)
  adjacency = state.adjacency.at[pa, pb].set(True).at[pb, pa].set(True)
  state = state._replace(
      group=jnp.where(connected, merged, group),
      connector_used=jnp.where(connected, used, state.connector_used),
      adjacency=jnp.where(connected, adjacency, state.adjacency))
  closed, closed_eq = _close_loops(tables, thresholds, state, eq_active, part_pos, part_rot)
  state = jax.tree.map(lambda x, y: jnp.where(connected, x, y), closed, state)
  eq_active = jnp.where(connected, closed_eq, eq_active)
  held_before = jnp.maximum(state.held, 0)
  moved_state, released = cursor_lib.on_parts_moved(state, part_pos, part_rot, moving)
  state = jax.tree.map(lambda x, y: jnp.where(connected, x, y), moved_state, state)
  grips = tables.grip_eq[jnp.arange(2), held_before]
  eq_active = eq_active.at[grips].set(eq_active[grips] & ~(released & connected))
  return state, qpos, qvel, eq_active, connected
