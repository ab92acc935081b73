"""A batched scripted expert for a single arm's last-part task, as pure jax functions.

The task: every part but one is joined (load option `preassembled` = parts - 1, so
the CPU task's own placement lays the assembly and the loose part within reach, a panel
standing in the panel rack: tasks/placement.PartGroups, tasks/panel_placement.py); the
expert takes the loose part from above, lifts it, turns and carries it so that it
stands over its place on the assembly, lowers it in and connects. The CPU expert
(experts/single_arm.py with top_down_grasp.py and mating.py) does the same one part at
a time with more cases (clearance routes, regrasps, turning the assembly over); this
one covers single parts that a top-down grasp across their longest horizontal axis can
carry to their mate in one motion, going in from above: the legs of the catalog's
tables and stools, lying on the floor, and the end panels and stretcher of a plank
bench, standing in the rack and taken by their top edge (the assembly lies turned over,
as the CPU placement lays its root: batch/arm_model.py).

Per world it reads the privileged state (part poses, the task-space target, the tool
pose) and keeps a small ExpertState (phase, step counter, the part's pose in the tool
frame measured when the fingers closed). Phases:

  REACH    open hand HOVER above the grasp point, pointing down, fingers across the
           part's long axis (over everything else until it is nearly above it)
  DESCEND  down to the grasp point (fingertips just above the part's underside, or
           EDGE_GRIP below a standing panel's top edge)
  CLOSE    squeeze for CLOSE_STEPS
  LIFT     straight up to the carry height
  CARRY    move and turn at the carry height until the part is over its mate
  LOWER    down to the part's mated pose raised by APPROACH
  INSERT   lower it onto the mate with connect on; the task snaps and welds it

A part that leaves the hand after CLOSE (missed, or dropped on the way) sends the world
back to REACH.

The grasp, the twist and the way round the held part turns are chosen per world when
its episode starts (choose): of four top-down grasps (either side of the part's middle,
the hand either way round), the pair's allowed twists and both ways round, the one whose
tool pose above the mate the arm's IK reaches best from the grasp, joints clear of their
ranges, as the CPU expert's choose_grasp_sign and plan_mating rank theirs
(experts/mating.py).

While carrying, the tool's command is the part's pose error applied to the tool (as
batch/scripted.py steers the Cursor's part), so slip in the grip is corrected too; the
target it moves is kept within LEAD of the measured tool, horizontally and vertically
each, so the servos' lag does not wind it up.
"""

import typing

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite.batch import arm_control
from ikea_suite.batch import rigid
from ikea_suite.batch import task_state
from ikea_suite.experts import top_down_grasp
from ikea_suite.tasks import placement as cpu_placement

# The arms this expert was shown to assemble with (docs/batch.md): two fingers facing each
# other. The Jaco's fingers close against a thumb, and its hand missed every leg.
ROBOTS = ("panda", "sawyer")
REACH, DESCEND, CLOSE, LIFT, CARRY, LOWER, INSERT = range(7)
PHASES = ("reach", "descend", "close", "lift", "carry", "lower", "insert")
HOVER = 0.06          # m above the grasp point the reach makes for
TIP_CLEARANCE = 0.004  # m between the fingertips and the part's underside (or the floor)
# A part standing TALL (m) or taller is taken by its top edge, the fingertips EDGE_GRIP (m)
# below it: the CPU expert's rule, where the rack's fins leave that much of a panel free.
TALL, EDGE_GRIP = top_down_grasp.TALL, top_down_grasp.EDGE_GRIP
CLOSE_STEPS = 10      # control steps the fingers squeeze before lifting (0.5 s)
CARRY_MARGIN = 0.04   # m of clearance under the carried part's lowest point
APPROACH = 0.03       # m above the mated pose from which the part goes in
GRIP_OFFSET = 0.3     # fraction of the half length from the centre the grasps take
POS_TOL, ROT_TOL = 0.006, 0.06   # m, rad: a waypoint is reached
# m, rad: the carried part is close enough above its mate to go in (the insertion goes on
# correcting its pose); held to POS_TOL, ROT_TOL the servo hunted round the last
# centimetre long enough for the part to slip out of the grip.
CARRY_GATE = (0.02, 0.1)
# m, rad: the carried part is over its mate (horizontally) and turned nearly as it
# mates, and goes down.
OVER_MATE = (0.02, 0.3)
LEAD = 0.03           # m the target may lead the measured tool while carrying (see act),
                      # horizontally and vertically each
