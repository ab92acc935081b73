"""Rounded visual shapes for fact-sheet bodies, fitted to the bounds of their mesh pieces.

A fact sheet gives each coloured mesh piece of a link only as an axis-aligned
box in the link's frame (`visual_mesh_bounds`). Drawn as boxes, an arm looks
like a stack of crates; so each piece becomes shapes that fill its box the
way the real part does:

- a plate (one thin side): a disc when square; an oblong plate that the sheet
  also traces with collision boxes (a finger and its knuckle) is drawn as
  those boxes, rounded; any other a rounded block;
- a piece that a joint axis runs through: the joint's housing, the widest
  drum round the axis that fits the box, plus a tube of the same radius where
  the piece reaches well beyond it (the links of these arms are housings and
  tubes);
- a piece with no joint: a tube when it is a rod, else a rounded block (a
  moulded cover: torso, head, hand, finger).

Every shape is a superellipsoid (`Shape`): drums, tubes and blocks differ
only in their exponents. Callers draw each as MuJoCo's built-in `supersphere`
mesh. Drawn with MuJoCo's own cylinders and capsules instead, a software
rendered (llvmpipe) 320 x 240 frame of Baxter took about twice as long as with
the boxes; with these meshes it takes about as long.
Shapes stay inside their piece's box. Sizes are metres in the body frame.
"""

import dataclasses

import numpy as np

# Pieces whose largest extent is below this (m) are screws and logos: skipped.
MIN_EXTENT = 0.03
# Decals are listed with zero thickness; they are drawn this thick (m).
_MIN_THICKNESS = 0.004
# Most pieces drawn per link, largest first: keeps rendering cheap.
MAX_PER_BODY = 4
# Ratios of a piece's sorted extents (thin <= middle <= long), picked by eye on
# renders of the arms (docs/robots_work_area.png):
_FLAT = 0.4        # thin / middle below this: a plate
_SQUARE = 1.25     # a plate whose sides differ less than this: a disc
_ROD = 3.0         # long / middle above this: a rod
# Two pieces whose boxes overlap this much (intersection over union) are one
# shell in two colours (the sheets list livery and trim with nearly equal
# bounds): drawing both z-fights, so only the more colourful is kept.
_SAME_SHELL = 0.6
# A joint axis passing this close (m) outside a piece's box still counts as housed by it.
_ANCHOR_MARGIN = 0.02
# A housing is at least this share of the box's narrower cross-section, even
# when the joint sits near the box's edge.
_MIN_HOUSING = 0.6
# A piece reaching this many housing radii beyond its joint also gets a tube.
_TUBE_REACH = 1.6
# Each smaller piece of a link is grown by this much (m) per rank, so a trim ring
# that shares a surface with the shell under it is drawn on top rather than
# flickering through it (z-fighting).
_TRIM_LIFT = 0.002

# Superellipsoid exponents (round the shape's axis, along it): 1 is round, 0
# square. A drum is a cylinder with softened rims, a tube has domed ends, a
# block is a box with rounded edges.
DRUM, TUBE, BLOCK = (1.0, 0.25), (1.0, 0.5), (0.4, 0.4)
# Mesh resolution of MuJoCo's supersphere: 134 vertices, 264 triangles; smooth
# enough at wrist-camera range, and a frame costs about what the boxes did.
RESOLUTION = 12


# Mesh axes (x, y, z) as body axes, once the mesh's z is turned onto body axis
# x, y or z by AXIS_QUATS (w, x, y, z): a quarter turn about y, about -x, none.
_MESH_AXES = ((2, 1, 0), (0, 2, 1), (0, 1, 2))
AXIS_QUATS = ((np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0),
              (np.sqrt(0.5), -np.sqrt(0.5), 0.0, 0.0),
              (1.0, 0.0, 0.0, 0.0))


@dataclasses.dataclass(frozen=True)
class Shape:
  """A superellipsoid in a body frame, filling the box centre +- half.

  Attributes:
    centre: (3,) m.
    half: (3,) half extents along the body axes, m.
    axis: the body axis (0 x, 1 y, 2 z) the second exponent runs along.
    exponents: (round the axis, along it): DRUM, TUBE or BLOCK.
  """
  centre: tuple
  half: tuple
  axis: int
  exponents: tuple

  def grown(self, amount):
    return dataclasses.replace(self, half=tuple(h + amount for h in self.half))

  @property
  def quat(self):
    """Turn of the mesh in the body: its z onto `axis`."""
    return AXIS_QUATS[self.axis]

  @property
  def mesh_scale(self):
    """Half extents along the mesh's own axes (MuJoCo's mesh `scale` of a unit supersphere)."""
    return tuple(self.half[i] for i in _MESH_AXES[self.axis])


