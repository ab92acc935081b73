"""Where the task lays the parts for a fixed-base arm robot: its placement figures."""

import numpy as np

from ikea_suite.robots import base


class WorkArea:
  """The band and sector around the base that an arm robot's parts lie in.

  A mixin for robots that set `_base_pos` (3,), `_base_rot` (3, 3) and `_arms`; a robot
  overrides the figures its own reach calls for (robots/baxter.py).
  """

  REACH = 0.85                   # metres from the base where parts are placed
  # Metres from the base inside which no part is placed: an arm pointing down cannot
  # reach right beside itself.
  PLACEMENT_INNER = 0.55
  # Metres out to the centre of the part built onto (more for a wide one): a held part mated
  # nearer the base folds the elbow into it (measured with the Sawyer at 0.4 m).
  ROOT_DISTANCE = 0.45
  # Parts lie within this angle either side of the base's heading (rad).
  PLACEMENT_SECTOR = np.radians(110)
  # (bearing, metres): parts beyond that bearing may lie out that far (base.ReachZone).
  PLACEMENT_SIDE_REACH = None
  # The body's footprint parts keep clear of (base.ReachZone.body); None: an arm's pedestal
  # lies well within PLACEMENT_INNER.
  BODY_FOOTPRINT = None

  @property
  def reach_zone(self):
    """base.ReachZone: where the task may put parts for this arm (tasks/arm_placement.py)."""
    return base.ReachZone(self._base_pos[:2].copy(), self._base_rot.copy(), float(self.REACH),
                          float(self.PLACEMENT_SECTOR), float(self.PLACEMENT_INNER),
                          float(self.ROOT_DISTANCE), len(self._arms), self.PLACEMENT_SIDE_REACH,
                          self.BODY_FOOTPRINT)
