"""Converts one original-format model into a model file in our format.

Geometry: each part keeps its own frame. Visual meshes are scaled to metres
(the original's per-axis `scale`) and written as binary STL; colliding
primitives (the original's `noviz_collision_*` boxes and cylinders) stay
primitives, hidden when the original hid them; a mesh geom that collides
collides as itself when convex, else through coacd convex pieces
(ikea_suite.design.decompose, cached by content hash). Colours map to the
nearest catalog material; textures are not carried over.

Mass: by default each part keeps the original's mass (what MuJoCo computes
from the original's densities and masses), spread over our collision geoms
in proportion to the original densities. With `material`, every collision
geom takes that material's density from our material table instead; so does
every part, with particleboard's, when any part of the file is lighter than
any furniture material (a placeholder mass; the repair is reported).

Layout: the parts take the assembled pose solved by `assemble`, each mated
part slid along its mate's up axis until it touches its partner (`seat`), turned onto
its side if it cannot stand upright (`rest`), set on the floor (lowest collision point
at z = 0) and centred. The original's initial
layout, when the file has one, is kept in the metadata as `initpos.<part>`
(see ikea_suite.props.layout).
"""

import dataclasses
import math
import pathlib

import numpy as np
import trimesh

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction
from ikea_suite.design import mass_properties
from ikea_suite.design import materials
from ikea_suite.design import mjcf_writer
from ikea_suite.design import part_geoms
from ikea_suite.design.original import assemble
from ikea_suite.design.original import names
from ikea_suite.design.original import reader
from ikea_suite.design.original import rest
from ikea_suite.design.original import seat
from ikea_suite.design.original import trim

DEFAULT_CATEGORY = "original"
FAMILY = "original"
_MIN_VOLUME = 1e-9   # m^3: a mesh enclosing less is an open surface (MuJoCo rejects those)
_MIN_THICKNESS = 1e-5   # m: rms thickness below which a mesh's vertices lie in a plane
_FALLBACK_MATERIAL = "wood_light"   # for textured parts: the original's textures are wood


@dataclasses.dataclass
class Converted:
  """What one conversion produced."""
  source: pathlib.Path
  path: pathlib.Path      # the written model file
  name: str
  num_parts: int
  num_connectors: int
  pairs: list             # (connector, connector) names of the mated pairs
  notes: list             # every repair, in reading then solving order


def material_names() -> list[str]:
  """Valid values of `material`: the solid constructions of our material table (the
  original's collision primitives are solid shapes, so hollow constructions do not apply)."""
  return sorted(construction.SOLIDS)


def material_density(material: str) -> float:
  """kg/m^3 of a solid construction in our material table (the one call into it)."""
  return construction.BY_NAME[material].density


def _nearest_material(rgba):
  return min(materials.MATERIALS, key=lambda m: np.linalg.norm(
      np.asarray(materials.MATERIALS[m][0][:3]) - np.asarray(rgba[:3])))


def _visual_material(geom, model, forced):
  if forced in materials.MATERIALS:
    return forced
  if geom.material in model.materials:
    rgba, textured = model.materials[geom.material]
    return _FALLBACK_MATERIAL if textured else _nearest_material(rgba)
  return _nearest_material(geom.rgba) if geom.rgba is not None else _FALLBACK_MATERIAL


def _primitive_volume(kind, size):
  size = list(size) + [0.0] * 3
  r = size[0]
  if kind == "box":
    return 8 * size[0] * size[1] * size[2]
  if kind == "sphere":
    return 4 / 3 * math.pi * r ** 3
  if kind == "cylinder":
    return math.pi * r ** 2 * 2 * size[1]
  if kind == "capsule":
    return math.pi * r ** 2 * 2 * size[1] + 4 / 3 * math.pi * r ** 3
  return 4 / 3 * math.pi * size[0] * size[1] * size[2]   # ellipsoid


def _primitive_corners(kind, size):
  size = list(size) + [size[0]] * 2
  r = size[0]
  half = {"box": size[:3], "sphere": [r, r, r], "cylinder": [r, r, size[1]],
          "capsule": [r, r, size[1] + r]}.get(kind, size[:3])
  return geometry.box_corners(-np.asarray(half, float), half)