def _rotation(quat):
  """3x3 rotation of a quaternion (w, x, y, z)."""
  w, x, y, z = np.asarray(quat, dtype=float) / np.linalg.norm(quat)
  return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                   [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                   [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _axis_index(direction):
  """Index of the body axis a direction runs along, or None when it is oblique."""
  direction = np.abs(np.asarray(direction, dtype=float))
  direction /= np.linalg.norm(direction)
  return int(np.argmax(direction)) if direction.max() > 0.99 else None


def joint_anchors(bodies):
  """Body name -> [(point, axis index)] of the hinges a body houses, in its frame.

  A link houses its own joints and those of its children (the child's joint
  frame mapped through the child's pos and quat): its own are listed first.
  """
  anchors = {body["name"]: [] for body in bodies}
  for body in bodies:
    rotation, offset = _rotation(body.get("quat", [1, 0, 0, 0])), np.asarray(body["pos"], float)
    for joint in body.get("joints", []):
      if joint.get("type", "hinge") != "hinge":
        continue  # finger slides house nothing
      point = np.asarray(joint.get("pos", [0, 0, 0]), dtype=float)
      anchors[body["name"]].append((point, _axis_index(joint["axis"])))
      if body.get("parent") in anchors:
        anchors[body["parent"]].append(
            (offset + rotation @ point, _axis_index(rotation @ joint["axis"])))
  return {name: [a for a in found if a[1] is not None] for name, found in anchors.items()}


def collision_boxes(collision_geoms):
  """(lo, hi) of the body's collision boxes that are square to the body axes."""
  boxes = []
  for geom in collision_geoms:
    if geom.get("type") != "box":
      continue
    rotation = np.abs(_rotation(geom.get("quat", [1, 0, 0, 0])))
    if not np.allclose(rotation, np.round(rotation), atol=1e-3):
      continue  # an oblique box's bounds would overstate it
    half = rotation @ np.asarray(geom["size"], dtype=float)
    centre = np.asarray(geom.get("pos", [0, 0, 0]), dtype=float)
    boxes.append((centre - half, centre + half))
  return boxes


def _overlap(a, b):
  """Intersection over union of boxes a and b, each (lo, hi, ...)."""
  inside = np.prod(np.clip(np.minimum(a[1], b[1]) - np.maximum(a[0], b[0]), 0, None))
  return inside / (np.prod(a[1] - a[0]) + np.prod(b[1] - b[0]) - inside)


def _colourfulness(rgba):
  return max(rgba[:3]) - min(rgba[:3])


def _distinct(boxes, key):
  """`boxes` less those overlapping an earlier one (in order of `key`) as one shell; largest first."""
  kept = []
  for box in sorted(boxes, key=key):
    if all(_overlap(box, k) < _SAME_SHELL for k in kept):
      kept.append(box)
  return sorted(kept, key=lambda b: -np.prod(b[1] - b[0]))


def pieces(body):
  """The coloured visual pieces of a sheet body to draw, as (lo, hi, rgba), largest first.

  Of pieces that are one shell in two colours, the more colourful is kept:
  the arms' livery (Rethink red) rather than the grey or white trim listed
  with it; between equally grey ones, the larger.
  """
  found = []
  for piece in body.get("visual_mesh_bounds", []):
    if piece.get("rgba") is None:
      continue  # the uncoloured entry is the whole-link collision mesh, not a visual piece
    lo, hi = (np.asarray(b, dtype=float) for b in piece["bounds_in_body"])
    if (hi - lo).max() >= MIN_EXTENT:
      found.append((lo, np.maximum(hi, lo + _MIN_THICKNESS), piece["rgba"]))
  kept = _distinct(found, key=lambda p: (-_colourfulness(p[2]), -np.prod(p[1] - p[0])))
  return kept[:MAX_PER_BODY]


def _along(centre, axis, radius, start, end, exponents):
  """A drum or tube round body axis `axis` through `centre`, from `start` to `end` along it."""
  centre = np.array(centre, dtype=float)
  centre[axis] = (start + end) / 2
  half = np.full(3, float(radius))
  half[axis] = abs(end - start) / 2
  return Shape(tuple(centre), tuple(half), axis, exponents)


def _filling(lo, hi, axis, exponents):
  """The shape filling box lo..hi, its second exponent along body axis `axis`."""
  return Shape(tuple((lo + hi) / 2), tuple((hi - lo) / 2), int(axis), exponents)


def _plate(lo, hi, boxes):
  """A disc across a square-ish plate; an oblong one traced by collision boxes is
  drawn as those boxes, rounded; else a rounded block."""
  extent = hi - lo
  thin, middle, long = np.argsort(extent, kind="stable")
  if extent[long] < _SQUARE * extent[middle]:
    return [_filling(lo, hi, thin, DRUM)]
  inside = [b for b in boxes if np.all(b[0] >= lo - 0.01) and np.all(b[1] <= hi + 0.01)]
  if inside:
    return [_filling(*box, 2, BLOCK) for box in
            _distinct(inside, key=lambda b: -np.prod(b[1] - b[0]))]
  return [_filling(lo, hi, 2, BLOCK)]


def _cover(lo, hi):
  """A piece with no joint: a tube along a rod, else a rounded block."""
  extent = hi - lo
  order = np.argsort(extent, kind="stable")
  if extent[order[2]] > _ROD * extent[order[1]]:
    return _filling(lo, hi, order[2], TUBE)
  return _filling(lo, hi, 2, BLOCK)


def _housed_anchor(lo, hi, anchors):
  """The first joint whose axis runs through the box (the link's own before its
  children's), moved along its axis into the box; or None."""
  for point, axis in anchors:
    cross = [c for c in range(3) if c != axis]
    if np.all(point[cross] >= lo[cross] - _ANCHOR_MARGIN) and \
        np.all(point[cross] <= hi[cross] + _ANCHOR_MARGIN):
      return np.clip(point, lo, hi), axis
  return None


def _housing(lo, hi, point, axis):
  """The joint's housing, and a tube towards the box's far side when it reaches well beyond."""
  cross = [c for c in range(3) if c != axis]
  near = np.minimum(point - lo, hi - point)[cross]
  radius = max(near.min(), _MIN_HOUSING * (hi - lo)[cross].min() / 2)
  centre = point.copy()   # on the joint axis, moved in where the drum would stick out
  centre[cross] = np.clip(point[cross], lo[cross] + radius, hi[cross] - radius)
  shapes = [_along(centre, axis, radius, lo[axis], hi[axis], DRUM)]
  far = np.maximum(centre - lo, hi - centre)[cross]
  if far.max() > _TUBE_REACH * radius:
    direction = cross[int(np.argmax(far))]
    end = lo[direction] if centre[direction] - lo[direction] > hi[direction] - centre[direction] \
        else hi[direction]
    # from behind the joint (inside the housing) to the box's far side
    start = centre[direction] - np.sign(end - centre[direction]) * radius
    tube = _along(centre, direction, radius, start, end, TUBE)
    shapes.append(_inside(tube, lo, hi))
  return shapes


def _inside(shape, lo, hi):
  """`shape` shrunk and moved, where needed, into box lo..hi."""
  half = np.minimum(shape.half, (hi - lo) / 2)
  centre = np.clip(shape.centre, lo + half, hi - half)
  return dataclasses.replace(shape, centre=tuple(centre), half=tuple(half))


def fit(lo, hi, anchors=(), boxes=()):
  """The shapes drawn for one visual piece.

  Args:
    lo, hi: the piece's bounds in the body frame, m.
    anchors: (point, axis index) of the hinges the body houses (`joint_anchors`).
    boxes: (lo, hi) of the body's collision boxes square to its axes.
  Returns:
    list of Shape: one, two for a housing and its tube, or one per collision
    box for a plate traced by boxes.
  """
  lo = np.asarray(lo, dtype=float)
  hi = np.maximum(np.asarray(hi, dtype=float), lo + _MIN_THICKNESS)
  extent = np.sort(hi - lo)
  if extent[0] < _FLAT * extent[1]:
    return _plate(lo, hi, boxes)
  anchor = _housed_anchor(lo, hi, anchors)
  if anchor is not None:
    return _housing(lo, hi, *anchor)
  return [_cover(lo, hi)]


def shapes(body, anchors=()):
  """[(Shape, rgba)] drawn for a fact-sheet body.

  Args:
    body: one entry of a fact sheet's `bodies`.
    anchors: the hinges the body houses (`joint_anchors(...)[body name]`).
  """
  boxes = collision_boxes(body.get("collision_geoms") or [])
  return [(shape.grown(rank * _TRIM_LIFT), rgba)
          for rank, (lo, hi, rgba) in enumerate(pieces(body))
          for shape in fit(lo, hi, anchors, boxes)]

