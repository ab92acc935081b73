"""Target poses the oracle drives parts to, computed from privileged state."""

import numpy as np

from ikea_suite import geometry

_ANY_TWIST_GRID = np.radians(np.arange(0, 360, 15))


def part_pose(physics, furniture, part):
  body = furniture.body_ids[part]
  return physics.data.xpos[body].copy(), physics.data.xmat[body].reshape(3, 3).copy()


def grasp_point(physics, furniture, part):
  """World centre of the part's largest collision geom: a point a cursor can enclose."""
  model, data = physics.model, physics.data
  body = furniture.body_ids[part]
  geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == body
           and (model.geom_contype[g] or model.geom_conaffinity[g])]
  g = max(geoms, key=lambda g: np.prod(model.geom_aabb[g, 3:]))
  return data.geom_xpos[g] + data.geom_xmat[g].reshape(3, 3) @ model.geom_aabb[g, :3]


def mating_target(physics, furniture, pair, moving_part):
  """Pose of `moving_part` that makes the pair's connector frames coincide.

  Among the allowed twists the one nearest the part's current orientation is
  chosen. Returns (position, rotation, unit vector from the connector towards
  the moving part's side, which is the direction to approach from).
  """
  table = furniture.connectors
  con_a, con_b = table.pair_a[pair], table.pair_b[pair]
  moving_con, fixed_con = (con_a, con_b) if table.part[con_a] == moving_part else (con_b, con_a)
  positions, rotations = furniture.part_poses(physics)
  cpos, crot = table.world_frames(positions, rotations)
  twists = _ANY_TWIST_GRID if table.any_twist[pair] else table.twist_angles[pair][table.twist_valid[pair]]
  # Aligned means R_b = R_a Rz(t): the moving frame is R_fixed Rz(-t) if it is a, Rz(t) if b.
  sign = -1.0 if moving_con == con_a else 1.0
  current = rotations[moving_part]
  best = None
  for t in twists:
    rot = crot[fixed_con] @ geometry.rot_z(sign * t) @ table.local_rot[moving_con].T
    angle = np.linalg.norm(geometry.mat_to_axis_angle(rot @ current.T))
    if best is None or angle < best[0]:
      best = (angle, rot)
  rot = best[1]
  pos = cpos[fixed_con] - rot @ table.local_pos[moving_con]
  side = pos - cpos[fixed_con]
  norm = np.linalg.norm(side)
  side = side / norm if norm > 1e-6 else crot[fixed_con][:, 2]
  return pos, rot, side