# The lightest furniture material, honeycomb board, is 150-300 kg/m^3 effective (docs/physics.md);
# a part lighter than this over its collision volume carries a placeholder mass.
IMPLAUSIBLE_DENSITY = 100.0


class _Converter:
  def __init__(self, model, material):
    self.model, self.material = model, material
    self.notes = list(model.repairs)
    self.mesh_cache = {}
    self.mass_repair = None   # what every part is made of when the file's masses are not real

  def repair_masses(self, parts):
    """Gives every part particleboard's density when any part of the file is lighter than
    any furniture material (some of the original's files weigh a leg at 1.2 g: MuJoCo's
    contacts then let it sink and the model drifts). `parts`: (body, name, part_geoms)."""
    if self.material is not None:
      return
    light = []
    for body, part_name, geoms in parts:
      volume = sum(v for _, base, v in geoms if base is not None)
      mass = self.original_mass(body)
      if volume > 0 and 0 < mass < IMPLAUSIBLE_DENSITY * volume:
        light.append((mass / volume, mass, part_name))
    if light:
      density, mass, part_name = min(light)
      self.mass_repair = construction.PARTICLEBOARD
      self.notes.append(
          f"masses repaired: {len(light)} of {len(parts)} parts are lighter than any furniture "
          f"material (under {IMPLAUSIBLE_DENSITY:g} kg/m^3; part {part_name!r} weighs "
          f"{mass * 1000:.1f} g, {density:.0f} kg/m^3), so every part is given particleboard's "
          f"{construction.PARTICLEBOARD.density:g} kg/m^3 (--material chooses another)")

  def mesh(self, name, label):
    if name in self.mesh_cache:
      return self.mesh_cache[name]
    asset = self.model.meshes.get(name)
    if asset is None:
      raise errors.ConversionError(self.model.path, label,
                                   f"uses mesh {name!r}, which no <mesh> declares")
    if not asset.file.is_file():
      raise errors.ConversionError(self.model.path, f"<mesh name={name!r}>",
                                   f"no mesh file {str(asset.file)!r} (an incomplete file)")
    try:
      mesh = trimesh.load(str(asset.file), force="mesh")
    except Exception as e:   # trimesh raises many kinds on a corrupt file
      raise errors.ConversionError(self.model.path, f"<mesh name={name!r}>",
                                   f"cannot read {str(asset.file)!r}: {e}") from None
    if not isinstance(mesh, trimesh.Trimesh) or not len(mesh.faces):
      raise errors.ConversionError(self.model.path, f"<mesh name={name!r}>",
                                   f"{str(asset.file)!r} holds no triangles")
    mesh.apply_scale(asset.scale)
    self.mesh_cache[name] = self.closed(mesh, name)
    return self.mesh_cache[name]

  def closed(self, mesh, name):
    """`mesh`, or its convex hull when it encloses no volume (MuJoCo rejects such meshes)."""
    with np.errstate(invalid="ignore", divide="ignore"):   # trimesh divides by the volume
      if abs(mesh.volume) > _MIN_VOLUME:
        return mesh
    points = mesh.vertices - mesh.vertices.mean(0)
    thinnest = np.linalg.svd(points, compute_uv=False)[-1] / np.sqrt(len(points))
    if thinnest < _MIN_THICKNESS:   # qhull cannot wrap a flat point set
      raise errors.ConversionError(self.model.path, f"<mesh name={name!r}>",
                                   "encloses no volume (a flat surface)")
    hull = mesh.convex_hull
    self.notes.append(f"mesh {name!r} encloses no volume (an open or double-sided surface); "
                      "replaced by its convex hull")
    return hull

  def original_mass(self, body):
    """The part's mass as MuJoCo computes it from the original file (kg)."""
    total = 0.0
    for g in body.geoms:
      if g.mass is not None:
        total += g.mass
      elif g.type == "mesh":
        total += g.density * abs(self.mesh(g.mesh, f"<geom name={g.name!r}>").volume)
      else:
        total += g.density * _primitive_volume(g.type, g.size)
    return total

  def part_geoms(self, furniture, part_name, body):
    """Our geoms of one part, each collision geom with (base density, volume)."""
    out = []   # (bp.Geom, base density or None, volume)
    for g in body.geoms:
      label = f"<geom name={g.name!r}>"
      material = _visual_material(g, self.model, self.material)
      base = None
      if g.collides:
        base = g.mass / _positive_volume(g, self) if g.mass is not None else g.density
      if g.type != "mesh":
        if not g.collides and not g.visible:
          continue
        geom = bp.Geom(g.type, tuple(g.size), pos=tuple(g.pos), rot=g.rot, material=material,
                       collide=g.collides, visible=g.visible)
        out.append((geom, base, _primitive_volume(g.type, g.size)))
        continue
      mesh = self.mesh(g.mesh, label)
      prefix = names.safe(f"{self.model.path.stem}_{g.mesh}").lower()
      if not g.collides:
        if g.visible:
          geom = bp.Geom("mesh", pos=tuple(g.pos), rot=g.rot, material=material, collide=False,
                         mesh=part_geoms.register_mesh(furniture, mesh, prefix))
          out.append((geom, None, 0.0))
        continue
      if mesh.is_convex:
        pieces = [bp.Geom("mesh", pos=tuple(g.pos), rot=g.rot, material=material, visible=g.visible,
                          mesh=part_geoms.register_mesh(furniture, mesh, prefix))]
      else:
        # The pieces carry the mass (set_densities), so the visual mesh carries none.
        pieces = part_geoms.concave(furniture, mesh, prefix, material, None, g.pos, g.rot)
        if not g.visible:
          pieces = pieces[1:]
        self.notes.append(f"part {part_name!r}: concave collision mesh {g.mesh!r} decomposed "
                          f"into {sum(p.collide for p in pieces)} convex pieces")
      for piece in pieces:
        if not piece.collide:
          out.append((piece, None, 0.0))
          continue
        out.append((piece, base, abs(furniture.meshes[piece.mesh].volume)))
    if not any(base is not None for _, base, _ in out):
      raise errors.ConversionError(
          self.model.path, f"<body name={body.name!r}>",
          "part has no collision geometry (no colliding primitive or mesh; an incomplete file)")
    return out

  def set_densities(self, part_name, body, geoms):
    colliding = [(geom, base, volume) for geom, base, volume in geoms if base is not None]
    if self.material is not None or self.mass_repair is not None:
      chosen = self.mass_repair or construction.BY_NAME[self.material]
      for geom, _, _ in colliding:
        geom.construction = chosen
      return
    target = self.original_mass(body)
    weighted = sum(base * volume for _, base, volume in colliding)
    if target <= 0 or weighted <= 0:
      density = construction.PARTICLEBOARD.density   # the usual flat-pack board
      self.notes.append(f"part {part_name!r} has no mass in the file; given {density:g} kg/m^3")
      for geom, _, _ in colliding:
        geom.construction = construction.solid(density, "the fallback density")
      return
    for geom, base, _ in colliding:
      geom.construction = construction.solid(base * target / weighted, "the original's mass")


