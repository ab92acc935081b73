"""Kinova Jaco (6 DoF) with its three-finger hand, from dm_control.entities.manipulators.kinova.

dm_control's velocity actuators are replaced by this suite's actuators for
the chosen control mode; the three fingers close together under
force-limited position actuators (gripper -1 open, +1 closed). Base on the
floor at (-0.45, 0, 0), facing +x.
"""

import numpy as np
from dm_control.entities.manipulators import kinova

from ikea_suite import config
from ikea_suite import physics_settings
from ikea_suite.robots import grippers
from ikea_suite.robots import manipulator
from ikea_suite.robots import robot_facts

JOINTS = tuple(f"joint_{i}" for i in range(1, 7))
# Kinova's peak torques (as in dm_control's JacoArm): large and small actuators.
_TORQUE_LIMITS = (30.5, 30.5, 30.5, 6.8, 6.8, 6.8)
_SEED = (np.pi, 3.5, 1.6, -0.45, 1.5, 0.2)
_FINGER_OPEN, _FINGER_CLOSED = 0.15, 1.35   # the hand's finger joint range
_FINGER_KP = 5.0
WRIST_CAMERA_TILT = 10.0   # degrees from the approach axis towards the fingers
# The KG-3's ~25 N grip comes from 1 N m per finger joint (kinova_hand.json, after dm_control).
_HAND_SHEET = "kinova_hand"
# Finger contacts as stiff as MuJoCo integrates stably (time constant twice the timestep,
# and the pads' impedance, physics_settings.PAD_SOLIMP), and taking precedence over the
# part's (geom priority). MuJoCo's contact softness scales with
# the effective mass, which at a finger is the light part's: with the default 20 ms
# contacts the 1 N m fingers sank 8-17 mm into a 24 g leg (the Lack's at scale 0.5), and
# the curved fingertips, that deep inside, pushed it down out of the hand.
_FINGER_SOLREF = physics_settings.HARD_SOLREF


class Jaco(manipulator.Manipulator):
  """One 6-DoF arm; actions: see control_modes (7 per arm in task space, 7 in joint modes)."""

  DEFAULT_NAME = "jaco"
  CONFIG = config.JacoConfig   # base_pos: the base's default position
  # Where parts may lie: the tool, pointing down, meets a part's centre on the floor to
  # 4 mm by IK out to 0.70 m ahead of the base and misses by 13 mm at 0.72 m (measured on
  # the compiled model, TCP at the pinch depth: the hand puts it 0.19 m past the wrist).
  # At 0.8, parts drawn 0.72-0.8 m out were never picked up.
  REACH = 0.7
  KP_PER_NM = 30.0   # the Jaco's heavy joint armature needs stiffer position gains

  def _build_body(self, name):
    arm_entity, hand_entity = kinova.JacoArm(name=name), kinova.JacoHand()
    for entity in (arm_entity, hand_entity):   # before attaching: frames have no gravcomp
      for body in entity.mjcf_model.worldbody.find_all("body"):
        body.gravcomp = 1.0
    arm_entity.attach(hand_entity, arm_entity.wrist_site)
    root = arm_entity.mjcf_model
    for actuator in list(arm_entity.actuators) + list(hand_entity.actuators):
      actuator.remove()
    hand = hand_entity.mjcf_model
    facts = grippers.grip_facts(_HAND_SHEET)
    finger_torque = float(robot_facts.load(_HAND_SHEET)["grip"]["finger_torque_nm"])
    for geom in hand.find_all("geom"):
      if geom.contype != 0 or geom.conaffinity != 0:
        geom.friction = (facts.friction, 0.05, 0.0001)
    grip, pinch = hand_entity.grip_site, hand_entity.pinch_site
    # The tool-centre point: on the hand's axis (through dm_control's grip site) at the
    # depth of its pinch site, where the curled fingertips meet (z along the approach).
    # The fingers hinge 4.4 cm behind the grip site and close in an arc: a 25 mm leg
    # (the Lack's at scale 0.5) is met on its sides only with its centre about 3.5 cm
    # beyond the grip site; centred at the grip site, the sweeping fingertips (up to
    # 4.4 cm beyond it) strike the floor first and never touch the part.
    tcp_pos = np.array([grip.pos[0], grip.pos[1], pinch.pos[2]])
    tcp = grip.parent.add("site", name="tcp", pos=tcp_pos, quat=(0.0, 1.0, 0.0, 0.0),
                          size=[0.005], group=4)
    # The wrist camera, 7 cm off the hand's axis (its -y side, where two fingers frame the
    # grasp rather than one filling the view), looks along the approach (the hand's -z)
    # tilted WRIST_CAMERA_TILT towards the axis: the fingertips and the part between them
    # are in view (looking along the hand's y it would see the horizon, the tool pointing down).
    tilt = np.radians(WRIST_CAMERA_TILT)
    camera = grip.parent.add("camera", name="eye_in_hand", pos=(0.0, -0.07, -0.06),
                             xyaxes=(1, 0, 0, 0, np.cos(tilt), np.sin(tilt)), fovy=75)
    actuators = [hand.actuator.add(
        "position", name=f"{joint.name}_position", joint=joint, kp=_FINGER_KP, ctrllimited=True,
        ctrlrange=(_FINGER_OPEN, _FINGER_CLOSED + finger_torque / _FINGER_KP), forcelimited=True,
        forcerange=(-finger_torque, finger_torque)) for joint in hand_entity.joints]
    count = len(hand_entity.joints)
    gripper = grippers.GripperParts(
        joints=list(hand_entity.joints), actuators=actuators,
        open_qpos=np.full(count, _FINGER_OPEN), closed_qpos=np.full(count, _FINGER_CLOSED),
        squeeze_qpos=np.full(count, _FINGER_CLOSED + finger_torque / _FINGER_KP),
        tcp_site=tcp, root_body=grip.parent, close_time=facts.close_time)
    arm = manipulator.Arm(
        prefix="", joints=list(arm_entity.joints), torque_limits=np.array(_TORQUE_LIMITS),
        gripper=gripper, camera=camera, seed=np.array(_SEED), home_tcp=np.array([0.4, 0.0, 0.35]),
        workspace=np.array([[-0.45, -0.8, 0.005], [0.85, 0.8, 0.9]]))
    return root, [arm]

  def after_compile(self, physics, random_state):
    super().after_compile(physics, random_state)
    model = physics.model   # after the task's configure_contacts, which sets every geom
    fingers = np.isin(self._finger_table[0][model.geom_bodyid], np.arange(3))
    fingers &= model.geom_contype != 0
    model.geom_priority[fingers] = 1
    physics_settings.configure_pads(model, np.flatnonzero(fingers), solref=_FINGER_SOLREF)
