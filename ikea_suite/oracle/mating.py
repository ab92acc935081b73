"""Where a scripted arm takes the part it holds: the mate and twist it reaches best, and
the tool pose that puts the part there (privileged state; nothing moves)."""

import numpy as np

from ikea_suite.oracle import targets
from ikea_suite.tasks import planner

_ANY_TWIST_GRID = np.radians(np.arange(0, 360, 45))


def reach_cost(robot, physics, arm, goal_pos, goal_rot):
  """IK miss, joint travel and joints near their limits of a tool pose: lower is easier."""
  miss, margin, travel = robot.reach_check(physics, arm, goal_pos, goal_rot)
  return miss + 0.02 * travel + np.maximum(0.0, 0.3 - margin).sum()


def tool_goal_for_part(env, arm, part, part_goal_pos, part_goal_rot, grip=None):
  """Tool pose that puts the held part at the goal; `grip` (tool pose in the part frame)
  defaults to the measured one."""
  if grip is None:
    physics, robot = env.physics, env.task.robot
    part_pos, part_rot = targets.part_pose(physics, env.task.furniture, part)
    tcp_pos, tcp_rot = robot.tcp_pose(physics, arm)
    grip = part_rot.T @ (tcp_pos - part_pos), part_rot.T @ tcp_rot
  grip_pos, grip_rot = grip
  return part_goal_pos + part_goal_rot @ grip_pos, part_goal_rot @ grip_rot


def plan_mating(env, arm, moving, approach, failed_plans=(), grip=None):
  """(score, pair, twist) for the held part: the mate and twist the arm reaches best.

  Each candidate's pre-insertion tool pose (`approach` m back from the mate along its
  side) is solved by IK; misses, joint travel, joints near their limits and a wrist
  cramped beside the base cost. (pair, twist) in `failed_plans` are skipped. None when
  no mate is open.
  """
  task, physics, robot = env.task, env.physics, env.task.robot
  table, state = task.furniture.connectors, task.state
  groups = state.group_labels()
  base_pos, _ = robot.base_pose
  part_xy = task.furniture.part_poses(physics)[0][moving][:2]
  centre, _ = targets.assembly_circle(physics, task.furniture, task.root_part)
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
      part_pos, part_rot, side = targets.mated_part_pose(
          physics, task.furniture, pair, moving, twist)
      goal_pos, goal_rot = tool_goal_for_part(
          env, arm, moving, part_pos + approach * side, part_rot, grip)
      # A wrist folded in beside the base is cramped: the differential IK stalls there.
      wrist = goal_pos - 0.25 * goal_rot[:, 2]
      cramped = max(0.0, 0.45 - np.linalg.norm(wrist[:2] - base_pos[:2]))
      # A hand reaching in from the middle of the assembly strikes the parts already on
      # it and drags the assembly along: come in from outside.
      inward = max(0.0, np.linalg.norm(goal_pos[:2] - centre) - np.linalg.norm(wrist[:2] - centre))
      score = (reach_cost(robot, physics, arm, goal_pos, goal_rot) + 2.0 * cramped
               + 2.0 * inward + 0.3 * np.linalg.norm(goal_pos[:2] - part_xy))   # mates nearby
      if best is None or score < best[0]:
        best = (score, int(pair), float(twist))
  return best
