"""Rethink Baxter: two 7-DoF arms on a torso, a Rethink electric gripper on each (fingers
in slot 1).

Torso on the floor at (-0.6, 0, 0.06) facing +x. The action covers both
arms, right arm first: each arm's entries are prefixed `right_` / `left_`.
"""

import numpy as np

from ikea_suite import config
from ikea_suite.robots import grippers
from ikea_suite.robots import manipulator
from ikea_suite.robots import robot_facts

_JOINT_SUFFIXES = ("s0", "s1", "e0", "e1", "w0", "w1", "w2")
_SEEDS = {"right": (0.535, -0.093, 0.038, 0.166, 0.643, 1.960, -1.297),
          "left": (-0.518, -0.026, -0.076, 0.175, -0.748, 1.641, -0.158)}


class Baxter(manipulator.Manipulator):
  """Two arms; actions: right arm's entries then left arm's (see control_modes)."""

  DEFAULT_NAME = "baxter"
  CONFIG = config.BaxterConfig   # base_pos: the base's default position
  # The floor both hands reach tool down, from the IK (tool 1.5 cm over the floor, both
  # arms): straight ahead to 0.80-0.85 m, at 40 degrees and wider to 0.95; beside the
  # torso not within 0.55 m. With parts placed from 0.55 to 0.95 m, in 25 of 80 failed
  # episodes a part lay where it was placed outside this band, the hand stalling over it
  # for the rest of the episode.
  REACH = 0.82
  PLACEMENT_INNER = 0.62
  # Tool down 3 cm over the floor, the IK from home keeps every joint 0.15 rad inside its
  # limits out to 85 degrees from the heading across the band; at 100 degrees 0.72 m out
  # a joint meets its limit, at 110 the hand stops 2-4 cm short. With the sector at the
  # arms' 110 degrees, a leg drawn 105 degrees out stalled the descent over it all
  # episode, on every model.
  PLACEMENT_SECTOR = np.radians(85)
  # Out to 0.92 m from 25 degrees on (same IK: misses under 4 mm, joints 0.17 rad inside
  # their limits). Within 85 degrees and 0.82 m, a wide table top left one half room for
  # a single leg: the next spilled out of reach in 31 of 40 episodes of w120_white.
  PLACEMENT_SIDE_REACH = (np.radians(25), 0.92)
  # Its table tops' mates 0.3 m from the torso left the hands cramped there, and a part
  # dropped near them lay out of reach; 0.55 m out: 64 of 90 episodes over 9 models
  # against 53 (tables 4 -> 6-8 of 10, the round bar stool 10 -> 7).
  ROOT_DISTANCE = 0.55

  def _build_body(self, name):
    root, elements, limits = robot_facts.build_model(
        name, "baxter", root="fixed_base_link", pos=[0, 0, 0])
    arms = []
    for side, y in (("right", -1.0), ("left", 1.0)):
      joints = [f"{side}_{s}" for s in _JOINT_SUFFIXES]
      # Fingers in the gripper's narrowest slot, as on the Sawyer (grippers.RETHINK_SLOT_1):
      # in slot 2 the closed fingertips stay 14 mm apart, and box walls, bench ends,
      # stretchers and panels 4-15 mm thick slipped out as soon as they were lifted. At the
      # half scale it works at, every loose part of the stools and tables it assembles
      # (17.5-25 mm legs) fits slot 1's 60 mm opening with room to spare.
      gripper = grippers.build(elements[f"{side}_hand"], grippers.RETHINK_SLOT_1,
                               prefix=f"{side}_")
      arms.append(manipulator.Arm(
          prefix=f"{side}_", joints=[root.find("joint", j) for j in joints],
          torque_limits=np.array([limits[j][1] for j in joints]), gripper=gripper,
          camera=root.find("camera", f"{side}_eye_in_hand"), seed=np.array(_SEEDS[side]),
          home_tcp=np.array([0.6, 0.3 * y, 0.3]),
          workspace=np.array([[-0.4, min(-0.2 * y, 1.1 * y), -0.055],
                              [1.1, max(-0.2 * y, 1.1 * y), 1.0]])))
    return root, arms
