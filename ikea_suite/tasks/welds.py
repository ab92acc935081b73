"""Inactive weld equalities between parts that can mate, declared once at build time."""

import numpy as np

from ikea_suite import geometry

# Stiff enough that a welded table does not sag visibly, soft enough for 2 ms steps.
WELD_SOLREF = (0.01, 1.0)


class PartWelds:
  """One weld per pair of parts that share a mating connector pair."""

  def __init__(self, arena, furniture):
    frames = furniture.part_frames
    self._pairs = furniture.spec.mating_part_pairs()
    self._elements = {(i, j): arena.mjcf_model.equality.add(
        "weld", name=f"part_weld_{i}_{j}", body1=frames[i], body2=frames[j], active=False,
        solref=WELD_SOLREF) for i, j in self._pairs}
    self._ids = {}

  def after_compile(self, physics):
    self._ids = {pair: physics.bind(el).element_id for pair, el in self._elements.items()}
    self._all_ids = np.array(list(self._ids.values()), dtype=int)

  def reset(self, physics):
    physics.data.eq_active[self._all_ids] = 0

  def activate(self, physics, part_i, part_j, pos_i, rot_i, pos_j, rot_j):
    """Welds two parts at their current relative pose (relpose = body2 in body1's frame)."""
    if part_i > part_j:
      part_i, part_j, pos_i, rot_i, pos_j, rot_j = part_j, part_i, pos_j, rot_j, pos_i, rot_i
    weld = self._ids[(part_i, part_j)]
    data = physics.model.eq_data[weld]
    data[:3] = 0.0
    data[3:6] = rot_i.T @ (pos_j - pos_i)
    data[6:10] = geometry.mat_to_quat(rot_i.T @ rot_j)
    physics.data.eq_active[weld] = 1

  def active_pairs(self, physics):
    return [pair for pair, i in self._ids.items() if physics.data.eq_active[i]]