def _collision_corners(furniture, part):
  """Points bounding a part's collision geoms, in the part frame (after any trim)."""
  out = []
  for g in part.geoms:
    if g.collide:
      local = (furniture.meshes[g.mesh].vertices if g.type == "mesh"
               else _primitive_corners(g.type, g.size))
      out.append(local @ g.rot.T + np.asarray(g.pos))
  return np.concatenate(out)


def _set_down(furniture):
  """Turns an assembly that cannot stand upright onto the side it rests on (rest.py);
  returns the note reporting it, if any."""
  points = np.concatenate([_collision_corners(furniture, p) @ p.rot.T + p.pos
                           for p in furniture.parts])
  com = mass_properties.combine(
      mass_properties.part_properties(p, furniture.meshes).moved(p.pos, p.rot)
      for p in furniture.parts).com
  turn, before, after = rest.resting_turn(points, com)
  if np.allclose(turn, np.eye(3)):
    return []
  for part in furniture.parts:
    part.pos, part.rot = turn @ part.pos, turn @ part.rot
  angle = np.degrees(np.linalg.norm(geometry.mat_to_axis_angle(turn)))
  how = (f"all its feet, tilted {angle:.1f} deg" if angle <= np.degrees(rest.NEAR_UPRIGHT)
         else f"its side instead, turned {angle:.0f} deg")
  return [f"the assembly cannot stand upright (its centre of mass lies {-before * 1000:.1f} mm "
          f"outside the footprint it stands on); set down on {how}, the centre of mass "
          f"{after * 1000:.1f} mm inside the new footprint"]


