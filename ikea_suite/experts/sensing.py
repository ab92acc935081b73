"""What a scripted arm reads from privileged state: whether it holds a part (where the
part is relative to the tool, how far the fingers stand open, what they touch) and
whether a connector pair is aligned well within the task's thresholds."""

import numpy as np

from ikea_suite.experts import part_geometry
from ikea_suite.tasks import hollow_parts


def holding(physics, robot, arm, furniture, part):
  """The part is near the tool and squeezed: between fingers that stay apart, or touched
  by two fingers (the robot's own test), since a thin part can hold the fingers at their
  closed limit, opening 0. A hollow part (tasks/hollow_parts.py) is near the tool by its
  nearest wall: a drawer held by its front has its largest wall's middle 14 cm away."""
  part_pos = part_geometry.grasp_point(physics, furniture, part)
  tcp_pos, _ = robot.tcp_pose(physics, arm)
  spec = furniture.spec.parts[part]
  if hollow_parts.is_hollow(spec):
    pos, rot = part_geometry.part_pose(physics, furniture, part)
    walls = np.array([centre for centre, _, _ in hollow_parts.collision_boxes(spec)])
    part_pos = min(walls @ rot.T + pos, key=lambda wall: np.linalg.norm(wall - tcp_pos))
  bounds = spec.bounds
  if np.linalg.norm(part_pos - tcp_pos) >= 0.6 * np.max(bounds[1] - bounds[0]):
    return False
  return squeezed(physics, robot, arm, furniture, part)


def squeezed(physics, robot, arm, furniture, part):
  """The fingers stay apart on the closed hand, or two fingers touch the part (the robot's
  own test), wherever the part is held."""
  if robot.gripper_opening(physics, arm) > 0.05:
    return True
  return bool(robot.held_parts_by_tool(physics, [furniture.body_ids[part]])[arm, 0])


def attachable(task, physics, pair, tolerance):
  """The pair's distance and angles are within `tolerance` (e.g. 0.9) of the thresholds."""
  scores, t = task.alignment(physics), task.thresholds
  return bool(scores.distance[pair] < tolerance * t.distance
              and scores.up_cos[pair] > 1 - tolerance * (1 - t.up_cos)
              and scores.forward_cos[pair] > 1 - tolerance * (1 - t.forward_cos))


def touching(physics, furniture, part, others):
  """Whether `part` is in contact with any of the parts `others` (indices)."""
  model, data = physics.model, physics.data
  mine, theirs = furniture.body_ids[part], set(int(furniture.body_ids[p]) for p in others)
  for contact in data.contact[:data.ncon]:
    bodies = {int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2])}
    if mine in bodies and bodies & theirs - {mine}:
      return True
  return False
