"""Where a scripted arm takes the part it holds: the mate and twist it reaches best, and
the tool pose that puts the part there (privileged state; nothing moves)."""

import numpy as np

from ikea_suite.experts import arm_motion
from ikea_suite.experts import part_geometry
from ikea_suite.tasks import planner

_ANY_TWIST_GRID = np.radians(np.arange(0, 360, 45))


def winds_past_a_turn(robot, arm):
  """Whether a joint of the arm turns more than a full turn between its limits (the
  Sawyer's wrist, +-4.71 rad): a tool pose then has two angles of that joint, and which
  one the servo ends at depends on its path, which a converged IK solve does not follow."""
  low, high = robot.ik.limits
  index = robot.ik.qpos_index[robot.ik_joint_indices(arm)]
  span = high[index] - low[index]
  return bool(np.any(np.isfinite(span) & (span > 2.0 * np.pi)))


# A converged IK solve that misses by more than this (m) may have stopped in a local
# minimum: the servo's own path is then tried too. From a racked trestle's grasp the IK
# missed the far mate by 12 cm, four joints at their limits, where the servo's path
# reached it (Panda, desk_trestle_w120_white).
PATH_CHECK_MISS = 0.01


def reach_cost(robot, physics, arm, goal_pos, goal_rot, start=None, servo=None, path_end=None):
  """IK miss, joint travel and joints near their limits of a tool pose, the IK solved
  from the present joints or `start` (an arm_qpos vector): lower is easier.

  With `servo` (control step in s, max_turn) and an arm that winds_past_a_turn, the IK
  starts where the servo's own path from there stops (arm_motion.servo_path_end): from
  home the IK reached a racked trestle's mate turning the wrist back from near its
  limit, where the carry drove it into that limit and stalled 15 cm short (Sawyer,
  desk_trestle_w120_white). For other arms the path is tried where the
  converged IK misses by more than PATH_CHECK_MISS, and the nearer of the two counts.
  `path_end`: where that path stops (its joints), when the caller has replayed it already.
  """
  def along_the_path():
    begin = robot.arm_qpos(physics) if start is None else start
    end = path_end if path_end is not None else arm_motion.servo_path_end(
        robot, arm, begin, goal_pos, goal_rot, *servo)[0]
    miss, margin, travel = robot.reach_check(physics, arm, goal_pos, goal_rot, start=end)
    return miss, margin, travel + float(np.linalg.norm(end - begin))

  if servo is not None and winds_past_a_turn(robot, arm):
    miss, margin, travel = along_the_path()
  else:
    miss, margin, travel = robot.reach_check(physics, arm, goal_pos, goal_rot, start=start)
    if servo is not None and miss > PATH_CHECK_MISS:
      miss, margin, travel = min((miss, margin, travel), along_the_path(), key=lambda r: r[0])
  return miss + 0.02 * travel + np.maximum(0.0, 0.3 - margin).sum()


def tool_goal_for_part(env, arm, part, part_goal_pos, part_goal_rot, grip=None):
  """Tool pose that puts the held part at the goal; `grip` (tool pose in the part frame)
  defaults to the measured one."""
  if grip is None:
    physics, robot = env.physics, env.task.robot
    part_pos, part_rot = part_geometry.part_pose(physics, env.task.furniture, part)
    tcp_pos, tcp_rot = robot.tcp_pose(physics, arm)
    grip = part_rot.T @ (tcp_pos - part_pos), part_rot.T @ tcp_rot
  grip_pos, grip_rot = grip
  return part_goal_pos + part_goal_rot @ grip_pos, part_goal_rot @ grip_rot


def _other_connectors(table, moving, pair):
  """Indices of `moving`'s connectors other than the pair's."""
  mine = np.flatnonzero(table.part == moving)
  return mine[(mine != table.pair_a[pair]) & (mine != table.pair_b[pair])]


