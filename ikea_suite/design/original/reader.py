"""Reads one model file of the original IKEA environment, repairing the quirks real files have.

What is read (facts about the format, see the README, "Bring models from the
original environment"):
  parts      the top-level <body> elements of <worldbody>: name, pos, quat
             (not always normalised); no joints, no nested bodies;
  orientation quat, or euler in radians (the original's base.xml sets
             <compiler angle="radian">; a file's own compiler angle overrides);
  geoms      visual meshes (collisions off) and invisible collision primitives
             `noviz_collision_<body>_<i>` that carry the mass by their density,
             or mesh geoms that collide themselves; top-level <default> classes
             apply;
  sites      connectors (names with `conn_site`) and helper sites;
  meshes     <mesh file scale>: paths relative to the compiler's meshdir (or the
             file's folder), `scale` converting STL units to metres;
  welds      <equality><weld body1 body2>: inactive, no relative pose;
  initpos    <custom><numeric name="<body>_initpos" data="x y z qw qx qy qz">.
Repairs (each reported in `OriginalModel.repairs`): quaternions normalised,
numbers written with commas read, initpos of unknown bodies dropped. Anything
that cannot be read raises ConversionError naming the element.
"""

import dataclasses
import math
import pathlib
import xml.etree.ElementTree as ET

import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.design import blueprint

_UNIT_TOL = 1e-4
_PRIMITIVES = ("box", "cylinder", "sphere", "capsule", "ellipsoid")
_HIDDEN_GROUPS = ("3", "4", "5")   # MuJoCo's viewer draws geom groups 0 to 2 by default
_GEOM_DEFAULTS = {"type": "sphere", "contype": "1", "conaffinity": "1", "density": "1000",
                  "rgba": "0.5 0.5 0.5 1", "group": "0"}


@dataclasses.dataclass
class Geom:
  """One geom of a part, in the part frame."""
  name: str
  type: str                # box, cylinder, sphere, capsule, ellipsoid or mesh
  size: np.ndarray
  pos: np.ndarray
  rot: np.ndarray
  mesh: str | None         # mesh asset name when type == "mesh"
  rgba: np.ndarray | None  # the geom's colour, if written (on it or its class)
  material: str | None     # the original's material asset name, if any
  collides: bool           # contype or conaffinity non-zero
  visible: bool            # drawn: not a noviz geom and not fully transparent
  density: float           # kg/m^3
  mass: float | None       # kg, when written instead of a density


@dataclasses.dataclass
class Site:
  name: str
  pos: np.ndarray          # in the part frame
  rot: np.ndarray          # the original's frame: z up, y forward


@dataclasses.dataclass
class Body:
  name: str
  pos: np.ndarray          # as written in the file (not necessarily assembled)
  rot: np.ndarray
  geoms: list
  sites: list


@dataclasses.dataclass
class MeshAsset:
  name: str
  file: pathlib.Path
  scale: np.ndarray        # (3,), STL units to metres


@dataclasses.dataclass
class OriginalModel:
  """Everything the converter needs from one original file."""
  path: pathlib.Path
  name: str
  bodies: list
  meshes: dict             # asset name -> MeshAsset
  materials: dict          # material name -> (rgba, textured)
  welds: list              # (body1, body2) as written, duplicates included
  initpos: dict            # body name -> (pos (3,), quat (4,))
  repairs: list            # one sentence per repair made while reading


