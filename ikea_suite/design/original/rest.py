"""The side an assembled furniture rests on, for files whose upright assembly cannot stand.

Some of the original's models are not free-standing as written: shelf_ivar_0678 is
one 27 x 18 mm column carrying five boxes on one side (a wall-mounted unit), so its
centre of mass lies outside the footprint it stands on and it topples. Such an
assembly is set down on the face of its convex hull on which it rests most
stably instead (the centre of mass furthest inside that face's support polygon),
as a real one would be laid on the floor. Assemblies that stand upright are not
turned.
"""

import numpy as np
import trimesh

from ikea_suite import geometry

# Hull points within this height of a resting plane touch the floor.
_CONTACT_BAND = 0.001   # m
# Hull faces turned at most this far from the floor still stand the assembly upright:
# chair_ingolf_0650's back legs end 2 mm above its front legs, so upright it rests on the
# front legs alone (its centre of mass outside them) and would rock back 0.5 degrees onto
# all four, where a real chair stands.
NEAR_UPRIGHT = np.radians(5.0)


def _cross(u, v):
  return u[0] * v[1] - u[1] * v[0]


def _hull_2d(points):
  """Counter-clockwise convex hull of 2D points (Andrew's monotone chain)."""
  pts = sorted(set(map(tuple, np.round(points, 9))))
  if len(pts) < 3:
    return np.array(pts)
  def half(seq):
    out = []
    for p in seq:
      while len(out) >= 2 and _cross(np.subtract(out[-1], out[-2]), np.subtract(p, out[-2])) <= 0:
        out.pop()
      out.append(p)
    return out[:-1]
  return np.array(half(pts) + half(reversed(pts)))


def support_margin(points_xy, com_xy):
  """Signed distance (m) from `com_xy` to the edge of the convex hull of `points_xy`:
  positive inside (how far the centre of mass may shift before the body tips), negative
  outside or when the points span no area."""
  hull = _hull_2d(points_xy)
  if len(hull) < 3:
    return -np.inf
  margin = np.inf
  for a, b in zip(hull, np.roll(hull, -1, axis=0)):
    edge = b - a
    # Counter-clockwise hull: the inside lies to the left of every edge.
    margin = min(margin, _cross(edge, com_xy - a) / np.linalg.norm(edge))
  return float(margin)


def _upright_margin(points, com):
  touching = points[points[:, 2] < points[:, 2].min() + _CONTACT_BAND]
  return support_margin(touching[:, :2], com[:2])


def _turn_onto(normal):
  """A rotation taking the outward unit `normal` of a resting face to -z (the floor)."""
  down = np.array([0.0, 0.0, -1.0])
  axis = np.cross(normal, down)
  sin, cos = np.linalg.norm(axis), float(normal @ down)
  if sin < 1e-9:
    return np.eye(3) if cos > 0 else np.diag([1.0, -1.0, -1.0])
  return geometry.axis_angle_to_mat(axis / sin * np.arctan2(sin, cos))


def resting_turn(points, com):
  """(rotation, margin before, margin after) that sets an assembly down stably.

  `points` bound the assembly's collision geometry and `com` is its centre of mass,
  both in the assembled frame (z up). The rotation is the identity when the assembly
  stands upright (the centre of mass over its footprint); otherwise it turns onto the
  floor the hull face with the largest support margin among those within NEAR_UPRIGHT
  of the floor, or, when none of them holds the centre of mass, among all faces.
  """
  points, com = np.asarray(points, float), np.asarray(com, float)
  upright = _upright_margin(points, com)
  if upright > 0:
    return np.eye(3), upright, upright
  hull = trimesh.convex.convex_hull(points)
  near, anywhere = (upright, np.eye(3)), (upright, np.eye(3))
  for normal in np.unique(np.round(hull.face_normals, 6), axis=0):
    normal = normal / np.linalg.norm(normal)
    turn = _turn_onto(normal)
    margin = _upright_margin(points @ turn.T, turn @ com)
    if margin > anywhere[0] + 1e-6:
      anywhere = (margin, turn)
    if -normal[2] >= np.cos(NEAR_UPRIGHT) and margin > near[0] + 1e-6:
      near = (margin, turn)
  best = near if near[0] > 0 else anywhere
  return best[1], upright, best[0]