REACH_NEAR = 0.05     # m (horizontal) from the hover within which the open hand goes down
LOST = 0.05           # m the part may move from where the closed fingers held it
CARRY_GAIN = 0.5      # fraction of the part's pose error the target takes per step
DESCEND_GAIN = 0.4    # fraction of a full step the open hand goes down by
CARRY_TURN = 0.15     # fraction of the top turning speed a held part turns at (see act)
# The choice of grasp and twist (choose): IK steps of at most IK_STEP rad follow the
# servo's path, REACH_ITERATIONS of them to the hover, GRASP_ITERATIONS down to the grasp
# point, LIFT_ITERATIONS up to the carry height, CARRY_ITERATIONS at that height to the
# point over the mate, LIFT_ITERATIONS down to the approach and GRASP_ITERATIONS on to the
# mated pose; a rotation miss of 1 rad costs as much as ROTATION_MISS_WEIGHT m
# of position miss, and a joint closer than LIMIT_MARGIN rad to its range costs the
# shortfall.
IK_STEP = 0.1
REACH_ITERATIONS, GRASP_ITERATIONS, LIFT_ITERATIONS, CARRY_ITERATIONS = 40, 10, 20, 60
ROTATION_MISS_WEIGHT = 0.1
LIMIT_MARGIN = 0.3
# m (with the rotation miss as above): a grasp whose hover the servo's path misses by more
# is ruled out (see choose).
HOVER_MISS = 0.05
# The arm's links and hand, as spheres along each collision geom's longest axis, are kept
# ARM_CLEARANCE (m) off every part but the loose one at the grasp and on the mate; each m
# they come closer costs CLEARANCE_WEIGHT m of reach miss (see choose).
ARM_CLEARANCE = 0.01
CLEARANCE_WEIGHT = 10.0


class Plan(typing.NamedTuple):
  """Device constants of one furniture for the expert.

  Attributes:
    center, half: (p, 3) each part's collision box centre and half size (part frame).
    mate: (p,) the part each part mates with in the design (its first design pair).
    rel_pos, rel_rot: (p, 3), (p, 3, 3) each part's design pose in its mate's frame.
    away: (p, 3) unit vector (part frame) along the part's long axis pointing away from
      its connector to the mate.
    conn_pos, conn_axis: (p, 3) that connector's position and up axis (part frame).
    twists, twist_valid: (p, t) the pair's allowed twists (rad) about that axis.
    closing: (3,) the fingers' closing axis in the tool frame.
    pad_below: m the fingertips reach below the tool centre when pointing down.
    sphere_body: (s,) index of the arm chain's body (arm_control.body_poses) each sphere
      that covers the arm's collision geoms rides on.
    sphere_pos, sphere_radius: (s, 3) their centres in that body's frame, (s,) radii.
  """
  center: jnp.ndarray
  half: jnp.ndarray
  mate: jnp.ndarray
  rel_pos: jnp.ndarray
  rel_rot: jnp.ndarray
  away: jnp.ndarray
  conn_pos: jnp.ndarray
  conn_axis: jnp.ndarray
  twists: jnp.ndarray
  twist_valid: jnp.ndarray
  closing: jnp.ndarray
  pad_below: float
  sphere_body: jnp.ndarray
  sphere_pos: jnp.ndarray
  sphere_radius: jnp.ndarray


class ExpertState(typing.NamedTuple):
  """One world's expert memory (batched: a leading world axis)."""
  phase: jnp.ndarray       # int32
  steps: jnp.ndarray       # int32 control steps in the phase
  grip_pos: jnp.ndarray    # (3,) part position in the tool frame, set when closing ends
  grip_rot: jnp.ndarray    # (3, 3)
  chosen: jnp.ndarray      # bool: grasp and twist chosen (choose) for this episode
  grasp: jnp.ndarray       # int32: which of the four grasps across the part's long axis
  twist: jnp.ndarray       # int32: which of the pair's allowed twists the part mates at
  turn: jnp.ndarray        # +1 / -1: the held part turns that way round about the world z
                           # axis to its mate; 0: the shorter way (see choose)


def _finger_geometry(env):
  """(closing axis in the tool frame, fingertip reach below the tool) at home, measured on
  the compiled model with MuJoCo."""
  am = env.arm_model
  model = am.model
  data = mujoco.MjData(model)
  data.qpos[:] = am.home_qpos
  mujoco.mj_forward(model, data)
  tool_pos = data.site_xpos[am.tcp_site]
  tool_rot = data.site_xmat[am.tcp_site].reshape(3, 3)
  # The fingers close along the line they spread over most: the two fingers' line, or for a
  # hand whose fingers close against a thumb, the thumb's line to the fingers.
  spread = data.xpos[am.finger_body] - data.xpos[am.finger_body].mean(axis=0)
  line = np.linalg.svd(spread)[2][0]
  line *= np.sign(line @ (spread[-1] - spread[0])) or 1.0
  closing = tool_rot.T @ line
  lowest = np.inf
  for g in np.flatnonzero(np.isin(model.geom_bodyid, am.finger_body)):
    if not (model.geom_contype[g] or model.geom_conaffinity[g]):
      continue
    half = model.geom_aabb[g, 3:]
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * half
    corners = corners + model.geom_aabb[g, :3]
    world = data.geom_xpos[g] + corners @ data.geom_xmat[g].reshape(3, 3).T
    lowest = min(lowest, world[:, 2].min())
  return closing, float(tool_pos[2] - lowest)


