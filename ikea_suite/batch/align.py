"""The alignment test of `tasks/alignment.py` (paper eqs. 1-4) in jax, for one world.

Same formulas, same symmetric forward measure, so a pair is attachable here
exactly when it is on the CPU (up to float32 rounding near the thresholds;
tests/test_batch_alignment.py checks agreement on thousands of pose pairs).
The extra output is the twist slot connect snaps to: the best allowed twist,
or for any-twist pairs the nearest quantum of `weld_table.ANY_TWIST_STEPS`.
"""

import typing

import jax.numpy as jnp
import numpy as np

from ikea_suite.batch import rigid


class Alignment(typing.NamedTuple):
  """Per candidate pair: distance (m), up cosine, best forward cosine, measured or allowed
  twist (radians), and the WeldTable slot connect would weld at."""
  distance: jnp.ndarray
  up_cos: jnp.ndarray
  forward_cos: jnp.ndarray
  twist: jnp.ndarray
  slot: jnp.ndarray

  def attachable(self, thresholds):
    """Mask of pairs within `thresholds` (a tasks.alignment.Thresholds)."""
    return ((self.distance < thresholds.distance) & (self.up_cos > thresholds.up_cos)
            & (self.forward_cos > thresholds.forward_cos))


class PairTables(typing.NamedTuple):
  """The connector and pair arrays the test reads, as device constants."""
  part: jnp.ndarray          # (c,) part of each connector
  local_pos: jnp.ndarray     # (c, 3)
  local_rot: jnp.ndarray     # (c, 3, 3)
  pair_a: jnp.ndarray        # (k,)
  pair_b: jnp.ndarray
  twist_cos: jnp.ndarray     # (k, w) allowed twists (CPU table), padded
  twist_sin: jnp.ndarray
  twist_valid: jnp.ndarray
  any_twist: jnp.ndarray     # (k,)
  slot_angles: jnp.ndarray   # (k, s) weld slots' twists (any-twist: quanta)
  slot_valid: jnp.ndarray


def pair_tables(table, welds):
  """PairTables from a ConnectorTable and its WeldTable."""
  f32 = lambda x: rigid.real(np.asarray(x))
  return PairTables(
      part=jnp.asarray(table.part, dtype=jnp.int32), local_pos=f32(table.local_pos),
      local_rot=f32(table.local_rot), pair_a=jnp.asarray(table.pair_a, dtype=jnp.int32),
      pair_b=jnp.asarray(table.pair_b, dtype=jnp.int32), twist_cos=f32(table.twist_cos),
      twist_sin=f32(table.twist_sin), twist_valid=jnp.asarray(table.twist_valid),
      any_twist=jnp.asarray(table.any_twist), slot_angles=f32(welds.twist_angles),
      slot_valid=jnp.asarray(welds.twist_valid))


def connector_frames(tables, part_pos, part_rot):
  """World positions (c, 3) and rotations (c, 3, 3) of every connector."""
  rot = part_rot[tables.part]
  return part_pos[tables.part] + rigid.apply(rot, tables.local_pos), rot @ tables.local_rot


def _unit(v):
  return v / jnp.maximum(jnp.linalg.norm(v, axis=-1, keepdims=True), 1e-9)


def align_pairs(tables, pos, rot):
  """Scores every candidate pair given connector world frames.

  Args:
    tables: PairTables.
    pos: (c, 3) connector positions.
    rot: (c, 3, 3) connector rotations (columns: forward, left, up).

  Returns:
    An Alignment over the k candidate pairs.
  """
  a, b = tables.pair_a, tables.pair_b
  rot_a, rot_b = rot[a], rot[b]
  distance = jnp.linalg.norm(pos[a] - pos[b], axis=-1)
  up_a, up_b = rot_a[:, :, 2], rot_b[:, :, 2]
  up_cos = jnp.sum(up_a * up_b, -1)
  up = _unit(up_a + up_b)
  fwd_a, fwd_b = rot_a[:, :, 0], rot_b[:, :, 0]
  fwd_a = _unit(fwd_a - up * jnp.sum(fwd_a * up, -1, keepdims=True))
  fwd_b = _unit(fwd_b - up * jnp.sum(fwd_b * up, -1, keepdims=True))
  c = jnp.sum(fwd_a * fwd_b, -1)
  s = jnp.sum(jnp.cross(up, fwd_a) * fwd_b, -1)
  per_twist = tables.twist_cos * c[:, None] + tables.twist_sin * s[:, None]
  per_twist = jnp.where(tables.twist_valid, per_twist, -jnp.inf)
  best = jnp.max(per_twist, axis=1)
  measured = jnp.arctan2(s, c)
  # Slot: the allowed twist closest to the measured one (for discrete twists this is the
  # argmax of the forward cosine above; for any-twist pairs the nearest quantum).
  slot_score = jnp.cos(tables.slot_angles - measured[:, None])
  slot = jnp.argmax(jnp.where(tables.slot_valid, slot_score, -jnp.inf), axis=1)
  slot_twist = jnp.take_along_axis(tables.slot_angles, slot[:, None], axis=1)[:, 0]
  forward_cos = jnp.where(tables.any_twist, 1.0, best)
  twist = jnp.where(tables.any_twist, measured, slot_twist)
  return Alignment(distance, up_cos, forward_cos, twist, slot.astype(jnp.int32))