def mate_pose(env, pair, moving, twist):
  """part_geometry.mated_part_pose of `moving` for the pair at `twist`: (position, rotation, side
  to approach from). A part that bridges the assembly there (another of its connectors
  then meets one of the assembly's too, as a bench's stretcher meets both ends) comes
  in from above: along its own axis, from the side, it would run through the far end."""
  task, physics = env.task, env.physics
  part_pos, part_rot, side = part_geometry.mated_part_pose(physics, task.furniture, pair,
                                                           moving, twist)
  table = task.furniture.connectors
  groups = task.state.group_labels()
  mine = _other_connectors(table, moving, pair)
  if mine.size:
    cpos, _ = table.world_frames(*task.furniture.part_poses(physics))
    built = np.flatnonzero(groups[table.part] == groups[task.root_part])
    there = part_pos + table.local_pos[mine] @ part_rot.T
    gaps = np.linalg.norm(there[:, None] - cpos[built][None], axis=-1)
    if built.size and gaps.min() < task.thresholds.distance:
      side = np.array([0.0, 0.0, 1.0])
  return part_pos, part_rot, side


def off_design(env, moving, part_pos, part_rot, pair):
  """How far (m) the held part's other connectors (all but the pair's) would lie, with the
  part at (part_pos, part_rot), from where the assembled design has connectors of their
  types (laid out from the root as it lies now): 0 when the part sits as the design has
  it, or as an identical part does. A bench end mated on its seat slot the wrong way
  round (both twists attach) turns its stretcher slot outwards, and the stretcher can
  then never go in."""
  task, physics = env.task, env.physics
  furniture, table = task.furniture, task.furniture.connectors
  mine = _other_connectors(table, moving, pair)
  if not mine.size:
    return 0.0
  rotation, translation = part_geometry.design_to_world(physics, furniture, task.root_part)
  parts = furniture.spec.parts
  designed = np.array([rotation @ (parts[p].rot @ local + parts[p].pos) + translation
                       for p, local in zip(table.part, table.local_pos)])
  types = np.array(table.types)
  return max(float(np.linalg.norm(designed[types == types[c]] - (
      part_pos + part_rot @ table.local_pos[c]), axis=1).min()) for c in mine)


def hand_in_the_way(env, arm, tool_pos, tool_rot):
  """How far (m, summed over parts) the hand, from the tool centre back to the wrist
  (arm_motion.WRIST_BACK along the tool axis) and as wide as it reaches sideways
  (arm_motion.hand_reach), runs into the parts already joined to the root (their
  collision boxes), with the tool at (tool_pos, tool_rot); 0 for a tool within 60
  degrees of vertical, whose hand stays above what it mates. A hand reaching in over
  the middle of the assembly strikes the parts standing there and drags it along: a
  Panda taking a chair's near corner, its tool pointing back at the base, crossed the
  seat, and its forearm pushed the two far legs 0.4 m."""
  physics, task, robot = env.physics, env.task, env.task.robot
  back = -tool_rot[:, 2]
  if np.linalg.norm(back[:2]) < 0.5:
    return 0.0
  side = np.array([-back[1], back[0], 0.0]) / np.linalg.norm(back[:2])
  half_width = max(arm_motion.hand_reach(robot, physics, arm, tool_rot, side),
                   arm_motion.hand_reach(robot, physics, arm, tool_rot, -side))
  hand = tool_pos + np.linspace(0.0, arm_motion.WRIST_BACK, 11)[:, None] * back
  positions, rotations = task.furniture.part_poses(physics)
  overlap = 0.0
  for part in part_geometry.root_group(task):
    if part == task.root_part:
      continue
    low, high = task.furniture.spec.parts[part].bounds
    local = (hand - positions[part]) @ rotations[part]
    gap = np.linalg.norm(local - np.clip(local, low, high), axis=1).min()
    overlap += max(0.0, half_width - gap)
  return overlap