def _arm_spheres(env):
  """(body index on the arm chain, centre in that body's frame, radius) of spheres covering
  the collision geoms of the bodies on the chain from the base to the tool (the links and
  the hand; the fingers hold the part): per geom, three along its bounding box's longest
  axis, as wide as its second longest half size. Every geom is taken whether or not it
  collides in this model (the light model switches the links off; the arm still has them)."""
  am = env.arm_model
  model = am.model
  bodies = []
  body = int(model.site_bodyid[am.tcp_site])
  while body != 0:
    bodies.append(body)
    body = int(model.body_parentid[body])
  bodies.reverse()
  index, centres, radii = [], [], []
  for i, b in enumerate(bodies):
    for g in range(int(model.body_geomadr[b]), int(model.body_geomadr[b] + model.body_geomnum[b])):
      centre, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
      order = np.argsort(half)
      radius = float(half[order[1]])
      axis = np.zeros(3)
      axis[order[2]] = max(float(half[order[2]]) - radius, 0.0)
      rot = np.empty(9)
      mujoco.mju_quat2Mat(rot, model.geom_quat[g])
      rot = rot.reshape(3, 3)
      for side in (-1.0, 0.0, 1.0):
        index.append(i)
        centres.append(model.geom_pos[g] + rot @ (centre + side * axis))
        radii.append(radius)
  return np.array(index, dtype=int), np.array(centres), np.array(radii)


def plan(env):
  """The expert's Plan for a BatchArmAssembly `env` (numpy work, once per environment).

  Raises:
    UnknownNameError: the env's robot is not one of ROBOTS.
  """
  if env.robot not in ROBOTS:
    raise errors.UnknownNameError("batched expert robot", env.robot, ROBOTS)
  bm = env.batch_model
  spec, table = bm.spec, bm.table
  p = bm.num_parts
  center, half = np.zeros((p, 3)), np.zeros((p, 3))
  for i in range(p):
    lo, hi = np.asarray(spec.parts[i].bounds, dtype=float)
    center[i], half[i] = (lo + hi) / 2, (hi - lo) / 2
  design_pos = np.array([q.pos for q in spec.parts], dtype=float)
  design_rot = np.array([q.rot for q in spec.parts], dtype=float)
  mate = np.zeros(p, dtype=int)
  rel_pos, rel_rot, away = np.zeros((p, 3)), np.tile(np.eye(3), (p, 1, 1)), np.zeros((p, 3))
  welds = bm.welds
  conn_pos, conn_axis = np.zeros((p, 3)), np.tile([0.0, 0.0, 1.0], (p, 1))
  twists = np.zeros((p, welds.twist_angles.shape[1]))
  twist_valid = np.zeros_like(twists, dtype=bool)
  twist_valid[:, 0] = True
  done = np.zeros(p, dtype=bool)
  for k in cpu_placement.design_pairs(spec, table):
    for own, other in ((table.pair_a[k], table.pair_b[k]), (table.pair_b[k], table.pair_a[k])):
      i, j = int(table.part[own]), int(table.part[other])
      if done[i]:
        continue
      done[i] = True
      mate[i] = j
      rel_rot[i] = design_rot[j].T @ design_rot[i]
      rel_pos[i] = design_rot[j].T @ (design_pos[i] - design_pos[j])
      axis = np.zeros(3)
      long = int(np.argmax(half[i]))
      axis[long] = -np.sign(table.local_pos[own][long] - center[i][long]) or 1.0
      away[i] = axis
      conn_pos[i], conn_axis[i] = table.local_pos[own], table.local_rot[own][:, 2]
      twists[i], twist_valid[i] = welds.twist_angles[k], welds.twist_valid[k]
  closing, pad_below = _finger_geometry(env)
  sphere_body, sphere_pos, sphere_radius = _arm_spheres(env)
  f = lambda x: rigid.real(np.asarray(x))
  return Plan(center=f(center), half=f(half), mate=jnp.asarray(mate, dtype=jnp.int32),
              rel_pos=f(rel_pos), rel_rot=f(rel_rot), away=f(away), conn_pos=f(conn_pos),
              conn_axis=f(conn_axis), twists=f(twists), twist_valid=jnp.asarray(twist_valid),
              closing=f(closing),
              pad_below=float(pad_below), sphere_body=jnp.asarray(sphere_body, dtype=jnp.int32),
              sphere_pos=f(sphere_pos), sphere_radius=f(sphere_radius))


def initial_state():
  """The expert's memory at an episode's start."""
  return ExpertState(phase=jnp.int32(REACH), steps=jnp.int32(0), grip_pos=jnp.zeros(3),
                     grip_rot=jnp.eye(3), chosen=jnp.bool_(False), grasp=jnp.int32(0),
                     twist=jnp.int32(0), turn=jnp.zeros(()))


