"""Parallel grippers built from fact sheets: the Rethink electric gripper and the Franka hand.

Each finger is a slide joint driven by a force-limited position actuator, so
a closed gripper squeezes a part with at most the manufacturer's grasp force
(the fact sheet's `grip` block: force, stroke, pad friction, each with its
source) and holds it by friction alone. With two opposed fingers each pushing
with at most F, the part is squeezed with F, so each finger's force limit is
the published grasp force. The gripper action maps -1 to open, +1 to closed.
"""

import dataclasses

import numpy as np

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.robots import robot_facts

# Finger pads resist twisting of a held part (condim 4); their sliding friction
# comes from the sheet's grip block (MuJoCo takes the larger of the two geoms').
_PAD_TORSION, _PAD_ROLLING = 0.05, 0.0001
_PAD_CONDIM = 4


@dataclasses.dataclass(frozen=True)
class GripFacts:
  """A hand's published grasp figures (the fact sheet's `grip` block).

  Attributes:
    force: continuous grasp force, N.
    peak_force: peak grasp force, N.
    stroke: full opening, m.
    friction: sliding friction coefficient of the finger pads.
    close_time: seconds the fingers take to close (0: not given, a few control steps).
    sources: figure name -> where the figure comes from.
  """
  force: float
  peak_force: float
  stroke: float
  friction: float
  sources: dict
  close_time: float = 0.0


def grip_facts(sheet: str) -> GripFacts:
  """The grasp figures of fact sheet `sheet` (e.g. "panda_gripper").

  Args:
    sheet: fact sheet name under robots/facts.
  Returns:
    GripFacts with the sheet's figures and their sources.
  Raises:
    UnknownNameError: no such sheet.
  """
  grip = robot_facts.load(sheet)["grip"]
  return GripFacts(force=float(grip["force_continuous_n"]), peak_force=float(grip["force_peak_n"]),
                   stroke=float(grip["stroke_m"]), friction=float(grip["finger_friction"]),
                   sources=dict(grip["sources"]),
                   close_time=float(grip.get("close_time_s", 0.0)))


@dataclasses.dataclass(frozen=True)
class GripperSpec:
  facts: str
  # finger joint -> (open value, closed value), in the sheet's joint coordinates
  fingers: dict
  tcp_site: str = "grip_site"
  pad_bodies: tuple = ()
  # Frame of the gripper root in the arm's hand body (w x y z); None: the sheet's own.
  mount_quat: tuple = None
  # How far (m) each finger is mounted nearer the centre than in the sheet (a finger
  # slot further in); its travel then ends at the closed value, where the two meet.
  slot_inward: float = 0.0


# The Rethink electric gripper with its fingers in the fact sheet's slot: Rethink's robot
# descriptions' default, slot 2 (baxter_description/urdf/left_end_effector.urdf.xacro:
# l_finger_slot='2'), where the closed fingertips stay 14 mm apart.
RETHINK = GripperSpec(
    facts="rethink_gripper",
    fingers={"r_finger_joint": (-0.020833, 0.0115), "l_finger_joint": (0.020833, -0.0115)},
    pad_bodies=("l_finger", "l_finger_tip", "r_finger", "r_finger_tip"))

# The same gripper with its fingers one slot in, slot 1. It takes fingers in four slots
# 9.5 mm apart per finger (the finger offset is (slot - 1) x 9.5 mm - 11 mm in the gripper
# xacro of Rethink's descriptions, as carried e.g. by ll4ma_robots_description's baxter
# gripper.xacro). In slot 1 the fingers meet when closed and open to 60 mm, so they
# squeeze the 4-10 mm walls and stretchers that slot 2's 14 mm cannot. Closed values: the
# sheet's 0.0115 m less the 2.5 mm at which the pads, 9.5 mm further in each, touch.
RETHINK_SLOT_1 = dataclasses.replace(
    RETHINK, fingers={"r_finger_joint": (-0.020833, 0.009), "l_finger_joint": (0.020833, -0.009)},
    slot_inward=0.0095)

