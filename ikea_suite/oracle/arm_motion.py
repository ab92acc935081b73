"""Task-space motion helpers for scripted arms: tool orientations, pose-seeking actions and
pose errors, shared by the arm controller and the experts."""

import numpy as np

from ikea_suite import geometry


def tool_rotation(approach, closing, closing_local):
  """Tool rotation whose z axis is `approach` and whose finger axis (`closing_local`) is `closing`."""
  local_b = np.cross([0.0, 0.0, 1.0], closing_local)
  world_b = np.cross(approach, closing)
  local = np.column_stack([closing_local, local_b, [0.0, 0.0, 1.0]])
  world = np.column_stack([closing, world_b, approach])
  return world @ local.T


def pose_action(robot, physics, arm, goal_pos, goal_rot, gain=0.6, max_turn=1.0):
  """Task-space action entries (6) moving the measured tool towards a goal pose.

  Acting on the measured error each step (the robot integrates deltas into
  its target) removes steady-state tracking offsets, e.g. from a held load.
  """
  pos, rot = robot.tcp_pose(physics, arm)
  move = gain * (goal_pos - pos) / robot.max_translation
  turn = gain * geometry.mat_to_axis_angle(goal_rot @ rot.T) / robot.max_rotation
  move /= max(1.0, np.abs(move).max())
  turn *= max_turn / max(max_turn, np.abs(turn).max())
  return np.concatenate([move, turn])


def pose_error(robot, physics, arm, goal_pos, goal_rot):
  pos, rot = robot.tcp_pose(physics, arm)
  return np.linalg.norm(goal_pos - pos), np.linalg.norm(geometry.mat_to_axis_angle(goal_rot @ rot.T))


def arc_waypoint(base, pos, goal, max_turn=0.25, max_step=0.1):
  """A point from the tool position `pos` towards `goal` on an arc around the robot base
  `base` (at most `max_turn` rad and `max_step` m per call), so a carried part never
  sweeps across the base."""
  here, there = pos[:2] - base[:2], goal[:2] - base[:2]
  radius, target_radius = np.linalg.norm(here), np.linalg.norm(there)
  angle = np.arctan2(here[1], here[0])
  turn = np.angle(np.exp(1j * (np.arctan2(there[1], there[0]) - angle)))
  angle += np.clip(turn, -max_turn, max_turn)
  radius += np.clip(target_radius - radius, -max_step, max_step)
  z = pos[2] + np.clip(goal[2] - pos[2], -max_step, max_step)
  return np.array([base[0] + radius * np.cos(angle), base[1] + radius * np.sin(angle), z])