def loose_part(env, state):
  """The part in the smallest group (the last part, outside the joined ones), or part 0
  when all are joined."""
  group = state.task.group
  sizes = (group[:, None] == group[None, :]).sum(axis=1)
  return jnp.where(sizes.min() < sizes.max(), jnp.argmin(sizes), 0)


def _corners(pos, rot, center, half):
  signs = jnp.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
  return pos + rigid.apply(rot, center + signs * half)


def _grasps(plan_, home_rot, part_pos, part_rot, m):
  """The four top-down grasps of part m lying or standing at (part_pos, part_rot): tool
  positions (4, 3) and rotations (4, 3, 3), pointing down with the fingers across the
  part's longest horizontal axis, GRIP_OFFSET of its half length from the centre away
  from the mate's connector (grasps 0, 1) or towards it (2, 3), the odd ones turned half a
  turn about the vertical. A part lying low (a leg) is taken as low as the fingertips
  allow; one standing TALL or taller (a panel in the rack) by its top edge, the fingertips
  EDGE_GRIP below it, across its thickness (as experts/top_down_grasp.py takes them)."""
  center, half = plan_.center[m], plan_.half[m]
  corners_z = _corners(part_pos, part_rot, center, half)[:, 2]
  low = jnp.maximum(jnp.min(corners_z), 0.0)
  top = jnp.max(corners_z)
  # Each part axis's horizontal extent as it lies now: a leg's long axis, a standing
  # panel's length (its height, though longer, is vertical).
  long = jnp.argmax(half * jnp.linalg.norm(part_rot[:2, :], axis=0))
  long_local = jnp.zeros(3).at[long].set(1.0)
  away = long_local * jnp.where(plan_.away[m][long] < 0, -1.0, 1.0)
  points = jnp.stack([part_pos + rigid.apply(part_rot, center + side * away * half
                                             * GRIP_OFFSET) for side in (1.0, -1.0)])
  tips = jnp.where(top - low >= TALL, top - EDGE_GRIP, low + TIP_CLEARANCE)
  points = points.at[:, 2].set(tips + plan_.pad_below)
  long_world = rigid.apply(part_rot, long_local)
  across = jnp.array([-long_world[1], long_world[0], 0.0])
  across = across / jnp.maximum(jnp.linalg.norm(across), 1e-9)
  home_closing = rigid.apply(home_rot, plan_.closing)
  yaw = jnp.arctan2(home_closing[0] * across[1] - home_closing[1] * across[0],
                    home_closing[0] * across[0] + home_closing[1] * across[1])
  yaw = jnp.where(yaw > jnp.pi / 2, yaw - jnp.pi, jnp.where(yaw < -jnp.pi / 2, yaw + jnp.pi, yaw))
  rots = jnp.stack([rigid.rot_z(yaw) @ home_rot, rigid.rot_z(yaw + jnp.pi) @ home_rot])
  return points[jnp.array([0, 0, 1, 1])], rots[jnp.array([0, 1, 0, 1])]


def _depth(rot, center, half):
  """How far (m) a part's box reaches below its origin at rotation `rot`."""
  return -jnp.min(_corners(jnp.zeros(3), rot, center, half)[:, 2])


def _mated_poses(plan_, part_pos, part_rot, m):
  """The poses of part m on its mate, one per allowed twist of the pair: positions (t, 3)
  and rotations (t, 3, 3), the design pose turned about the connector's axis by each
  twist (entries where plan_.twist_valid[m] is False are not allowed)."""
  t = plan_.mate[m]
  design_rot = part_rot[t] @ plan_.rel_rot[m]
  design_pos = part_pos[t] + rigid.apply(part_rot[t], plan_.rel_pos[m])
  connector = design_pos + rigid.apply(design_rot, plan_.conn_pos[m])
  axis = plan_.conn_axis[m]
  turns = jax.vmap(lambda a: arm_control._axis_rot(axis, a))(plan_.twists[m])      # (t, 3, 3)
  rots = design_rot[None] @ turns
  return connector[None] - jnp.einsum("tij,j->ti", rots, plan_.conn_pos[m]), rots


def _heights(plan_, part_pos, part_rot, m, goal_pos, goal_rot):
  """(top of every part but m, carry height of m's origin) (m): the carry height keeps
  part m, however it is turned, CARRY_MARGIN clear of its mated pose's height and of the
  top of everything else (the legs already standing on the assembly: passing among them
  knocked the part out of the grip)."""
  corners = jax.vmap(_corners)(part_pos, part_rot, plan_.center, plan_.half)   # (p, 8, 3)
  others = jnp.arange(part_pos.shape[0]) != m
  others_top = jnp.max(jnp.where(others, corners[:, :, 2].max(axis=1), 0.0))
  depth = jnp.maximum(_depth(part_rot[m], plan_.center[m], plan_.half[m]),
                      _depth(goal_rot, plan_.center[m], plan_.half[m]))
  carry_z = CARRY_MARGIN + jnp.maximum(others_top + depth, jnp.maximum(goal_pos[2], 0.0) + depth)
  return others_top, carry_z