def in_a_later_carry(env, moving, pair, part_pos, part_rot, carry_top):
  """Whether `moving`, standing at (part_pos, part_rot) for `pair`, would stand on the arc
  another racked part takes to one of its open mates (arm_motion.arc_waypoint, from where
  it lies), so tall that the other, hanging below the tool, would pass over it only with
  the tool above `carry_top` (the nominal carry height). The Panda reaches 0.70 m, not the
  0.75 m a half-scale trestle needs over the one standing before it; the first trestle
  stood at the mate nearer the rack, the second struck it on its way to the far one and
  fell (desk_trestle_w120_white, table_trestle_l120_white)."""
  task, physics, robot = env.task, env.physics, env.task.robot
  furniture, table = task.furniture, task.furniture.connectors
  groups = task.state.group_labels()
  built = groups[task.root_part]
  others = [p for p in task.initializer.racked_parts if p != moving and groups[p] != built]
  if not others:   # stools and tables: nothing racked is still to come
    return False
  mine = part_geometry.part_corners(furniture, moving, part_pos, part_rot)
  positions, rotations = furniture.part_poses(physics)
  cpos, _ = table.world_frames(positions, rotations)
  base, base_rot = robot.base_pose
  heading = np.arctan2(base_rot[1, 0], base_rot[0, 0])
  taken = (table.pair_a[pair], table.pair_b[pair])
  for other in others:
    theirs = part_geometry.part_corners(furniture, other, positions[other], rotations[other])
    if mine[:, 2].max() + np.ptp(theirs[:, 2]) + 0.03 <= carry_top:
      continue
    near = (np.linalg.norm(mine[:, :2] - part_pos[:2], axis=1).max()
            + np.linalg.norm(theirs[:, :2] - positions[other][:2], axis=1).max())
    for open_pair in np.flatnonzero(planner.open_pairs(table, task.state)):
      for fixed, loose in ((table.pair_a[open_pair], table.pair_b[open_pair]),
                           (table.pair_b[open_pair], table.pair_a[open_pair])):
        if (table.part[loose] != other or groups[table.part[fixed]] != built
            or fixed in taken):
          continue
        point, goal = positions[other].copy(), cpos[fixed].copy()
        point[2] = goal[2] = 0.0
        for _ in range(40):   # the arc, step by step, until it arrives
          if np.linalg.norm(point[:2] - part_pos[:2]) < near:
            return True
          if np.linalg.norm(point[:2] - goal[:2]) < 0.01:
            break
          point = arm_motion.arc_waypoint(base, point, goal, heading=heading)
  return False


