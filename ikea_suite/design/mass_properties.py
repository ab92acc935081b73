"""Mass, centre of mass and inertia of a part, from the constructions of its geoms.

Each geom that carries a `construction` (see construction.py) contributes the
mass of what it is really made of: a honeycomb top its faces, frame and paper
core, a steel tube its shell, not its bounding box at a solid density. Geoms
without one (visual meshes, collision stand-ins for a shape whose mass another
geom carries) add nothing. The writer puts the sum on the body as an explicit
`<inertial>`, which MuJoCo uses in place of geom-derived inertia
(compiler `inertiafromgeom="auto"`, the default).

Units: metres, kilograms; inertia in kg m^2 about the centre of mass, in the
part frame.
"""

import dataclasses

import numpy as np
import trimesh

from ikea_suite.design import construction as cons


@dataclasses.dataclass(frozen=True)
class MassProperties:
  mass: float
  com: np.ndarray        # (3,), part frame
  inertia: np.ndarray    # (3, 3), about com, part frame axes

  def moved(self, pos, rot):
    """The same body seen from a frame in which it sits at `pos` turned by `rot`."""
    return MassProperties(self.mass, np.asarray(pos, float) + rot @ self.com,
                          rot @ self.inertia @ rot.T)


def combine(items):
  """One MassProperties of several rigidly joined ones (parallel-axis theorem).

  A negative mass subtracts (a hollow box is its outer box minus its inside).
  """
  items = list(items)
  mass = sum(p.mass for p in items)
  if mass <= 0:
    raise ValueError(f"combined mass {mass} is not positive")
  com = sum(p.mass * p.com for p in items) / mass
  inertia = np.zeros((3, 3))
  for p in items:
    d = p.com - com
    inertia += p.inertia + p.mass * (d @ d * np.eye(3) - np.outer(d, d))
  return MassProperties(mass, com, inertia)


def solid_box(size, density, center=(0.0, 0.0, 0.0)):
  """A solid box of full extents `size` centred at `center`, axes along the frame's."""
  size = np.asarray(size, float)
  mass = density * np.prod(size)
  sq = size ** 2
  inertia = mass / 12 * np.diag([sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]])
  return MassProperties(mass, np.asarray(center, float), inertia)


def solid_cylinder(radius, length, density, center=(0.0, 0.0, 0.0)):
  """A solid cylinder along z."""
  mass = density * np.pi * radius ** 2 * length
  side = mass * (3 * radius ** 2 + length ** 2) / 12
  return MassProperties(mass, np.asarray(center, float),
                        np.diag([side, side, mass * radius ** 2 / 2]))


def _axes(size):
  """(thin, u, v): the smallest extent's axis, then the other two in order."""
  thin = int(np.argmin(size))
  u, v = [a for a in range(3) if a != thin]
  return thin, u, v


def _box_along(axes_sizes, center_along, density):
  """A solid box given as {axis: extent} and {axis: centre coordinate}."""
  size = [axes_sizes[a] for a in range(3)]
  center = [center_along.get(a, 0.0) for a in range(3)]
  return solid_box(size, density, center)


def _plate_box(size, c):
  thin, u, v = _axes(size)
  sheet = dict(enumerate(size))
  sheet[thin] = c.thickness
  return _box_along(sheet, {}, c.density)


def _honeycomb_box(size, c):
  thin, u, v = _axes(size)
  half = np.asarray(size) / 2
  core_h = size[thin] - 2 * c.thickness
  w = c.frame_width
  if core_h <= 0 or 2 * w >= min(size[u], size[v]):
    raise ValueError(f"honeycomb board {tuple(size)} too thin or narrow for "
                     f"{c.thickness} m faces and a {w} m frame")
  parts = []
  for s in (-1, 1):
    parts.append(_box_along({thin: c.thickness, u: size[u], v: size[v]},
                            {thin: s * (half[thin] - c.thickness / 2)}, c.density))
    parts.append(_box_along({thin: core_h, u: size[u], v: w},
                            {v: s * (half[v] - w / 2)}, c.frame_density))
    parts.append(_box_along({thin: core_h, u: w, v: size[v] - 2 * w},
                            {u: s * (half[u] - w / 2)}, c.frame_density))
  parts.append(_box_along({thin: core_h, u: size[u] - 2 * w, v: size[v] - 2 * w}, {},
                          c.core_density))
  return combine(parts)


