"""The task's per-world state besides MuJoCo's Data: cursors, what they hold, the scene graph."""

import typing

import jax.numpy as jnp

from ikea_suite.batch import rigid


class TaskState(typing.NamedTuple):
  """One world's task state (a pytree; batched worlds add a leading axis).

  Attributes:
    cursor_pos: (2, 3) cursor positions, m.
    cursor_quat: (2, 4) cursor orientations (w, x, y, z).
    held: (2,) int32 part each cursor holds, -1 for none.
    grip_pos: (2, 3) held part's position in its cursor's frame.
    grip_rot: (2, 3, 3) held part's orientation in its cursor's frame.
    group: (parts,) int32 group label per part (parts with one label are welded together).
    connector_used: (connectors,) bool.
    adjacency: (parts, parts) bool, True where a weld joins two parts (the scene graph).
    steps: int32 control steps taken this episode.
  """
  cursor_pos: jnp.ndarray
  cursor_quat: jnp.ndarray
  held: jnp.ndarray
  grip_pos: jnp.ndarray
  grip_rot: jnp.ndarray
  group: jnp.ndarray
  connector_used: jnp.ndarray
  adjacency: jnp.ndarray
  steps: jnp.ndarray


def part_poses(tables, qpos):
  """World positions (p, 3) and rotations (p, 3, 3) of the parts, read from qpos."""
  q = qpos[tables.part_qpos]
  quat = q[:, 3:] / jnp.linalg.norm(q[:, 3:], axis=-1, keepdims=True)
  return q[:, :3], rigid.quat_to_mat(quat)


def write_part_poses(tables, qpos, qvel, pos, rot, mask):
  """qpos, qvel with the parts in `mask` moved to (pos, rot) and at rest."""
  quat = rigid.mat_to_quat(rot)
  new = jnp.concatenate([pos, quat], axis=-1)
  qpos = qpos.at[tables.part_qpos].set(jnp.where(mask[:, None], new, qpos[tables.part_qpos]))
  qvel = qvel.at[tables.part_dof].set(jnp.where(mask[:, None], 0.0, qvel[tables.part_dof]))
  return qpos, qvel


def complete(state):
  """Whether every part is in one group."""
  return jnp.all(state.group == state.group[0])
