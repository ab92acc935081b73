"""What an arm robot's `_build_body` returns per arm: its joints, gripper, camera and home."""

import dataclasses

import numpy as np

from ikea_suite.robots import grippers


@dataclasses.dataclass
class Arm:
  prefix: str                 # action-name prefix: "" or "right_" / "left_"
  joints: list                # joint elements, base to wrist
  torque_limits: np.ndarray   # N m per joint
  gripper: grippers.GripperParts
  camera: object              # wrist camera element
  seed: np.ndarray            # joint angles near the home pose, refined by IK
  home_tcp: np.ndarray        # home tool-centre point in the base frame
  workspace: np.ndarray       # (2, 3) box in the base frame the tool is kept in
  impedance_target: object = None   # the target site of impedance mode (arm_actuators)


def single_arm(root, elements, limits, joints, gripper_spec, seed, home_tcp, workspace_box):
  """The one Arm of a single-arm robot whose joints, hand and camera follow the sheets' names."""
  gripper = grippers.build(elements["right_hand"], gripper_spec, prefix="right_")
  return Arm(
      prefix="", joints=[root.find("joint", j) for j in joints],
      torque_limits=np.array([limits[j][1] for j in joints]), gripper=gripper,
      camera=root.find("camera", "eye_in_hand"), seed=np.array(seed),
      home_tcp=np.array(home_tcp), workspace=np.array(workspace_box))