def _positive_volume(g, converter):
  if g.type == "mesh":
    return max(abs(converter.mesh(g.mesh, f"<geom name={g.name!r}>").volume), 1e-12)
  return max(_primitive_volume(g.type, g.size), 1e-12)


def _unique(mapping, path, kind):
  seen = {}
  for original, safe in mapping.items():
    if safe in seen:
      raise errors.ConversionError(
          path, f"<{kind} name={original!r}>",
          f"its safe name {safe!r} is also that of {seen[safe]!r}; rename one")
    seen[safe] = original
  return mapping


def _fmt(values):
  return " ".join(f"{v:.6g}" for v in values)


def convert(source: str | pathlib.Path, out_dir: str | pathlib.Path, material: str | None = None,
            category: str = DEFAULT_CATEGORY) -> Converted:
  """Converts one original-format model file into our format under `out_dir`.

  Args:
    source: the original model's XML file.
    out_dir: where the model file and its meshes (meshes/*.stl) are written.
    material: None to keep the original's masses, or a name from material_names()
      to give every part that material's density (and colour, if it is a visual material).
    category: the catalog category written in the model's metadata.

  Returns:
    A Converted summary (written path, counts, mated pairs, repairs).

  Raises:
    ConversionError: the file cannot be converted; the message names the element and why.
    OptionValueError: `material` is not a known material.
  """
  if material is not None and material not in material_names():
    raise errors.OptionValueError(f"material must be one of {material_names()}, got {material!r}")
  model = reader.read(source)
  solved = assemble.solve(model)
  converter = _Converter(model, material)
  part_names = _unique({b.name: names.safe(b.name) for b in model.bodies}, model.path, "body")
  site_names = _unique({c.site: names.safe(c.site) for c in solved.connectors}, model.path, "site")
  name = names.safe(model.path.stem).lower()
  furniture = bp.Blueprint(name, category, FAMILY, name, f"converted from {model.path.name}")
  furniture.metadata["source"] = model.path.name
  parts = [(body, part_names[body.name],
            converter.part_geoms(furniture, part_names[body.name], body)) for body in model.bodies]
  converter.repair_masses(parts)
  for body, part_name, geoms in parts:
    converter.set_densities(part_name, body, geoms)
    pos, rot = solved.poses[body.name]
    part = furniture.add_part(part_name, pos, rot, [g for g, _, _ in geoms])
    for c in solved.connectors:
      if c.body == body.name:
        part.connectors.append(bp.Connector(site_names[c.site], c.pos, c.rot, c.type, c.mates,
                                            c.twists_deg))
  tree = {frozenset((a.site, b.site)) for a, b in solved.tree}
  by_site = {c.site: c for c in solved.connectors}
  def named(a, b):
    return (part_names[by_site[a].body], site_names[a], part_names[by_site[b].body], site_names[b])
  seat_notes, dropped = seat.seat(
      furniture, [named(a.site, b.site) for a, b in solved.tree],
      [named(a, b) for a, b in solved.pairs if frozenset((a, b)) not in tree])
  pairs = [(site_names[a], site_names[b]) for a, b in solved.pairs
           if (site_names[a], site_names[b]) not in dropped]
  trim_notes = trim.trim(furniture, {part_names[b.name]: (b.pos, b.rot) for b in model.bodies})
  rest_notes = _set_down(furniture)
  corners = np.concatenate([_collision_corners(furniture, p) @ p.rot.T + p.pos
                            for p in furniture.parts])
  shift = -np.array([*(corners[:, :2].max(0) + corners[:, :2].min(0)) / 2, corners[:, 2].min()])
  for part in furniture.parts:
    part.pos = part.pos + shift
  for body, (pos, quat) in model.initpos.items():
    furniture.metadata[f"initpos.{part_names[body]}"] = _fmt(np.concatenate([pos, quat]))
  path = mjcf_writer.write(furniture, out_dir)
  return Converted(pathlib.Path(source), path, name, len(furniture.parts), 2 * len(pairs), pairs,
                   converter.notes + solved.notes + seat_notes + trim_notes + rest_notes)
