"""The one definition of mating: which connector types pair up, and when two frames coincide.

Every tool asks here: the model loader (mates present and coinciding in the
assembled pose), the furniture spec and connector table (candidate pairs),
the curriculum placement (pairs joined in the design), the model writer (the
welds it writes) and the task (loops that close after a connection).

A connector is anything with `type`, `mates` and `part` attributes. Frames
are world (or any common frame) position (3,) and rotation (3, 3); the
rotation's z axis is up and its x axis forward.
"""

import numpy as np

# In the assembled design two mating frames coincide to within these: 1 mm and
# about 2.6 degrees (cos 0.999). Models are written to 1e-6 m, so this only
# absorbs rounding and the quaternion normalisation of the file.
DESIGN_POSITION_TOL = 1e-3
DESIGN_ANGLE_COS = 0.999


def types_mate(a, b):
  """Whether connectors a and b on different parts are of mating types (both ways)."""
  return a.part != b.part and a.mates == b.type and b.mates == a.type


def frames_coincide(pos_a, rot_a, pos_b, rot_b, twists, position_tol=DESIGN_POSITION_TOL,
                    angle_cos=DESIGN_ANGLE_COS):
  """Whether frame b sits on frame a: same point, same up axis, forward turned by one of
  `twists` (radians about up; empty means any twist)."""
  if np.linalg.norm(np.subtract(pos_a, pos_b)) > position_tol:
    return False
  if rot_a[:, 2] @ rot_b[:, 2] < angle_cos:
    return False
  fwd_b = rot_b[:, 0]
  return not len(twists) or any(
      fwd_b @ (np.cos(t) * rot_a[:, 0] + np.sin(t) * rot_a[:, 1]) > angle_cos for t in twists)


def world_frame(part_pos, part_rot, local_pos, local_rot):
  return part_pos + part_rot @ local_pos, part_rot @ local_rot


def coinciding_connector_pairs(connectors, part_poses):
  """(a, b) index pairs, a < b, of mating connectors whose frames coincide, given
  `part_poses`: part name -> (position, rotation) and connectors with pos/rot in their
  part's frame and `twists`."""
  frames = [world_frame(*part_poses[c.part], np.asarray(c.pos), np.asarray(c.rot))
            for c in connectors]
  return [(i, j) for i, a in enumerate(connectors) for j in range(i + 1, len(connectors))
          if types_mate(a, connectors[j])
          and frames_coincide(*frames[i], *frames[j], a.twists)]