class _Reader:
  def __init__(self, path):
    self.path = pathlib.Path(path)
    self.repairs = []
    # The original merges each model into its base.xml, whose <compiler angle="radian">
    # makes every euler radians; a file's own <compiler angle=...> overrides that.
    self.angle_scale = 1.0

  def error(self, element, problem):
    return errors.ConversionError(self.path, element, problem)

  def numbers(self, elem, attr, label, counts, default=None):
    text = elem.get(attr)
    if text is None:
      return None if default is None else np.array(default, float)
    cleaned = text.replace(",", " ")
    try:
      values = np.array([float(v) for v in cleaned.split()])
    except ValueError:
      raise self.error(label, f"{attr}={text!r} must be numbers") from None
    if len(values) not in counts or not np.all(np.isfinite(values)):
      expected = " or ".join(map(str, counts))
      raise self.error(label, f"{attr}={text!r} must be {expected} finite numbers")
    if cleaned.split() != text.split():
      self.repairs.append(f"{label}: read {attr}={text!r} written with commas")
    return values

  def unit_quat(self, quat, label, attr="quat"):
    norm = np.linalg.norm(quat)
    if norm < 1e-9:
      raise self.error(label, f"{attr} {quat.tolist()} has zero length")
    if abs(norm - 1.0) > _UNIT_TOL:
      self.repairs.append(f"{label}: normalised {attr} (its length was {norm:.4g})")
    return quat / norm

  def frame(self, elem, label):
    pos = self.numbers(elem, "pos", label, (3,), (0, 0, 0))
    for unsupported in ("axisangle", "xyaxes", "zaxis"):
      if elem.get(unsupported) is not None:
        raise self.error(
            label, f"orientation written as {unsupported}; the converter reads quat or euler")
    euler = self.numbers(elem, "euler", label, (3,))
    if euler is not None:
      a, b, c = euler * self.angle_scale   # MuJoCo's default eulerseq 'xyz', axes that move
      return pos, blueprint.rot_x(a) @ blueprint.rot_y(b) @ geometry.rot_z(c)
    quat = self.unit_quat(self.numbers(elem, "quat", label, (4,), (1, 0, 0, 0)), label)
    return pos, geometry.quat_to_mat(quat)

  def read(self):
    try:
      root = ET.parse(self.path).getroot()
    except ET.ParseError as e:
      lines = self.path.read_text(errors="replace").splitlines()
      # An error on the last line (an element left open at the end) is a file cut short.
      cut = " (it ends mid-element: an incomplete file)" if e.position[0] >= len(lines) else ""
      raise self.error("<file>", f"not well-formed XML: {e}{cut}") from None
    except OSError as e:
      raise self.error("<file>", f"cannot be read: {e.strerror}") from None
    if root.tag != "mujoco":
      raise self.error(f"<{root.tag}>", "root element must be <mujoco>")
    compiler = root.find("compiler")
    mesh_dir = self.path.parent
    if compiler is not None:
      if compiler.get("angle", "radian") == "degree":
        self.angle_scale = math.pi / 180.0
      mesh_dir = mesh_dir / compiler.get("meshdir", compiler.get("assetdir", ""))
    classes = _default_classes(root)
    worldbody = root.find("worldbody")
    if worldbody is None:
      raise self.error("<mujoco>", "no <worldbody>")
    bodies = [self.body(b, classes) for b in worldbody.findall("body")]
    if len(bodies) < 2:
      raise self.error("<worldbody>", f"needs at least 2 part bodies, found {len(bodies)}")
    return OriginalModel(
        path=self.path, name=root.get("model") or self.path.stem, bodies=bodies,
        meshes=self.meshes(root, mesh_dir), materials=self.materials(root),
        welds=[(w.get("body1"), w.get("body2")) for e in root.findall("equality")
               for w in e.findall("weld")],
        initpos=self.initpos(root, {b.name for b in bodies}), repairs=self.repairs)

  def body(self, elem, classes):
    name = elem.get("name")
    if not name:
      raise self.error("<body>", "every part body needs a name")
    label = f"<body name={name!r}>"
    if elem.find("body") is not None:
      raise self.error(label, "nested bodies: a part must be one rigid body")
    pos, rot = self.frame(elem, label)
    childclass = elem.get("childclass")
    geoms = [self.geom(g, classes, childclass, name, i) for i, g in enumerate(elem.findall("geom"))]
    sites = []
    for site in elem.findall("site"):
      site_name = site.get("name", "")
      sites.append(Site(site_name, *self.frame(site, f"<site name={site_name!r}>")))
    return Body(name, pos, rot, geoms, sites)

  def geom(self, elem, classes, childclass, body, index):
    attrs = dict(_GEOM_DEFAULTS)
    attrs.update(classes.get("main", {}))
    attrs.update(classes.get(elem.get("class") or childclass or "main", {}))
    attrs.update(elem.attrib)
    merged = ET.Element("geom", attrs)
    name = attrs.get("name", f"{body}_geom{index}")
    label = f"<geom name={name!r}>"
    kind = attrs["type"]
    if kind not in _PRIMITIVES + ("mesh",):
      raise self.error(
          label, f"type {kind!r} is not supported; parts use {', '.join(_PRIMITIVES)} or mesh")
    size = self.numbers(merged, "size", label, (1, 2, 3), (0, 0, 0))
    pos, rot = self.frame(merged, label)
    fromto = self.numbers(merged, "fromto", label, (6,))
    if fromto is not None:
      pos, rot, size = _from_to(fromto, size, kind, label, self)
    shown = self.numbers(merged, "rgba", label, (4,))
    rgba = shown if attrs["rgba"] != _GEOM_DEFAULTS["rgba"] else None
    mass = self.numbers(merged, "mass", label, (1,))
    return Geom(
        name=name, type=kind, size=size, pos=pos, rot=rot,
        mesh=attrs.get("mesh") if kind == "mesh" else None, rgba=rgba,
        material=attrs.get("material"),
        collides=attrs["contype"] != "0" or attrs["conaffinity"] != "0",
        visible=(not name.startswith("noviz") and shown[3] > 0
                 and attrs["group"] not in _HIDDEN_GROUPS),
        density=float(self.numbers(merged, "density", label, (1,))[0]),
        mass=None if mass is None else float(mass[0]))

  def meshes(self, root, mesh_dir):
    out = {}
    for asset in root.findall("asset"):
      for mesh in asset.findall("mesh"):
        file = mesh.get("file")
        if not file:
          raise self.error(f"<mesh name={mesh.get('name')!r}>", "a mesh needs a file")
        name = mesh.get("name") or pathlib.Path(file).stem
        label = f"<mesh name={name!r}>"
        scale = self.numbers(mesh, "scale", label, (1, 3), (1, 1, 1))
        out[name] = MeshAsset(name, mesh_dir / file, np.broadcast_to(scale, (3,)).astype(float))
    return out

  def materials(self, root):
    out = {}
    for asset in root.findall("asset"):
      for material in asset.findall("material"):
        name = material.get("name")
        rgba = self.numbers(material, "rgba", f"<material name={name!r}>", (4,), (1, 1, 1, 1))
        out[name] = (rgba, material.get("texture") is not None)
    return out

  def initpos(self, root, body_names):
    out = {}
    for custom in root.findall("custom"):
      for numeric in custom.findall("numeric"):
        name = numeric.get("name", "")
        if not name.endswith("_initpos"):
          continue
        label = f"<numeric name={name!r}>"
        body = name[:-len("_initpos")]
        if body not in body_names:
          self.repairs.append(f"{label}: dropped, no part body is named {body!r}")
          continue
        data = self.numbers(numeric, "data", label, (3, 7))
        quat = data[3:] if len(data) == 7 else np.array([1.0, 0, 0, 0])
        out[body] = (data[:3], self.unit_quat(quat, label, "initpos quaternion"))
    return out