def _tube_box(size, c):
  long = int(np.argmax(size))
  inner = [s if a == long else s - 2 * c.thickness for a, s in enumerate(size)]
  if min(inner) <= 0:
    raise ValueError(f"tube {tuple(size)} narrower than its two {c.thickness} m walls")
  outer = solid_box(size, c.density)
  hole = solid_box(inner, c.density)
  shell = MassProperties(outer.mass - hole.mass, outer.com, outer.inertia - hole.inertia)
  if not c.core_density:
    return shell
  return combine([shell, solid_box(inner, c.core_density)])


def _tray_box(size, c):
  """Top sheet on the thin axis' + side, lips down all four edges, open underneath."""
  thin, u, v = _axes(size)
  half = np.asarray(size) / 2
  t = c.thickness
  lip = size[thin] - t
  parts = [_box_along({thin: t, u: size[u], v: size[v]}, {thin: half[thin] - t / 2}, c.density)]
  for s in (-1, 1):
    parts.append(_box_along({thin: lip, u: size[u], v: t},
                            {thin: -t / 2, v: s * (half[v] - t / 2)}, c.density))
    parts.append(_box_along({thin: lip, u: t, v: size[v] - 2 * t},
                            {thin: -t / 2, u: s * (half[u] - t / 2)}, c.density))
  return combine(parts)


_BOX = {cons.SOLID: lambda size, c: solid_box(size, c.density), cons.PLATE: _plate_box,
        cons.HONEYCOMB: _honeycomb_box, cons.TUBE: _tube_box, cons.TRAY: _tray_box}


def _cylinder(radius, length, c):
  if c.kind == cons.SOLID:
    return solid_cylinder(radius, length, c.density)
  if c.kind == cons.PLATE:     # a disc of the sheet's thickness, centred
    return solid_cylinder(radius, c.thickness, c.density)
  if c.kind == cons.TUBE:
    inner = radius - c.thickness
    if inner <= 0:
      raise ValueError(f"tube of radius {radius} m thinner than its {c.thickness} m wall")
    outer, hole = solid_cylinder(radius, length, c.density), solid_cylinder(inner, length, c.density)
    shell = MassProperties(outer.mass - hole.mass, outer.com, outer.inertia - hole.inertia)
    if not c.core_density:
      return shell
    return combine([shell, solid_cylinder(inner, length, c.core_density)])
  raise ValueError(f"a cylinder cannot be built as {c.kind} ({c.name})")


def _mesh(mesh, c):
  if c.kind != cons.SOLID:
    raise ValueError(f"a mesh part can only be solid, not {c.kind} ({c.name})")
  if not mesh.is_volume:   # an imported mesh with holes: its convex hull bounds the material
    mesh = mesh.convex_hull
  props = trimesh.triangles.mass_properties(mesh.triangles, density=c.density)
  return MassProperties(float(props["mass"]), np.asarray(props["center_mass"], float),
                        np.asarray(props["inertia"], float))


def geom_properties(geom, meshes):
  """MassProperties of one Geom in the part frame; None when it carries no construction."""
  c = geom.construction
  if c is None:
    return None
  if geom.type == "box":
    local = _BOX[c.kind](2 * np.asarray(geom.size, float), c)
  elif geom.type == "cylinder":
    local = _cylinder(geom.size[0], 2 * geom.size[1], c)
  elif geom.type == "mesh":
    local = _mesh(meshes[geom.mesh], c)
  else:
    raise ValueError(f"no mass model for a {geom.type} geom ({c.name})")
  return local.moved(geom.pos, np.asarray(geom.rot, float))


def part_properties(part, meshes):
  """MassProperties of a blueprint Part; raises ValueError if none of its geoms has mass."""
  items = [p for p in (geom_properties(g, meshes) for g in part.geoms) if p is not None]
  if not items:
    raise ValueError(f"part {part.name!r}: no geom carries a construction, so it has no mass")
  return combine(items)
