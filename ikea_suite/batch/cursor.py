"""The Cursor agent's action in one world, as `robots/cursor.py` does it on the CPU.

Per cursor: move (m/s at 1), rotate about world axes (rad/s at 1), select.
Select on grabs the part whose collision box (plus the grasp margin)
encloses the cursor, unless the other cursor holds that assembly; select off
releases. While held, the part's target pose (cursor pose times the grip
offset) is written to the cursor's mocap body, and the grip weld from that
body to the part is on. Cursors act in index order, as on the CPU.
"""

import typing

import jax.numpy as jnp

from ikea_suite.batch import rigid
from ikea_suite.batch import task_state

PER_CURSOR = 7


class CursorSettings(typing.NamedTuple):
  """The Cursor's options (see `robots.cursor.Cursor`): speeds, grasp margin, workspace."""
  move_speed: float
  rotate_speed: float
  grasp_margin: float
  workspace_low: tuple
  workspace_high: tuple


def enclosed_part(tables, part_pos, part_rot, point, margin):
  """The part whose collision box (plus `margin`) holds `point`, nearest centre first; -1."""
  rot = part_rot[tables.geom_part] @ tables.geom_rot
  origin = part_pos[tables.geom_part] + rigid.apply(part_rot[tables.geom_part], tables.geom_pos)
  local = jnp.einsum("gji,gj->gi", rot, point - origin)
  offset = jnp.abs(local - tables.geom_center)
  inside = jnp.all(offset <= tables.geom_half + margin, axis=1)
  score = jnp.where(inside, jnp.sum(offset ** 2, axis=1), jnp.inf)
  best = jnp.argmin(score)
  return jnp.where(inside[best], tables.geom_part[best], -1)


def grip_offset(cursor_pos, cursor_rot, part_pos, part_rot):
  """Part pose in the cursor frame."""
  return cursor_rot.T @ (part_pos - cursor_pos), cursor_rot.T @ part_rot


def act(settings, tables, dt, state, action, qpos, eq_active, mocap_pos, mocap_quat):
  """Applies the cursors' 14 action entries (already clipped to [-1, 1]).

  Args:
    settings: CursorSettings.
    tables: the furniture's Tables.
    dt: control timestep, s.
    state: TaskState.
    action: (14,) both cursors' actions.
    qpos, eq_active, mocap_pos, mocap_quat: the world's MuJoCo state.

  Returns:
    (state, eq_active, mocap_pos, mocap_quat) after the action.
  """
  action = action.reshape(2, PER_CURSOR)
  part_pos, part_rot = task_state.part_poses(tables, qpos)
  positions = jnp.clip(state.cursor_pos + action[:, :3] * (settings.move_speed * dt),
                       jnp.asarray(settings.workspace_low), jnp.asarray(settings.workspace_high))
  turns = rigid.axis_angle_to_quat(action[:, 3:6] * (settings.rotate_speed * dt))
  quats = rigid.quat_mul(turns, state.cursor_quat)
  quats = quats / jnp.linalg.norm(quats, axis=-1, keepdims=True)
  held, grip_pos, grip_rot = state.held, state.grip_pos, state.grip_rot
  for i in range(2):
    rot = rigid.quat_to_mat(quats[i])
    selecting = action[i, 6] > 0
    current = held[i]
    part = enclosed_part(tables, part_pos, part_rot, positions[i], settings.grasp_margin)
    other = held[1 - i]
    taken = (other >= 0) & (state.group[jnp.maximum(part, 0)] == state.group[jnp.maximum(other, 0)])
    grab = selecting & (current < 0) & (part >= 0) & ~taken
    release = ~selecting & (current >= 0)
    safe_part = jnp.maximum(part, 0)
    offset_pos, offset_rot = grip_offset(positions[i], rot, part_pos[safe_part],
                                         part_rot[safe_part])
    grip_pos = grip_pos.at[i].set(jnp.where(grab, offset_pos, grip_pos[i]))
    grip_rot = grip_rot.at[i].set(jnp.where(grab, offset_rot, grip_rot[i]))
    eq_active = eq_active.at[tables.grip_eq[i, safe_part]].set(
        jnp.where(grab, True, eq_active[tables.grip_eq[i, safe_part]]))
    old = jnp.maximum(current, 0)
    eq_active = eq_active.at[tables.grip_eq[i, old]].set(
        jnp.where(release, False, eq_active[tables.grip_eq[i, old]]))
    held = held.at[i].set(jnp.where(grab, part, jnp.where(release, -1, current)))
  state = state._replace(cursor_pos=positions, cursor_quat=quats, held=held, grip_pos=grip_pos,
                         grip_rot=grip_rot)
  mocap_pos, mocap_quat = grip_targets(state, mocap_pos, mocap_quat)
  return state, eq_active, mocap_pos, mocap_quat


def grip_targets(state, mocap_pos, mocap_quat):
  """Mocap poses at the held parts' targets (cursor pose times grip offset); idle cursors'
  mocap bodies stay where they are."""
  rot = rigid.quat_to_mat(state.cursor_quat)
  target_pos = state.cursor_pos + rigid.apply(rot, state.grip_pos)
  target_quat = rigid.mat_to_quat(rot @ state.grip_rot)
  holding = (state.held >= 0)[:, None]
  return (jnp.where(holding, target_pos, mocap_pos),
          jnp.where(holding, target_quat, mocap_quat))


def on_parts_moved(state, part_pos, part_rot, moved):
  """After a snap moved the parts in `moved` (bool, per part): grips on them are re-taken at
  the new pose, and if both cursors now hold one assembly the first whose part moved lets go
  (as the CPU cursor does). Returns (state, released: bool per cursor)."""
  rot = rigid.quat_to_mat(state.cursor_quat)
  safe = jnp.maximum(state.held, 0)
  holder = (state.held >= 0) & moved[safe]
  new_pos = jnp.einsum("cji,cj->ci", rot, part_pos[safe] - state.cursor_pos)
  new_rot = jnp.swapaxes(rot, 1, 2) @ part_rot[safe]
  grip_pos = jnp.where(holder[:, None], new_pos, state.grip_pos)
  grip_rot = jnp.where(holder[:, None, None], new_rot, state.grip_rot)
  both = (state.held >= 0).all() & (state.group[safe[0]] == state.group[safe[1]])
  first = jnp.where(holder[0], 0, 1)
  released = both & holder.any() & (jnp.arange(2) == first)
  held = jnp.where(released, -1, state.held)
  return state._replace(held=held, grip_pos=grip_pos, grip_rot=grip_rot), released