def _default_classes(root):
  """class name -> geom attributes, each class inheriting its parents' ('main' at the top)."""
  classes = {}
  def walk(default, inherited, name):
    attrs = dict(inherited)
    for geom in default.findall("geom"):
      attrs.update(geom.attrib)
    classes[name] = attrs
    for child in default.findall("default"):
      walk(child, attrs, child.get("class", name))
  for default in root.findall("default"):
    walk(default, {}, default.get("class", "main"))
  return classes


def _from_to(fromto, size, kind, label, reader):
  if kind not in ("capsule", "cylinder", "box", "ellipsoid"):
    raise reader.error(label, f"fromto is not valid for a {kind}")
  start, end = fromto[:3], fromto[3:]
  axis = end - start
  length = np.linalg.norm(axis)
  if length < 1e-9:
    raise reader.error(label, "fromto has zero length")
  z = axis / length
  helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
  x = np.cross(helper, z)
  x /= np.linalg.norm(x)
  rot = geometry.frame_from_axes(z, x)
  radius = size[0]
  full = (radius, length / 2) if kind in ("capsule", "cylinder") else (radius, radius, length / 2)
  return (start + end) / 2, rot, np.array(full)


def read(path: str | pathlib.Path) -> OriginalModel:
  """Reads an original-format model file.

  Args:
    path: the model's XML file.

  Returns:
    An OriginalModel, with every repair made listed in its `repairs`.

  Raises:
    ConversionError: the file cannot be read as an original model (names the element).
  """
  return _Reader(path).read()
