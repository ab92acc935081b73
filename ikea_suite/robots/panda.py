"""Franka Emika Panda (7 DoF) with the Franka hand, built from fact sheets.

Base on the floor at (-0.5, 0, 0), facing +x. White links, dark joints. The
sheet has no collision primitives for the links, so each link collides as
the box bounding its visual mesh.
"""

import numpy as np

from ikea_suite import config
from ikea_suite.robots import grippers
from ikea_suite.robots import manipulator
from ikea_suite.robots import robot_facts

JOINTS = tuple(f"joint{i}" for i in range(1, 8))
_SEED = (0.0, np.pi / 16, 0.0, -np.pi / 2 - np.pi / 3, 0.0, np.pi - 0.2, np.pi / 4)


class Panda(manipulator.Manipulator):
  """One 7-DoF arm; actions: see control_modes."""

  DEFAULT_NAME = "panda"
  CONFIG = config.PandaConfig   # base_pos: the base's default position
  # Tool down 3 cm above the floor the hand reaches 0.8 m only fully stretched (6 mm short);
  # a 0.72 m band spilled a quarter of the full-size Lack's parts outwards, past reach.
  REACH = 0.8
  # Wrist not flipped, elbow not straight. Failed episodes ended with joint
  # 4 at +-2.9 and joint 5 at -0.02 or 3.75, trapped at the limits beside the part; the
  # completed ones stayed within these ranges.
  IK_WORKING_RANGES = {2: (-2.1, 2.1), 3: (-3.07, -0.5), 4: (-2.0, 2.0), 5: (0.3, 3.3)}

  def _build_body(self, name):
    root, elements, limits = robot_facts.build_model(name, "panda", root="link0")
    return root, [manipulator.single_arm(
        root, elements, limits, JOINTS, grippers.FRANKA_HAND, _SEED, home_tcp=(0.45, 0.0, 0.35),
        workspace_box=[[-0.45, -0.8, 0.005], [0.9, 0.8, 0.9]])]
