"""Inactive weld equalities between parts that can mate, declared once at build time."""

import numpy as np

from ikea_suite import geometry
from ikea_suite import physics_settings


class PartWelds:
  """One weld per pair of parts that share a mating connector pair.

  A weld holds its two parts at the relative pose written when it is
  activated; several connector pairs between the same two parts share it.
  """

  def __init__(self, arena, furniture):
    frames = furniture.part_frames
    self._pairs = furniture.spec.mating_part_pairs()
    self._elements = {(i, j): arena.mjcf_model.equality.add(
        "weld", name=f"part_weld_{i}_{j}", body1=frames[i], body2=frames[j], active=False,
        solref=physics_settings.WELD_SOLREF, solimp=physics_settings.WELD_SOLIMP,
        torquescale=physics_settings.WELD_TORQUESCALE) for i, j in self._pairs}
    self._ids = {}

  def after_compile(self, physics):
    self._ids = {pair: physics.bind(el).element_id for pair, el in self._elements.items()}
    self._all_ids = np.array(list(self._ids.values()), dtype=int)

  def reset(self, physics):
    physics.data.eq_active[self._all_ids] = 0

  def is_active(self, physics, part_i, part_j):
    return bool(physics.data.eq_active[self._ids[tuple(sorted((part_i, part_j)))]])

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
    """Sorted (i, j) part pairs whose weld is on."""
    return sorted(pair for pair, i in self._ids.items() if physics.data.eq_active[i])

  def relative_poses(self, physics):
    """{(i, j): (7,) pose of part j in part i's frame, position (m) then quaternion (w x y z)}
    held by each weld that is on."""
    return {pair: physics.model.eq_data[self._ids[pair]][3:10].copy()
            for pair in self.active_pairs(physics)}
