"""Low-poly part meshes built with trimesh: bevelled boards, round legs, frames, curves, brackets.

Every mesh is centred on its part-local origin with the same extents as the
primitive it stands for, so a family can swap a box for a bevelled board
without moving anything. Meshes are built from vertices and faces directly
(no boolean engine needed) and are watertight, which coacd requires.
"""

import numpy as np
import trimesh


def _mesh(vertices, faces):
  mesh = trimesh.Trimesh(np.asarray(vertices, float), np.asarray(faces, int), process=True)
  if mesh.volume < 0:   # faces are wound consistently by construction; only the sense may flip
    mesh.invert()
  return mesh


def bevelled_board(size, bevel=0.003):
  """A box of full extents `size` whose twelve edges are chamfered by `bevel` metres."""
  half = np.asarray(size, float) / 2
  b = np.minimum(bevel, 0.45 * half.min())
  points = []
  for corner in np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]):
    for axis in range(3):
      p = corner * half
      p[axis] -= corner[axis] * b
      points.append(p)
  return trimesh.convex.convex_hull(np.array(points))


def round_leg(radius, length, top_radius=None, sections=16):
  """A cylinder along z of `length`, optionally tapered to `top_radius` at +z."""
  angles = np.linspace(0, 2 * np.pi, sections, endpoint=False)
  ring = np.stack([np.cos(angles), np.sin(angles)], 1)
  top = radius if top_radius is None else top_radius
  points = np.concatenate([np.column_stack([ring * radius, np.full(sections, -length / 2)]),
                           np.column_stack([ring * top, np.full(sections, length / 2)])])
  return trimesh.convex.convex_hull(points)


def _extrude_band(inner, outer, depth, closed):
  """Solid between two matching 2-D polylines (xy), extruded over z in [-depth/2, depth/2].

  Point i of `inner` faces point i of `outer`; the band between them must not
  fold over itself. Closed loops make a ring (a frame), open ones a strip with
  end caps (a curved board, an L).
  """
  inner, outer = np.asarray(inner, float), np.asarray(outer, float)
  n = len(inner)
  z0, z1 = -depth / 2, depth / 2
  # vertex blocks: inner bottom, outer bottom, inner top, outer top
  vertices = np.concatenate([np.column_stack([loop, np.full(n, z)])
                             for z in (z0, z1) for loop in (inner, outer)])
  ib, ob, it, ot = 0, n, 2 * n, 3 * n
  faces = []
  segments = n if closed else n - 1
  for i in range(segments):
    j = (i + 1) % n
    faces += [[ib + i, ob + j, ob + i], [ib + i, ib + j, ob + j]]          # bottom cap
    faces += [[it + i, ot + i, ot + j], [it + i, ot + j, it + j]]          # top cap
    faces += [[ob + i, ob + j, ot + j], [ob + i, ot + j, ot + i]]          # outer wall
    faces += [[ib + i, it + j, ib + j], [ib + i, it + i, it + j]]          # inner wall
  if not closed:
    faces += [[ib, ob, ot], [ib, ot, it]]                                  # start cap
    e = n - 1
    faces += [[ib + e, ot + e, ob + e], [ib + e, it + e, ot + e]]          # end cap
  return _mesh(vertices, faces)


def _to_plane(mesh, plane):
  """Turns a mesh extruded along z so that its extrusion axis becomes `plane`'s normal."""
  if plane == "xz":    # extrusion along y: a board standing upright, facing y
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
  elif plane == "yz":  # extrusion along x: outline x runs along y, outline y up z
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 0, 1]))
  return mesh


def frame(width, height, thickness, border, plane="xz"):
  """A rectangular frame (a board with a rectangular opening), outer size width x height,
  in the xz plane (`plane="yz"`: width runs along y)."""
  w, h = width / 2, height / 2
  iw, ih = w - border, h - border
  outer = [(w, h), (-w, h), (-w, -h), (w, -h)]
  inner = [(iw, ih), (-iw, ih), (-iw, -ih), (iw, -ih)]
  return _to_plane(_extrude_band(inner, outer, thickness, closed=True), plane)