def _servo_path(env, q, pos, rot, iterations):
  """Arm joints where repeated IK steps (the task-space controller's, IK_STEP rad at
  most each) from joints q towards tool poses pos (n, 3), rot (n, 3, 3) in turn,
  iterations[i] (Python ints) of them towards pose i, stop at the end of each leg
  (n, joints): the servo's path through those targets, which ends short where a joint
  meets its range. (One scan over all the legs, so that it compiles once.)"""
  am = env.arm_model
  low, high = rigid.real(am.ik_low), rigid.real(am.ik_high)
  home = rigid.real(am.home_qpos[am.arm_qpos])
  leg = jnp.asarray(np.repeat(np.arange(len(iterations)), iterations))

  def step(x, i):
    x = arm_control.ik_step(env.chain, x, pos[i], rot[i], home, low, high, IK_STEP)
    return x, x

  path = jax.lax.scan(step, q, leg)[1]
  return path[jnp.asarray(np.cumsum(iterations) - 1)]


def _reach_cost(env, q, pos, rot):
  """How badly joints q reach the tool pose (pos, rot): the position miss (m), the
  rotation miss (rad, ROTATION_MISS_WEIGHT m each) and the joints' encroachment on
  LIMIT_MARGIN (rad) from the IK's ranges (as experts/mating.reach_cost counts it)."""
  am = env.arm_model
  low, high = rigid.real(am.ik_low), rigid.real(am.ik_high)
  tool_pos, tool_rot = arm_control.tool_pose(env.chain, q)
  miss = (jnp.linalg.norm(tool_pos - pos)
          + ROTATION_MISS_WEIGHT * jnp.linalg.norm(arm_control.rotation_vector(rot @ tool_rot.T)))
  margin = jnp.minimum(q - low, high - q)
  return miss + jnp.maximum(0.0, LIMIT_MARGIN - margin).sum()


def _arm_intrusion(env, plan_, q, part_pos, part_rot, m):
  """How far (m, summed over the arm's spheres and the parts) the arm at joints q comes
  within ARM_CLEARANCE of any part but m (each part as its collision box)."""
  body_pos, body_rot = arm_control.body_poses(env.chain, q)
  centres = body_pos[plan_.sphere_body] + jnp.einsum(
      "sij,sj->si", body_rot[plan_.sphere_body], plan_.sphere_pos)                # (s, 3)
  local = jnp.einsum("pji,psj->psi", part_rot, centres[None] - part_pos[:, None])
  outside = jnp.maximum(jnp.abs(local - plan_.center[:, None]) - plan_.half[:, None], 0.0)
  gap = jnp.linalg.norm(outside, axis=-1)                                        # (p, s)
  intrusion = jnp.maximum(plan_.sphere_radius[None] + ARM_CLEARANCE - gap, 0.0)
  others = jnp.arange(part_pos.shape[0]) != m
  return jnp.sum(jnp.where(others[:, None], intrusion, 0.0))


def _yaw(rot):
  """Angle (rad, in (-pi, pi]) about the world z axis of a rotation that is mostly one
  about it (between two poses of a hand pointing down)."""
  return jnp.arctan2(rot[1, 0] - rot[0, 1], rot[0, 0] + rot[1, 1])


