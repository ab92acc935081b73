"""Device constants of one furniture's batched task, gathered once from its BatchModel.

Everything a world's step indexes with (connector pairs, weld ids, qpos
addresses, grab boxes, the planner's order) as jax arrays, so the step is
pure array code with no Python data structures.
"""

import typing

import jax.numpy as jnp
import numpy as np

from ikea_suite.assembly import sequence
from ikea_suite.batch import align
from ikea_suite.batch import rigid
from ikea_suite.tasks import placement
from ikea_suite.tasks import planner


class Tables(typing.NamedTuple):
  """Index and geometry tables; all jax arrays (see BatchModel for their meaning)."""
  pairs: align.PairTables
  slot_eq: jnp.ndarray        # (k, s) equality id of pair k welded at twist slot s, -1 if none
  part_qpos: jnp.ndarray      # (p, 7) qpos indices: position then quaternion
  part_dof: jnp.ndarray       # (p, 6) dof indices
  grip_eq: jnp.ndarray        # (cursors, p) equality ids
  geom_part: jnp.ndarray      # (g,)
  geom_pos: jnp.ndarray       # (g, 3) in the part frame
  geom_rot: jnp.ndarray       # (g, 3, 3)
  geom_center: jnp.ndarray    # (g, 3) box centre in the geom frame
  geom_half: jnp.ndarray      # (g, 3) box half size
  design_pair: jnp.ndarray    # (k,) bool: the pair coincides in the assembled design
  order: jnp.ndarray          # (p,) buildable part order, root first


def assembly_order(spec):
  """The CPU task's part order for next_pair: root, then the buildable sequence."""
  return sequence.assembly_order(spec, planner.root_part(spec))


def build(batch_model):
  """Tables from a `model.BatchModel`."""
  bm = batch_model
  welds = bm.welds
  slot_eq = np.where(welds.weld_of >= 0, bm.weld_eq[np.maximum(welds.weld_of, 0)], -1)
  design = np.zeros(bm.table.num_pairs, dtype=bool)
  design[placement.design_pairs(bm.spec, bm.table)] = True
  f32 = lambda x: rigid.real(np.asarray(x))
  i32 = lambda x: jnp.asarray(np.asarray(x), dtype=jnp.int32)
  return Tables(
      pairs=align.pair_tables(bm.table, welds), slot_eq=i32(slot_eq),
      part_qpos=i32(bm.part_qpos[:, None] + np.arange(7)),
      part_dof=i32(bm.part_dof[:, None] + np.arange(6)), grip_eq=i32(bm.grip_eq),
      geom_part=i32(bm.geom_part), geom_pos=f32(bm.geom_pos), geom_rot=f32(bm.geom_rot),
      geom_center=f32(bm.geom_center), geom_half=f32(bm.geom_half),
      design_pair=jnp.asarray(design), order=i32(assembly_order(bm.spec)))
