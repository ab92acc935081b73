"""Collision filtering so that parts joined into one group stop colliding with each other.

Part geoms of group g get contype = bit_g and conaffinity = ALL & ~bit_g, with
bit_g = 1 << (g + 1). Two geoms collide when (contype1 & conaffinity2) or
(contype2 & conaffinity1) is non-zero, so parts in one group never collide,
parts in different groups do, and bit 0 in every conaffinity keeps collisions
with the floor and robots (MuJoCo's default contype = conaffinity = 1).
"""

import numpy as np

_ALL = (1 << 31) - 1


class CollisionGroups:

  def __init__(self, num_parts):
    self._num_parts = num_parts

  def after_compile(self, furniture):
    self._geoms, self._geom_part = furniture.collision_geoms

  def reset(self, physics):
    self.assign(physics, np.arange(self._num_parts))

  def assign(self, physics, group_of_part):
    """Writes collision bits from a group label per part (labels in 0..29)."""
    bits = np.left_shift(1, np.asarray(group_of_part)[self._geom_part] + 1)
    physics.model.geom_contype[self._geoms] = bits
    physics.model.geom_conaffinity[self._geoms] = _ALL & ~bits