def choose(env, plan_, state):
  """(grasp, twist, turn) of one world: of the four grasps of the loose part, the pair's
  allowed twists and the two ways round the held part may turn about the vertical on its
  way to the mate, the choice the arm reaches best. The servo's path is followed by IK as
  act's phases go: from the present joints to the hover above the grasp, down to the grasp
  point, up to the carry height, over to the point above the mate turned to that twist
  (the chosen way round: first to halfway), down to the tool pose that holds the part
  APPROACH above its mated pose (the grip the grasp makes) and on to the mated pose;
  reach_cost at the hover, over the mate and at the approach ranks them, and so does the
  arm's intrusion (_arm_intrusion) on the parts other than the loose one at the grasp
  point and at the mated pose, CLEARANCE_WEIGHT m per m. A twist that turns the part
  upright on the far side of the wrist's range ends short with the wrist at its limit, as
  the carry did before the choice was made; so did a panel taken from the rack beside the
  base and turned the shorter way round to its mate in front of it. A grasp whose hover
  the path misses by more than HOVER_MISS is ruled out while another's is reached: the
  hand never comes down there, however well the rest of its path goes.

  Args:
    env: the BatchArmAssembly.
    plan_: its Plan.
    state: the world's arm_env.State.

  Returns:
    (grasp index (0 to 3, see _grasps), twist index), int32 scalars, and the way round the
    part turns about the world z axis to its mate (+1, -1; 0: the shorter way).
  """
  am = env.arm_model
  m = loose_part(env, state)
  part_pos, part_rot = task_state.part_poses(env.tables, state.data.qpos)
  home_rot = rigid.real(am.home_tcp_rot)
  points, grasp_rots = _grasps(plan_, home_rot, part_pos[m], part_rot[m], m)
  goal_pos, goal_rots = _mated_poses(plan_, part_pos, part_rot, m)
  hovers = points + jnp.array([0.0, 0.0, HOVER])
  q = state.data.qpos[jnp.asarray(am.arm_qpos)]

  def turn(start, end, way):   # the signed turn about z from start to end: the shorter
    short = _yaw(end @ start.T)   # way round (way 0) or the other
    return jnp.where(way == 1, short - 2 * jnp.pi * jnp.sign(short), short)

  def cost(g, k, v):
    grip_pos = rigid.apply(part_rot[m].T, points[g] - part_pos[m])
    grip_rot = part_rot[m].T @ grasp_rots[g]
    tool_rot = goal_rots[k] @ grip_rot
    above = goal_pos[k] + jnp.array([0.0, 0.0, APPROACH])
    tool_pos = above + rigid.apply(goal_rots[k], grip_pos)
    _, carry_z = _heights(plan_, part_pos, part_rot, m, goal_pos[k], goal_rots[k])
    lift = points[g].at[2].add(carry_z - part_pos[m][2])
    high = tool_pos.at[2].add(jnp.maximum(carry_z - above[2], 0.0))
    carry_turn = turn(grasp_rots[g], tool_rot, v)
    halfway = jnp.where(v == 1, rigid.rot_z(carry_turn / 2) @ grasp_rots[g], tool_rot)
    mated = goal_pos[k] + rigid.apply(goal_rots[k], grip_pos)
    pos = jnp.stack([hovers[g], points[g], lift, high, high, tool_pos, mated])
    rot = jnp.stack([grasp_rots[g], grasp_rots[g], grasp_rots[g], halfway, tool_rot, tool_rot,
                     tool_rot])
    ends = _servo_path(env, q, pos, rot, (REACH_ITERATIONS, GRASP_ITERATIONS, LIFT_ITERATIONS,
                                          CARRY_ITERATIONS // 2, CARRY_ITERATIONS,
                                          LIFT_ITERATIONS, GRASP_ITERATIONS))
    costs = [_reach_cost(env, ends[i], pos[i], rot[i]) for i in (0, 4, 5)]
    # The arm's links and hand beside the parts already joined, where the hand takes the
    # part and where it holds it on its mate: with every robot geom colliding (the Warp
    # model, and the CPU env), a forearm resting on a standing leg while the hand took the
    # loose one turned it in the grip, and one pressed on a leg beside the mate held the
    # shoulder at its range short of the insertion.
    clash = sum(_arm_intrusion(env, plan_, ends[i], part_pos, part_rot, m) for i in (1, 6))
    return (sum(costs) + CLEARANCE_WEIGHT * clash, costs[0] > HOVER_MISS,
            jnp.where(v == 1, jnp.sign(carry_turn), 0.0))

  grasps = jnp.arange(points.shape[0])
  twists = jnp.arange(plan_.twists.shape[1])
  ways = jnp.arange(2)
  costs, missed, turns = jax.vmap(lambda g: jax.vmap(lambda k: jax.vmap(
      lambda v: cost(g, k, v))(ways))(twists))(grasps)   # (4, t, 2)
  valid = plan_.twist_valid[m][None, :, None]
  costs = jnp.where(valid, costs, jnp.inf)
  costs = jnp.where(missed & ~jnp.all(missed | ~valid), jnp.inf, costs)
  best = jnp.unravel_index(jnp.argmin(costs.ravel()), costs.shape)
  return best[0].astype(jnp.int32), best[1].astype(jnp.int32), turns[best]


def _turning(rot, goal_rot, way):
  """The rotation to steer `rot` towards on its way to `goal_rot`, turning about the world
  z axis the way round `way` says (+1, -1; 0: the shorter way, goal_rot itself): while
  the shorter way turns more than a quarter turn against it, a quarter turn ahead that
  way."""
  short = _yaw(goal_rot @ rot.T)
  against = (way != 0) & (jnp.sign(short) != way) & (jnp.abs(short) > jnp.pi / 2)
  return jnp.where(against, rigid.rot_z(way * jnp.pi / 2) @ rot, goal_rot)


def _toward(targets, pos, rot, max_translation, max_rotation, gain=1.0):
  """Task-space action entries (6,) that move the target towards (pos, rot)."""
  move = jnp.clip((pos - targets.pos) / max_translation * gain, -1.0, 1.0)
  turn = jnp.clip(arm_control.rotation_vector(rot @ targets.rot.T) / max_rotation * gain,
                  -1.0, 1.0)
  return jnp.concatenate([move, turn])