FRANKA_HAND = GripperSpec(
    facts="panda_gripper",
    fingers={"finger_joint1": (0.04, 0.0), "finger_joint2": (-0.04, 0.0)},
    pad_bodies=("finger_joint1_tip", "finger_joint2_tip", "leftfinger", "rightfinger"))


@dataclasses.dataclass
class GripperParts:
  """MJCF elements of one built gripper."""
  joints: list
  actuators: list
  open_qpos: np.ndarray
  closed_qpos: np.ndarray
  tcp_site: object
  root_body: object
  # Colliding geoms of the finger pads (physics_settings.configure_pads).
  pad_geoms: list = dataclasses.field(default_factory=list)
  # Position target of a closed command: past the closed limit by force / kp, so a
  # finger squeezes with its full force limit whatever the part's thickness (as a
  # real gripper's force-controlled grasp does), not kp times the travel left.
  squeeze_qpos: np.ndarray = None
  # Seconds a closed command takes to close the fingers on a part (the sheet's figure);
  # 0 where the sheet gives none and the fingers close within a few control steps.
  close_time: float = 0.0

  def __post_init__(self):
    if self.squeeze_qpos is None:
      self.squeeze_qpos = self.closed_qpos


def build(hand_body, spec, prefix):
  """Builds `spec` under the arm's hand body; names get `prefix`. Returns GripperParts."""
  facts = robot_facts.load(spec.facts)
  grip = grip_facts(spec.facts)
  root = facts["bodies"][0]
  elements = robot_facts.add_tree(hand_body, facts, name_prefix=prefix, pos=[0, 0, 0],
                                  quat=spec.mount_quat or root.get("quat", [1, 0, 0, 0]))
  if spec.slot_inward:
    _mount_fingers_inward(hand_body.root, spec, prefix)
  pad_geoms = []
  for body_name in spec.pad_bodies:
    for geom in elements[body_name].find_all("geom", immediate_children_only=True):
      if geom.contype:
        geom.friction = (grip.friction, _PAD_TORSION, _PAD_ROLLING)
        geom.condim = _PAD_CONDIM
        pad_geoms.append(geom)
  mjcf_root = hand_body.root
  limits = {a["joint"]: a for a in facts["actuators"]}
  force = grip.force   # each finger pushes with at most the published grasp force
  values = np.array(list(spec.fingers.values()), dtype=float)
  joints, actuators, squeeze = [], [], []
  for (joint_name, (open_q, closed_q)) in spec.fingers.items():
    joint = mjcf_root.find("joint", prefix + joint_name)
    kp = float(limits[joint_name]["kp"])
    target = closed_q + np.sign(closed_q - open_q) * force / kp
    squeeze.append(target)
    joints.append(joint)
    actuators.append(mjcf_root.actuator.add(
        "position", name=f"{prefix}{joint_name}_position", joint=joint, kp=kp,
        ctrllimited=True, ctrlrange=sorted([open_q, target]), forcelimited=True,
        forcerange=[-force, force]))
  _couple(mjcf_root, joints, values)
  return GripperParts(joints=joints, actuators=actuators, open_qpos=values[:, 0],
                      closed_qpos=values[:, 1],
                      tcp_site=mjcf_root.find("site", prefix + spec.tcp_site),
                      root_body=elements[root["name"]], squeeze_qpos=np.array(squeeze),
                      pad_geoms=pad_geoms)


def _mount_fingers_inward(mjcf_root, spec, prefix):
  """Moves each finger's body `spec.slot_inward` towards the other along its closing
  direction, and ends its travel at the closed value (where the fingers meet)."""
  for joint_name, (open_q, closed_q) in spec.fingers.items():
    joint = mjcf_root.find("joint", prefix + joint_name)
    body = joint.parent
    rotation = geometry.quat_to_mat(body.quat if body.quat is not None else [1, 0, 0, 0])
    closing = np.sign(closed_q - open_q) * rotation @ np.asarray(joint.axis, dtype=float)
    body.pos = np.asarray(body.pos, dtype=float) + spec.slot_inward * closing
    joint.range = sorted([open_q, closed_q])