def plan_mating(env, arm, moving, approach, failed_plans=(), grip=None, start=None,
                carry_top=None):
  """(score, pair, twist) for the held part: the mate and twist the arm reaches best.

  Each candidate's pre-insertion tool pose (`approach` m back from the mate along its
  side) is solved by IK from `start` (the present joints by default), along the carry's
  servo path (reach_cost); misses, joint travel, joints near their limits, a wrist
  cramped beside the base and a hand that runs into the parts already standing on the
  root (hand_in_the_way: a centimetre of it weighs as 0.1 of reach cost, so a hand
  from outside wins wherever the arm reaches it) cost. (pair, twist) in `failed_plans`
  and mates off the design (off_design) are skipped: a trestle that attached facing
  out, once the twist facing in had stalled, left its stretcher no slot (Panda,
  desk_trestle_w100_birch); with no other mate left the part is
  set down and taken the other way. With `carry_top` (the nominal carry height), a mate
  where the part would stand in a later racked part's carry, too tall to be passed over
  (in_a_later_carry), costs 1, and so does a mate on the other side for a part from one
  of a two-arm robot's racks (part_geometry.nearer_another_rack). None when no mate is
  open.
  """
  task, physics, robot = env.task, env.physics, env.task.robot
  table, state = task.furniture.connectors, task.state
  groups = state.group_labels()
  base_pos, _ = robot.base_pose
  part_xy = task.furniture.part_poses(physics)[0][moving][:2]
  # Mates nearby first; from the rack, the farthest first (see next_part.nearest_open_job).
  nearby = -0.3 if moving in task.initializer.racked_parts else 0.3
  best = None
  for pair in np.flatnonzero(planner.open_pairs(table, state)):
    parts = {int(table.part[table.pair_a[pair]]), int(table.part[table.pair_b[pair]])}
    if moving not in parts or groups[(parts - {moving}).pop()] != groups[task.root_part]:
      continue
    twists = _ANY_TWIST_GRID if table.any_twist[pair] else (
        table.twist_angles[pair][table.twist_valid[pair]])
    for twist in twists:
      if (int(pair), float(twist)) in failed_plans:
        continue
      part_pos, part_rot, side = mate_pose(env, pair, moving, twist)
      if off_design(env, moving, part_pos, part_rot, pair) > task.thresholds.distance:
        continue
      goal_pos, goal_rot = tool_goal_for_part(
          env, arm, moving, part_pos + approach * side, part_rot, grip)
      cramped = arm_motion.cramped(base_pos, goal_pos, goal_rot[:, 2])
      in_the_way = hand_in_the_way(env, arm, goal_pos, goal_rot)
      score = (reach_cost(robot, physics, arm, goal_pos, goal_rot, start, servo=(
          env.control_timestep(), arm_motion.CARRY_TURN)) + 2.0 * cramped
               + 10.0 * in_the_way + nearby * np.linalg.norm(goal_pos[:2] - part_xy)
               + 1.0 * (carry_top is not None and in_a_later_carry(
                   env, moving, pair, part_pos, part_rot, carry_top))
               + 1.0 * part_geometry.nearer_another_rack(task, physics, moving, part_pos))
      if best is None or score < best[0]:
        best = (score, int(pair), float(twist))
  return best


def choose_grasp_sign(env, arm, moving, grasp_pose, hover, approach, failed_plans=(),
                      stalled_grasps=(), carry_top=None):
  """Which of the two symmetric top-down grasps of `moving` (grasp_pose(part, sign) -> tool
  pose) the wrist reaches best, `hover` m above it, and leaves the easier mating; a
  (part, sign) in `stalled_grasps` goes last.

  The mating is judged from where the servo's path (arm_motion.servo_path_end) stops
  above the grasp, not from the present pose: a wrist that took a racked trestle near
  the end of its range turned into its limit on the way to the mate, which from home
  the IK reached turning it the other way (Sawyer, desk_trestle_w100_birch and
  w120_white); from home the IK reached a trestle's far mate that from the grasp
  neither it nor the servo reached, the last joint at its limit 16 cm short, and the
  trestle went to the near mate, where the next one's carry struck it (Panda,
  desk_trestle_w120_white)."""
  physics, furniture, robot = env.physics, env.task.furniture, env.task.robot
  part_pos, part_rot = part_geometry.part_pose(physics, furniture, moving)
  best = None
  for sign in (1.0, -1.0):
    point, rot = grasp_pose(moving, sign)
    grip = (part_rot.T @ (point - part_pos), part_rot.T @ rot)
    above, dt = point + [0.0, 0.0, hover], env.control_timestep()
    start = arm_motion.servo_path_end(robot, arm, robot.arm_qpos(physics), above, rot, dt)[0]
    plan = plan_mating(env, arm, moving, approach, failed_plans, grip, start, carry_top)
    # A grasp the last wrist joint cannot turn to stalls the reach; after a stall the other
    # grasp goes first (the Panda's last joint met its limit again from the same pose).
    score = reach_cost(robot, physics, arm, above, rot, servo=(dt, 1.0), path_end=start) + (
        10.0 if plan is None else plan[0]) + 5.0 * ((moving, sign) in stalled_grasps)
    if best is None or score < best[0]:
      best = (score, sign)
  return best[1]