def act(env, plan_, expert, state):
  """(action, next ExpertState) of one world.

  Args:
    env: the BatchArmAssembly (task_space control).
    plan_: its Plan.
    expert: ExpertState of the world, its grasp and twist chosen (choose; batched_policy
      does both).
    state: the world's arm_env.State.
  """
  am = env.arm_model
  qpos = state.data.qpos
  targets = state.targets
  m = loose_part(env, state)
  part_pos, part_rot = task_state.part_poses(env.tables, qpos)
  tool_pos, tool_rot = env.tool_pose(qpos)
  home_rot = rigid.real(am.home_tcp_rot)
  # The mated pose of m at the chosen twist, and the chosen grasp.
  goal_pos, goal_rot = (x[expert.twist] for x in _mated_poses(plan_, part_pos, part_rot, m))
  grasp_points, grasp_rots = _grasps(plan_, home_rot, part_pos[m], part_rot[m], m)
  grasp_pos, grasp_rot = grasp_points[expert.grasp], grasp_rots[expert.grasp]
  hover = grasp_pos + jnp.array([0.0, 0.0, HOVER])
  others_top, carry_z = _heights(plan_, part_pos, part_rot, m, goal_pos, goal_rot)
  above = goal_pos + jnp.array([0.0, 0.0, APPROACH])
  # The task-space target moved by the part's present pose error: the target integrates
  # the error, so the tool's tracking offset (gravity on the servos) and slip in the grip
  # are taken out too.
  def tool_for(pos, rot):
    delta = rot @ part_rot[m].T
    return (pos + rigid.apply(delta, targets.pos - part_pos[m]), delta @ targets.rot)
  part_err = lambda pos, rot: (jnp.linalg.norm(part_pos[m] - pos),
                               jnp.linalg.norm(arm_control.rotation_vector(rot @ part_rot[m].T)))
  mt, mr = am.max_translation, am.max_rotation
  phase, steps = expert.phase, expert.steps
  lift_pos = jnp.concatenate([tool_pos[:2], carry_z[None] + (tool_pos[2] - part_pos[m][2])])
  goal_tool = tool_for(goal_pos, goal_rot)
  # Carry at the carry height until over the mate (CARRY), then down to `above` (LOWER).
  horizontal = jnp.linalg.norm((part_pos[m] - above)[:2])
  high = above.at[2].set(jnp.maximum(above[2], carry_z))
  carry_tool = tool_for(high, _turning(part_rot[m], goal_rot, expert.turn))
  lower_tool = tool_for(above, goal_rot)
  # The open hand goes over everything else before it comes down to the hover: reaching
  # straight for it, the fingers swept through the legs standing on the assembly and
  # pushed it away from where the grasp and twist were chosen.
  reach_pos = jnp.where(jnp.linalg.norm((tool_pos - hover)[:2]) > REACH_NEAR,
                        hover.at[2].set(jnp.maximum(hover[2], others_top + plan_.pad_below
                                                    + CARRY_MARGIN)), hover)
  waypoints = [
      (reach_pos, grasp_rot, 1.0),
      (grasp_pos, grasp_rot, DESCEND_GAIN),
      (targets.pos, targets.rot, 1.0),
      (lift_pos, targets.rot, 1.0),
      (carry_tool[0], carry_tool[1], CARRY_GAIN),
      (lower_tool[0], lower_tool[1], CARRY_GAIN),
      (goal_tool[0], goal_tool[1], CARRY_GAIN),
  ]
  pos_d = jnp.stack([w[0] for w in waypoints])[phase]
  rot_d = jnp.stack([w[1] for w in waypoints])[phase]
  gain = jnp.array([w[2] for w in waypoints])[phase]
  tool_action = _toward(targets, pos_d, rot_d, mt, mr, gain)
  # While the part is steered by its own pose error the target integrates that error; a
  # target far ahead of the lagging tool overshot, and the part hunted round the point
  # above its mate. The target is kept within LEAD of the measured tool instead (the
  # servos' sag under a held part is about half that).
  # The horizontal and the vertical lead are bounded each on its own: bounded together,
  # the horizontal lag of a long carry used up the lead the target needs above the tool to
  # hold the sagging servos at the carry height, and the part sank 9 cm on its way.
  ahead = targets.pos + tool_action[:3] * mt - tool_pos
  across = ahead.at[2].set(0.0)
  kept = (tool_pos + across * jnp.minimum(1.0, LEAD / jnp.maximum(jnp.linalg.norm(across), 1e-9))
          + jnp.array([0.0, 0.0, 1.0]) * jnp.clip(ahead[2], -LEAD, LEAD))
  tool_action = jnp.where(phase >= CARRY, tool_action.at[:3].set(
      jnp.clip((kept - targets.pos) / mt, -1.0, 1.0)), tool_action)
  # A held part turns at CARRY_TURN of the top turning speed, half the CPU expert's
  # carry turn (experts/arm_motion.CARRY_TURN): at full speed it swung out of the grip,
  # and at the CPU's 0.3 more legs slipped (table, seed 2: 2 of 8 worlds completed
  # against 5).
  turn = tool_action[3:]
  turn_limit = jnp.where(phase >= CARRY, CARRY_TURN, 1.0)
  turn = turn * jnp.minimum(1.0, turn_limit / jnp.maximum(jnp.max(jnp.abs(turn)), 1e-9))
  tool_action = tool_action.at[3:].set(turn)
  gripper = jnp.where(phase >= CLOSE, 1.0, -1.0)
  connect = jnp.where(phase == INSERT, 1.0, -1.0)
  # Phase changes.
  at = lambda pos, rot: ((jnp.linalg.norm(tool_pos - pos) < POS_TOL)
                         & (jnp.linalg.norm(arm_control.rotation_vector(rot @ tool_rot.T))
                            < ROT_TOL))
  carry_err = part_err(above, goal_rot)
  advance = jnp.stack([
      at(hover, grasp_rot),
      at(grasp_pos, grasp_rot) | (steps > 40),
      steps >= CLOSE_STEPS,
      part_pos[m][2] > carry_z - 0.01,
      (horizontal < OVER_MATE[0]) & (carry_err[1] < OVER_MATE[1]),
      (carry_err[0] < CARRY_GATE[0]) & (carry_err[1] < CARRY_GATE[1]),
      jnp.bool_(False),
  ])[phase]
  next_phase = jnp.where(advance, jnp.minimum(phase + 1, INSERT), phase)
  # A part that is not in the hand after the fingers closed (they missed it, or it fell
  # out on the way) is taken again from where it lies, the grasp and twist chosen anew.
  lost = (phase >= LIFT) & (jnp.linalg.norm(part_pos[m] - tool_pos)
                            > jnp.linalg.norm(expert.grip_pos) + LOST)
  advance = advance | lost
  next_phase = jnp.where(lost, REACH, next_phase)
  grip_pos = rigid.apply(tool_rot.T, part_pos[m] - tool_pos)
  grip_rot = tool_rot.T @ part_rot[m]
  closing_done = (phase == CLOSE) & advance
  expert = expert._replace(
      phase=next_phase, steps=jnp.where(advance, 0, steps + 1), chosen=expert.chosen & ~lost,
      grip_pos=jnp.where(closing_done, grip_pos, expert.grip_pos),
      grip_rot=jnp.where(closing_done, grip_rot, expert.grip_rot))
  action = jnp.concatenate([tool_action, gripper[None], connect[None]])
  return action, expert


