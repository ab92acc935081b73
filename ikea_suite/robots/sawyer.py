"""Rethink Sawyer (7 DoF) with the Rethink electric parallel gripper, built from fact sheets.

Base on the floor at (-0.55, 0, 0), facing +x (towards the assembly area at
the origin). Colours follow the real robot: red links, white and dark trim.
"""


from ikea_suite import config
from ikea_suite.robots import grippers
from ikea_suite.robots import manipulator
from ikea_suite.robots import robot_facts

JOINTS = tuple(f"right_j{i}" for i in range(7))
# A ready pose with the tool above the floor in front of the base; refined by IK.
_SEED = (0.0, -1.18, 0.0, 2.18, 0.0, 0.57, 3.3161)


class Sawyer(manipulator.Manipulator):
  """One 7-DoF arm; actions: see control_modes (7 per arm in task space, 8 in joint modes)."""

  DEFAULT_NAME = "sawyer"
  CONFIG = config.SawyerConfig   # base_pos: the base's default position
  REACH = 0.85
  # Shoulder forward, elbow up (limits: j0 +-3.05, j1 -3.81..2.27, j2 +-3.04, j3 +-3.04).
  # Measured over 150 random tool-down poses in the work sector, IK from home solves 108
  # inside these ranges and 107 with the full ones. In a stool episode the unbounded arm ended flipped (j0 -3.05, j1 -2.82: reaching over its
  # shoulder) and could reach no loose part; bounding j0 at +-2.6 and j1 at -3.0 still
  # let it flip there, so j1 stays above -2.3.
  IK_WORKING_RANGES = {0: (-2.2, 2.2), 1: (-2.3, 0.5), 2: (-1.2, 1.2), 3: (0.0, 2.9)}

  def _build_body(self, name):
    root, elements, limits = robot_facts.build_model(name, "sawyer", root="right_arm_base_link")
    # Fingers in the gripper's narrowest slot: they close on the thin walls, stretchers and
    # racked panels of boxes, benches and desks (grippers.RETHINK_SLOT_1).
    return root, [manipulator.single_arm(
        root, elements, limits, JOINTS, grippers.RETHINK_SLOT_1, _SEED, home_tcp=(0.45, 0.0, 0.35),
        workspace_box=[[-0.5, -0.9, 0.005], [1.0, 0.9, 1.0]])]
