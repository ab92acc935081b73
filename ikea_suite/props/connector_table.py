"""Connectors of one furniture as flat arrays, and the candidate mating pairs among them."""

import numpy as np

from ikea_suite import geometry
from ikea_suite.assembly import mating


class ConnectorTable:
  """Part-frame connector geometry and the precomputed list of mating pairs.

  Pairs are stored once (a < b) with their allowed twists padded into
  fixed-width arrays, so one numpy expression checks all of them.
  """

  def __init__(self, spec):
    part_index = {p.name: i for i, p in enumerate(spec.parts)}
    self.names = [c.name for c in spec.connectors]
    self.types = [c.type for c in spec.connectors]
    self.part = np.array([part_index[c.part] for c in spec.connectors])
    self.local_pos = np.array([c.pos for c in spec.connectors])
    self.local_rot = np.array([c.rot for c in spec.connectors])
    pairs = [(a, b) for a, ca in enumerate(spec.connectors) for b, cb in enumerate(spec.connectors)
             if a < b and mating.types_mate(ca, cb)]
    self.pair_a = np.array([a for a, _ in pairs], dtype=int)
    self.pair_b = np.array([b for _, b in pairs], dtype=int)
    twists = [spec.connectors[a].twists for a, _ in pairs]
    width = max([len(t) for t in twists] + [1])
    angles = np.zeros((len(pairs), width))
    self.twist_valid = np.zeros((len(pairs), width), dtype=bool)
    for i, t in enumerate(twists):
      angles[i, :len(t)] = t
      self.twist_valid[i, :len(t)] = True
    self.twist_angles = angles
    self.twist_cos, self.twist_sin = np.cos(angles), np.sin(angles)
    self.any_twist = np.array([not t for t in twists], dtype=bool)

  def __len__(self):
    return len(self.names)

  @property
  def num_pairs(self):
    return len(self.pair_a)

  def mated_frame(self, pair, moving_con, cpos, crot, twist):
    """World frame (position, rotation) connector `moving_con` of candidate `pair` takes to
    mate at `twist`, given all connectors' world frames (cpos, crot).

    Mated means R_b = R_a Rz(twist): the moving frame is R_a Rz(twist) when it is b and
    R_b Rz(-twist) when it is a, at the fixed connector's position.
    """
    moving_is_b = moving_con == self.pair_b[pair]
    fixed_con = self.pair_a[pair] if moving_is_b else self.pair_b[pair]
    return cpos[fixed_con], crot[fixed_con] @ geometry.rot_z(twist if moving_is_b else -twist)

  def world_frames(self, part_pos, part_rot):
    """World positions (c, 3) and rotations (c, 3, 3) of every connector."""
    rot = part_rot[self.part]
    pos = part_pos[self.part] + np.einsum("cij,cj->ci", rot, self.local_pos)
    return pos, rot @ self.local_rot
