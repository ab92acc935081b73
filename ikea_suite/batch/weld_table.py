"""The batched task's welds: one per (candidate connector pair, allowed twist), fixed pose.

MJX keeps `eq_data` (a weld's relative pose) in the model, shared by every
world; only `eq_active` is per world. Connect snaps the moving group so the
two connector frames coincide exactly at one allowed twist, so the relative
pose of the two parts is known before the episode: it is declared here, and
connect switches that weld on in its world.

Pairs whose connectors allow any twist get `ANY_TWIST_STEPS` welds, one per
quantum, and connect snaps to the nearest quantum (the CPU task keeps the
measured twist); the snap then turns the moving group by at most half a
quantum about the connector's up axis.
"""

import dataclasses

import numpy as np

from ikea_suite import geometry

ANY_TWIST_STEPS = 24   # 15 degree quanta for any-twist connectors: snaps turn <= 7.5 degrees


@dataclasses.dataclass(frozen=True)
class WeldTable:
  """Per candidate pair k and twist slot t: the twist angle and the weld that holds it.

  Attributes:
    twist_angles: (pairs, width) radians; for any-twist pairs the quanta.
    twist_valid: (pairs, width) bool, which slots exist.
    weld_of: (pairs, width) index into the welds below, -1 for missing slots.
    body1, body2: (welds,) part indices, body1 < body2, as the CPU task orders them.
    relpos: (welds, 3) body2's position in body1's frame.
    relquat: (welds, 4) body2's orientation in body1's frame (w, x, y, z).
  """
  twist_angles: np.ndarray
  twist_valid: np.ndarray
  weld_of: np.ndarray
  body1: np.ndarray
  body2: np.ndarray
  relpos: np.ndarray
  relquat: np.ndarray

  @property
  def num_welds(self):
    return len(self.body1)


def relative_pose(local_pos_a, local_rot_a, local_pos_b, local_rot_b, twist):
  """Pose of part b in part a's frame when connector b sits on connector a turned by
  `twist` (radians about a's up): R_b = R_a L_a Rz(twist) L_b^T, and the frames meet."""
  rot = local_rot_a @ geometry.rot_z(twist) @ local_rot_b.T
  return local_pos_a - rot @ local_pos_b, rot


def build(table):
  """The WeldTable of a `props.connector_table.ConnectorTable`.

  Args:
    table: the furniture's connector table (candidate pairs and their twists).

  Returns:
    A WeldTable with one weld per (pair, allowed twist).
  """
  quanta = np.arange(ANY_TWIST_STEPS) * (2 * np.pi / ANY_TWIST_STEPS)
  width = max(table.twist_angles.shape[1], ANY_TWIST_STEPS if table.any_twist.any() else 1)
  num_pairs = table.num_pairs
  angles = np.zeros((num_pairs, width))
  valid = np.zeros((num_pairs, width), dtype=bool)
  weld_of = np.full((num_pairs, width), -1)
  body1, body2, relpos, relquat = [], [], [], []
  for k in range(num_pairs):
    twists = quanta if table.any_twist[k] else table.twist_angles[k][table.twist_valid[k]]
    con_a, con_b = table.pair_a[k], table.pair_b[k]
    part_a, part_b = int(table.part[con_a]), int(table.part[con_b])
    for t, twist in enumerate(twists):
      pos, rot = relative_pose(table.local_pos[con_a], table.local_rot[con_a],
                               table.local_pos[con_b], table.local_rot[con_b], twist)
      if part_a > part_b:   # the CPU task's welds run from the lower part index
        pos, rot = -rot.T @ pos, rot.T
      angles[k, t], valid[k, t], weld_of[k, t] = twist, True, len(body1)
      body1.append(min(part_a, part_b))
      body2.append(max(part_a, part_b))
      relpos.append(pos)
      relquat.append(geometry.mat_to_quat(rot))
  return WeldTable(angles, valid, weld_of, np.array(body1, dtype=int), np.array(body2, dtype=int),
                   np.array(relpos).reshape(-1, 3), np.array(relquat).reshape(-1, 4))