def batched_policy(env, plan_):
  """The expert over a batch of worlds: a function (ExpertState, arm_env.State), both with
  a leading world axis, -> (actions (worlds, action size), next ExpertState). Worlds
  that have not chosen their grasp and twist yet (a new episode) choose them first; the
  choice runs only in steps where some world needs it."""

  def pick(expert, state):
    grasp, twist, turn = jax.vmap(lambda s: choose(env, plan_, s))(state)
    keep = expert.chosen
    return expert._replace(chosen=jnp.ones_like(keep), grasp=jnp.where(keep, expert.grasp, grasp),
                           twist=jnp.where(keep, expert.twist, twist),
                           turn=jnp.where(keep, expert.turn, turn))

  def policy(expert, state):
    expert = jax.lax.cond(jnp.all(expert.chosen), lambda e, s: e, pick, expert, state)
    return jax.vmap(lambda e, s: act(env, plan_, e, s))(expert, state)

  return policy


def rollout(env, num_worlds, steps, seed=0, host_physics=False):
  """Runs the expert in `num_worlds` worlds for up to `steps` control steps, stopping when
  every world has ended its first episode. `host_physics`: step with
  env.step_batch_host (MuJoCo's C physics) instead of MJX.

  Returns:
    (success (worlds,) bool: the world completed its first episode, steps it took (0 if
    it did not), phase reached (worlds,) int).
  """
  plan_ = plan(env)
  with env.precision():
    policy = jax.jit(batched_policy(env, plan_))
    state = env.reset_batch(jax.random.PRNGKey(seed), num_worlds)
    expert = jax.vmap(lambda _: initial_state())(jnp.arange(num_worlds))
  done_at = np.zeros(num_worlds, dtype=int)
  ended = np.zeros(num_worlds, dtype=bool)
  phase = np.zeros(num_worlds, dtype=int)
  for step in range(1, steps + 1):
    with env.precision():
      action, expert = policy(expert, state)
    phase = np.where(ended, phase, np.asarray(expert.phase))
    state = (env.step_batch_host if host_physics else env.step_batch)(state, action)
    done = np.asarray(state.done)
    success = np.asarray(state.metrics["success"])
    done_at = np.where(~ended & done & success, step, done_at)
    ended |= done
    if ended.all():
      break
    # A world that ended starts its next episode; the expert starts over there too.
    with env.precision():
      fresh = jax.vmap(lambda _: initial_state())(jnp.arange(num_worlds))
      expert = jax.tree.map(lambda a, b: jnp.where(
          jnp.asarray(done).reshape((-1,) + (1,) * (a.ndim - 1)), a, b), fresh, expert)
  return done_at > 0, done_at, phase
