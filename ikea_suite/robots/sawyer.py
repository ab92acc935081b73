"""Rethink Sawyer (7 DoF) with the Rethink electric parallel gripper, built from fact sheets.

Base on the floor at (-0.55, 0, 0), facing +x (towards the assembly area at
the origin). Colours follow the real robot: red links, white and dark trim.
"""

import numpy as np
from dm_control import mjcf

from ikea_suite.robots import grippers
from ikea_suite.robots import manipulator
from ikea_suite.robots import robot_facts

JOINTS = tuple(f"right_j{i}" for i in range(7))
# A ready pose with the tool above the floor in front of the base; refined by IK.
_SEED = (0.0, -1.18, 0.0, 2.18, 0.0, 0.57, 3.3161)


class Sawyer(manipulator.Manipulator):
  """One 7-DoF arm; actions: see control_modes (7 per arm in task space, 8 in joint modes)."""

  DEFAULT_NAME = "sawyer"
  BASE_POS = (-0.55, 0.0, 0.0)
  REACH = 0.85

  def _build_body(self, name):
    facts = robot_facts.load("sawyer")
    root = mjcf.RootElement(model=name)
    root.compiler.angle = "radian"   # the fact sheets are in radians
    elements = robot_facts.add_tree(root.worldbody, facts, skip=("base",),
                                    root="right_arm_base_link")
    gripper = grippers.build(elements["right_hand"], grippers.RETHINK, prefix="right_")
    limits = robot_facts.actuator_limits(facts)
    arm = manipulator.Arm(
        prefix="", joints=[root.find("joint", j) for j in JOINTS],
        torque_limits=np.array([limits[j][1] for j in JOINTS]), gripper=gripper,
        camera=root.find("camera", "eye_in_hand"), seed=np.array(_SEED),
        home_tcp=np.array([0.45, 0.0, 0.35]),
        workspace=np.array([[-0.5, -0.9, 0.005], [1.0, 0.9, 1.0]]))
    return root, [arm]
