"""The surface parts rest on at the start of an episode: its height and, for a table, its extent.

An arena states its `support` so the task can lay parts on it and the scripted
experts can measure heights from it; the floor is an unbounded support at z = 0.
"""

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True)
class Support:
  """A horizontal rectangle (or the unbounded floor) that parts rest on.

  Attributes:
    height: world z of the surface (m).
    centre: world xy (2,) of the rectangle's centre (m); the floor's is the origin.
    yaw: rotation of the rectangle about world z (rad).
    half_size: half extents (2,) along the rectangle's own x and y (m); None: unbounded.
  """
  height: float = 0.0
  centre: tuple = (0.0, 0.0)
  yaw: float = 0.0
  half_size: tuple | None = None

  @property
  def bounded(self):
    return self.half_size is not None

  @property
  def origin(self):
    """World point (3,) where the surface's assembly area is: its centre, on the surface."""
    return np.array([self.centre[0], self.centre[1], self.height])

  def local_xy(self, xy):
    """World xy (..., 2) in the rectangle's frame."""
    c, s = np.cos(self.yaw), np.sin(self.yaw)
    d = np.asarray(xy, dtype=float) - np.asarray(self.centre, dtype=float)
    return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)

  def contains(self, xy, radius=0.0):
    """Whether a disc of `radius` (m) about world `xy` lies wholly on the surface."""
    if not self.bounded:
      return True
    room = np.asarray(self.half_size, dtype=float) - radius
    return bool((room > 0).all() and (np.abs(self.local_xy(xy)) <= room).all())

  def farthest_from(self, xy):
    """Distance (m) from world `xy` to the surface's farthest corner; inf when unbounded."""
    if not self.bounded:
      return np.inf
    hx, hy = self.half_size
    corners = np.array([[hx, hy], [hx, -hy], [-hx, hy], [-hx, -hy]])
    c, s = np.cos(self.yaw), np.sin(self.yaw)
    world = corners @ np.array([[c, s], [-s, c]]) + np.asarray(self.centre, dtype=float)
    return float(np.linalg.norm(world - np.asarray(xy, dtype=float), axis=1).max())


FLOOR = Support()
