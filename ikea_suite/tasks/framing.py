"""Where the arena's front camera looks: at the work area, filling most of the image.

The floor arena's cameras look at a fixed 2 m square around the origin, sized for
full-size furniture: from there an arm's parts at its work scale would be a few pixels
long at 84 px, and the Cursor's scattered parts (a ring up to 1.6 m out) fall partly
outside it. So the task places the front camera once, when it is built, on the work area's outline
(`work_area`): for an arm the band its parts are laid in (its reach zone, clipped to
the work table), for the Cursor the ring they are scattered in, with the assembled
furniture at its centre. The camera looks down at ELEVATION from the work area's front:
for an arm from across the work area, facing the robot, as FurnitureBench's front camera
faces its arm over the work table; for the Cursor from -y, as the floor arena's camera.
It stands where the outline fills FILL of a square image (a wider image shows more at
the sides). The top and side cameras stay where the arena puts them; the arms' wrist
cameras ride on the hand.
"""

import numpy as np

from ikea_suite.tasks import placement
from ikea_suite.tasks import planner

CAMERA = "front"
# Degrees the front camera looks down from the horizontal: high enough that the work
# area's depth (a metre for an arm's band) spreads over the image's height and the arm,
# at the far edge, hides little of it; low enough that the parts' sides and heights show.
ELEVATION = 60.0
# Share of the image's half-width (and half-height) the work area's outline may reach.
FILL = 0.9
# Points per arc of an arm's band outline and of the Cursor's ring.
_ARC_POINTS = 33


def loose_part_radius(spec):
  """Half the largest bounding diagonal (m) of the parts laid out around the one built
  onto: how far past its centre a part may reach, however it lies."""
  root = planner.root_part(spec)
  return max(0.5 * float(np.linalg.norm(p.bounds[1] - p.bounds[0]))
             for i, p in enumerate(spec.parts) if i != root or len(spec.parts) == 1)


def work_area(furniture, robot, support, spread):
  """World points (n, 3) outlining where the parts lie and are assembled.

  The placement bounds the parts' centres (a ring widens when crowded, a band spills a
  few parts outwards); the outline reaches a loose part's radius past those bounds, so
  the parts' ends stay in view.

  Args:
    furniture: the Furniture prop (its assembled size sets the Cursor's ring).
    robot: the robot entity; its `reach_zone` (None for the Cursor) bounds an arm's band.
    support: the arenas.support.Support the parts lie on (a bounded one clips the band).
    spread: the resolved `spread` option: the width (m) of the Cursor's ring.
  Returns:
    Points on the support's surface, plus the assembled furniture's top at its centre
    for the Cursor.
  """
  zone = robot.reach_zone
  part = loose_part_radius(furniture.spec)
  if zone is None:   # centres lie out to the ring's outer edge plus their own radius
    radius = (placement.assembled_radius(furniture.spec) + placement.CLEARANCE + spread
              + 2 * part)
    angles = np.linspace(0.0, 2 * np.pi, _ARC_POINTS, endpoint=False)
    ring = np.stack([radius * np.cos(angles), radius * np.sin(angles),
                     np.full_like(angles, support.height)], axis=1)
    height = max(p.assembled_corners()[:, 2].max() for p in furniture.spec.parts)
    return np.vstack([ring, [[0.0, 0.0, support.height + height]]])
  bearings = np.linspace(-zone.sector, zone.sector, _ARC_POINTS)
  outer = np.full_like(bearings, zone.reach)
  if zone.side_reach is not None:
    side_bearing, side_distance = zone.side_reach
    outer = np.where(np.abs(bearings) > side_bearing, side_distance, outer)
  outer = outer + part
  heading = np.arctan2(zone.base_rot[1, 0], zone.base_rot[0, 0])
  points = []
  for distances in (outer, np.full_like(bearings, max(zone.min_distance - part, 0.0))):
    angle = heading + bearings
    points.append(np.stack([zone.base_xy[0] + distances * np.cos(angle),
                            zone.base_xy[1] + distances * np.sin(angle)], axis=1))
  xy = np.vstack(points)
  if support.bounded:   # parts lie on the table: clip the band to its top
    local = np.clip(support.local_xy(xy), -np.asarray(support.half_size),
                    np.asarray(support.half_size))
    c, s = np.cos(support.yaw), np.sin(support.yaw)
    xy = local @ np.array([[c, s], [-s, c]]) + np.asarray(support.centre)
  return np.hstack([xy, np.full((len(xy), 1), support.height)])


def view_direction(robot):
  """Unit vector (3,) from the work area towards the front camera: horizontally along an
  arm's heading (across the work area from its base), -y for the Cursor; ELEVATION up."""
  zone = robot.reach_zone
  if zone is None:
    horizontal = np.array([0.0, -1.0])
  else:
    horizontal = zone.base_rot[:2, 0] / np.linalg.norm(zone.base_rot[:2, 0])
  up = np.radians(ELEVATION)
  return np.array([*(np.cos(up) * horizontal), np.sin(up)])


def _camera_axes(direction):
  """(right, up, forward) of a camera looking along -direction, its x axis horizontal
  (as MuJoCo orients a camera that tracks a target body)."""
  forward = -direction
  right = np.cross(forward, [0.0, 0.0, 1.0])
  right /= np.linalg.norm(right)
  return right, np.cross(right, forward), forward


def _extent(points, position, axes):
  """(low, high) tangents (2,) of `points` seen from `position`: x right, y up."""
  right, up, forward = axes
  offset = points - position
  depth = offset @ forward
  tangents = np.stack([offset @ right, offset @ up], axis=1) / depth[:, None]
  return tangents.min(axis=0), tangents.max(axis=0), depth.min()


def look_at(points, direction, fovy, fill=FILL):
  """A camera pose that sees `points` within `fill` of a square image, centred.

  Args:
    points: world points (n, 3) to frame.
    direction: unit vector (3,) from the points towards the camera.
    fovy: the camera's vertical field of view (degrees).
    fill: share of the half-image the points may reach.
  Returns:
    (position, target): the camera's world position and the point it looks at.
  """
  axes = _camera_axes(direction)
  right, up, _ = axes
  limit = fill * np.tan(np.radians(fovy) / 2)
  centre = points.mean(axis=0)
  for _ in range(4):   # fit the distance, then shift the view to centre the points on it
    low_d, high_d = 0.05, 50.0
    for _ in range(50):
      distance = 0.5 * (low_d + high_d)
      low, high, nearest = _extent(points, centre + distance * direction, axes)
      fits = nearest > 0 and max(-low.min(), high.max()) <= limit
      low_d, high_d = (low_d, distance) if fits else (distance, high_d)
    low, high, _ = _extent(points, centre + high_d * direction, axes)
    middle = 0.5 * (low + high)
    centre = centre + high_d * (middle[0] * right + middle[1] * up)
  return centre + high_d * direction, centre


def frame_front_camera(arena, furniture, robot, spread):
  """Moves the arena's front camera (and the body it tracks) to frame the work area.

  Args:
    arena: the arena; its `cameras[CAMERA]` tracks a target body (arenas/floor.py).
    furniture, robot, spread: as work_area().
  """
  camera = arena.cameras[CAMERA]
  position, target = look_at(work_area(furniture, robot, arena.support, spread),
                             view_direction(robot), float(camera.fovy))
  camera.pos = position
  camera.target.pos = target