def _couple(mjcf_root, joints, values):
  """Ties each finger to the first, as the hands' single motor does (Franka hand: both
  fingers on one drive, the URDF's mimic joint; Rethink electric gripper: one motor).
  Uncoupled, the finger that touches first pushes the part along the floor until the
  other arrives, and a thin part ends up pinched at the pad's edge: measured with the
  Panda on a Lack leg, one finger closed fully and the leg was squeezed out on lifting."""
  (open0, closed0) = values[0]
  for joint, (open_q, closed_q) in zip(joints[1:], values[1:]):
    ratio = (closed_q - open_q) / (closed0 - open0)
    mjcf_root.equality.add("joint", joint1=joint, joint2=joints[0],
                           polycoef=(open_q - ratio * open0, ratio, 0, 0, 0),
                           solref=physics_settings.HARD_SOLREF,   # a gear train: rigid
                           solimp=physics_settings.HARD_SOLIMP)


def command(open_qpos, closed_qpos, action):
  """Finger position targets for a gripper action in [-1, 1] (-1 open, +1 closed).

  Args:
    open_qpos: finger targets of an open command.
    closed_qpos: finger targets of a closed command (GripperParts.squeeze_qpos).
    action: the gripper entry of the action.
  Returns:
    Finger position targets, interpolated linearly.
  """
  fraction = (np.clip(action, -1.0, 1.0) + 1.0) / 2.0
  return open_qpos + fraction * (closed_qpos - open_qpos)


def opening(open_qpos, closed_qpos, qpos):
  """Opening in [0, 1]: 1 fully open, 0 fully closed (mean over fingers)."""
  return float(np.mean(np.clip((qpos - closed_qpos) / (open_qpos - closed_qpos), 0.0, 1.0)))


def finger_of_body(physics, finger_body_ids):
  """(arms, bodies) int: which finger of each arm's gripper a body belongs to, -1 for none.

  A finger is the body its joint moves plus every body below it (pads are often children).
  `finger_body_ids` lists, per arm, the body ids its finger joints move.
  """
  parent = physics.model.body_parentid
  out = np.full((len(finger_body_ids), len(parent)), -1)
  for arm, fingers in enumerate(finger_body_ids):
    for body in range(len(parent)):
      ancestor = body
      while ancestor > 0 and ancestor not in fingers:
        ancestor = parent[ancestor]
      if ancestor > 0:
        out[arm, body] = int(np.flatnonzero(fingers == ancestor)[0])
  return out


def held_by_fingers(physics, finger_table, part_body_ids):
  """(arms, parts) bool: a part is held by an arm when it touches that arm's first finger
  and at least one other (`finger_table` from `finger_of_body`): both fingers of a parallel
  gripper, or the thumb and an opposing finger of the Jaco's hand (its two fingers side
  by side touch a part from the same side and do not hold it)."""
  part_body_ids = np.asarray(part_body_ids)
  out = np.zeros((len(finger_table), len(part_body_ids)), dtype=bool)
  contact = physics.data.contact
  body = physics.model.geom_bodyid
  part_of_body = np.full(physics.model.nbody, -1)
  part_of_body[part_body_ids] = np.arange(len(part_body_ids))
  for arm, arm_fingers in enumerate(finger_table):
    pairs = set()
    for first, second in ((body[contact.geom1], body[contact.geom2]),
                          (body[contact.geom2], body[contact.geom1])):
      finger, part = arm_fingers[first], part_of_body[second]
      pairs |= {(int(p), int(f)) for p, f in zip(part, finger) if p >= 0 and f >= 0}
    for p in {p for p, _ in pairs}:
      touching = {f for q, f in pairs if q == p}
      if 0 in touching and len(touching) >= 2:
        out[arm, p] = True
  return out