def curved_board(chord, sagitta, height, thickness, segments=8):
  """A board bent into a circular arc in the xy plane, standing `height` tall along z.

  The arc spans `chord` along x and bows by `sagitta` towards -y; the shape is
  centred on its bounding box so it replaces a flat board of the same outline.
  """
  radius = (chord ** 2 / 4 + sagitta ** 2) / (2 * sagitta)
  half_angle = np.arcsin(chord / 2 / radius)
  angles = np.linspace(-half_angle, half_angle, segments + 1)
  centre_y = radius - sagitta   # circle centre above the arc's lowest point at y = 0
  def arc(r):
    return np.column_stack([r * np.sin(angles), centre_y - r * np.cos(angles)])
  inner, outer = arc(radius - thickness / 2), arc(radius + thickness / 2)
  mesh = _extrude_band(inner, outer, height, closed=False)
  lo, hi = mesh.bounds
  mesh.apply_translation(-(lo + hi) / 2)
  return mesh


def l_bracket(leg_a, leg_b, width, thickness):
  """An L of two flanges: one `leg_a` long along +x, one `leg_b` long along +z, `width` deep in y."""
  t = thickness
  outer = [(leg_a, 0.0), (0.0, 0.0), (0.0, leg_b)]
  inner = [(leg_a, t), (t, t), (t, leg_b)]
  mesh = _to_plane(_extrude_band(inner, outer, width, closed=False), "xz")
  lo, hi = mesh.bounds
  mesh.apply_translation(-(lo + hi) / 2)
  return mesh


def t_profile(width, height, stem, flange):
  """An upside-down T outline in the xz plane (foot `width` x `flange`, stem `stem` wide), as a
  closed polygon for `extrude_polygon`."""
  s, f = stem / 2, flange
  return [(-width / 2, 0), (width / 2, 0), (width / 2, f), (s, f), (s, height), (-s, height),
          (-s, f), (-width / 2, f)]


def extrude_polygon(polygon, depth, plane="xz"):
  """A prism of a simple (possibly concave) polygon, counter-clockwise, extruded by `depth`."""
  poly = np.asarray(polygon, float)
  n = len(poly)
  triangles = _ear_clip(poly)
  vertices = np.concatenate([np.column_stack([poly, np.full(n, -depth / 2)]),
                             np.column_stack([poly, np.full(n, depth / 2)])])
  faces = [[a, c, b] for a, b, c in triangles] + [[a + n, b + n, c + n] for a, b, c in triangles]
  for i in range(n):
    j = (i + 1) % n
    faces += [[i, j, j + n], [i, j + n, i + n]]
  mesh = _to_plane(_mesh(vertices, faces), plane)
  lo, hi = mesh.bounds
  mesh.apply_translation(-(lo + hi) / 2)
  return mesh


def _ear_clip(poly):
  """Triangles (index triples) of a simple counter-clockwise polygon, by ear clipping."""
  remaining = list(range(len(poly)))
  triangles = []
  def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
  while len(remaining) > 3:
    for k in range(len(remaining)):
      i, j, l = remaining[k - 1], remaining[k], remaining[(k + 1) % len(remaining)]
      a, b, c = poly[i], poly[j], poly[l]
      if cross(a, b, c) <= 1e-12:
        continue   # reflex or flat corner: not an ear
      inside = any(cross(a, b, poly[m]) >= 0 and cross(b, c, poly[m]) >= 0
                   and cross(c, a, poly[m]) >= 0 for m in remaining if m not in (i, j, l))
      if not inside:
        triangles.append((i, j, l))
        remaining.pop(k)
        break
    else:
      raise ValueError("polygon is not simple and counter-clockwise")
  triangles.append(tuple(remaining))
  return triangles
