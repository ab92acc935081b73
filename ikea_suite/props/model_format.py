"""Reads and validates a furniture MJCF file into a FurnitureSpec.

The format (documented in the README): every top-level body of <worldbody> is
a rigid part in its assembled pose, optionally with a <freejoint/>. A connector
is a <site> on a part plus a <custom><text name="connector:SITE" data="..."/>
entry whose data is `type=T; mates=M; twists=0 90 180 270` (degrees; omit
`twists` or leave it empty to allow any twist). Furniture-wide metadata sits in
<text name="furniture" data="category=...; ...">. Plain MuJoCo loads the file
and shows the assembled furniture.

A file is read into its document (read_document: the parsed <mujoco> element
with its asset folders made absolute, so it compiles from memory anywhere) and
the document into a FurnitureSpec (spec_from_document), which carries the
document along: the scaled furniture (props/scaling.py) and the sequencer's
collision scene (compile_model) are made from it, never from the file again.
"""

import math
import os
import pathlib
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.assembly import mating
from ikea_suite.props import furniture_spec

CONNECTOR_PREFIX = "connector:"
FURNITURE_TEXT = "furniture"
MAX_PARTS = 30          # one collision bit per assembled group, bits 1..30
_UNIT_TOL = 1e-4        # how far a written quaternion may be from unit length


def parse_key_values(text, path, element):
  """'a=1; b=x y' -> {'a': '1', 'b': 'x y'}."""
  out = {}
  for item in filter(None, (s.strip() for s in text.split(";"))):
    key, sep, value = item.partition("=")
    if not sep or not key.strip():
      raise errors.ModelFormatError(path, element, f"expected 'key=value', got {item!r}")
    out[key.strip()] = value.strip()
  return out


def _floats(text, n, path, element, attr):
  try:
    values = [float(v) for v in text.split()]
  except ValueError:
    values = []
  if len(values) != n or not all(math.isfinite(v) for v in values):
    raise errors.ModelFormatError(path, element, f"{attr}={text!r} must be {n} finite numbers")
  return np.array(values)


def _frame(elem, path, label):
  """Position and rotation written on a body or site (pos + optional unit quat)."""
  pos = _floats(elem.get("pos", "0 0 0"), 3, path, label, "pos")
  for unsupported in ("euler", "axisangle", "xyaxes", "zaxis"):
    if elem.get(unsupported) is not None:
      raise errors.ModelFormatError(
          path, label, f"orientation must be written as quat, not {unsupported}")
  quat = _floats(elem.get("quat", "1 0 0 0"), 4, path, label, "quat")
  if abs(np.linalg.norm(quat) - 1.0) > _UNIT_TOL:
    raise errors.ModelFormatError(
        path, label, f"quat {elem.get('quat')!r} is not normalised (norm {np.linalg.norm(quat):.6f})")
  return pos, geometry.quat_to_mat(quat)


def _parse_twists(text, path, label):
  if not text:
    return ()
  try:
    degrees = sorted({float(t) % 360.0 for t in text.replace(",", " ").split()})
  except ValueError:
    raise errors.ModelFormatError(path, label, f"twists={text!r} must be angles in degrees") from None
  return tuple(math.radians(d) for d in degrees)


def to_xml(document: ET.Element) -> str:
  """A document (read_document's, a spec's) as MJCF text that compiles from memory."""
  return ET.tostring(document, encoding="unicode")


def _compile(document, path):
  try:
    return mujoco.MjModel.from_xml_string(to_xml(document))
  except ValueError as e:
    raise errors.ModelFormatError(path, "<mujoco>", f"plain MuJoCo cannot load it: {e}") from None


def compile_model(spec: furniture_spec.FurnitureSpec) -> mujoco.MjModel:
  """The furniture as plain MuJoCo compiles it (its assembled pose), from the spec's document.

  Args:
    spec: a FurnitureSpec.
  Returns:
    A mujoco.MjModel.
  """
  return _compile(spec.document, spec.path)


def collision_geoms(model, body_ids):
  """(geom ids, index into `body_ids` of each geom's body) of the collision geoms
  (contype or conaffinity not 0) on the bodies `body_ids`, as compiled."""
  body_ids = np.asarray(body_ids, dtype=int)
  index = np.full(model.nbody, -1)
  index[body_ids] = np.arange(len(body_ids))
  owner = index[model.geom_bodyid]
  geoms = np.flatnonzero((owner >= 0) & ((model.geom_contype != 0) | (model.geom_conaffinity != 0)))
  return geoms, owner[geoms]


def _collision_bounds(model, body_id, path, label):
  """AABB, in the body frame, of the body's collision geoms."""
  geom_ids, _ = collision_geoms(model, [body_id])
  if not len(geom_ids):
    raise errors.ModelFormatError(path, label, "part has no collision geometry")
  corners = []
  for g in geom_ids:
    center, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
    local = geometry.box_corners(center - half, center + half)
    rot = geometry.quat_to_mat(model.geom_quat[g])
    corners.append(local @ rot.T + model.geom_pos[g])
  corners = np.concatenate(corners)
  return np.stack([corners.min(0), corners.max(0)])


def _check_names_unique(root, path):
  for tag in ("body", "site", "geom", "joint"):
    seen = set()
    for elem in root.iter(tag):
      name = elem.get("name")
      if name is None:
        continue
      if name in seen:
        raise errors.ModelFormatError(path, f"<{tag} name={name!r}>", "duplicate name")
      seen.add(name)


def _read_texts(root, path):
  texts = {}
  for custom in root.iter("custom"):
    for text in custom.iter("text"):
      name = text.get("name")
      if name in texts:
        raise errors.ModelFormatError(path, f"<text name={name!r}>", "duplicate name")
      texts[name] = text.get("data", "")
  return texts


def _read_parts(root, model, path):
  worldbody = root.find("worldbody")
  if worldbody is None:
    raise errors.ModelFormatError(path, "<mujoco>", "no <worldbody>")
  bodies = worldbody.findall("body")
  if len(bodies) < 2:
    raise errors.ModelFormatError(path, "<worldbody>", f"needs at least 2 part bodies, found {len(bodies)}")
  if len(bodies) > MAX_PARTS:
    raise errors.ModelFormatError(path, "<worldbody>", f"{len(bodies)} parts; at most {MAX_PARTS} are supported")
  parts = []
  for body in bodies:
    name = body.get("name")
    label = f"<body name={name!r}>"
    if not name:
      raise errors.ModelFormatError(path, "<body>", "every part body needs a name")
    if body.find("body") is not None:
      raise errors.ModelFormatError(path, label, "a part is one rigid body; nested bodies are not allowed")
    if body.find("joint") is not None or len(body.findall("freejoint")) > 1:
      raise errors.ModelFormatError(path, label, "a part may only carry a single <freejoint/>")
    pos, rot = _frame(body, path, label)
    body_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    parts.append(furniture_spec.PartSpec(
        name=name, pos=pos, rot=rot, element=body,
        bounds=_collision_bounds(model, body_id, path, label),
        mass=float(model.body_mass[body_id])))
  return parts


def _read_connectors(parts, texts, path):
  sites = {}
  for part in parts:
    for site in part.element.findall("site"):
      sites[site.get("name")] = (part, site)
  connectors = []
  for key, data in texts.items():
    if not key.startswith(CONNECTOR_PREFIX):
      continue
    site_name = key[len(CONNECTOR_PREFIX):]
    label = f"<text name={key!r}>"
    if site_name not in sites:
      raise errors.ModelFormatError(path, label, f"names site {site_name!r}, which is not a site on any part")
    fields = parse_key_values(data, path, label)
    for field in ("type", "mates"):
      if not fields.get(field):
        raise errors.ModelFormatError(path, label, f"missing '{field}=' (the connector's {field})")
    unknown = set(fields) - {"type", "mates", "twists"}
    if unknown:
      raise errors.ModelFormatError(path, label, f"unknown fields {sorted(unknown)}; valid: type, mates, twists")
    part, site = sites[site_name]
    pos, rot = _frame(site, path, f"<site name={site_name!r}>")
    connectors.append(furniture_spec.ConnectorSpec(
        name=site_name, part=part.name, type=fields["type"], mates=fields["mates"],
        twists=_parse_twists(fields.get("twists", ""), path, label), pos=pos, rot=rot))
  if not connectors:
    raise errors.ModelFormatError(path, "<custom>", "no connectors (<text name='connector:SITE' ...>)")
  return connectors


def _check_mates(parts, connectors, path):
  """Every connector's mate type exists, mates back, and sits on it when assembled."""
  by_type = {}
  for c in connectors:
    by_type.setdefault(c.type, []).append(c)
  pose = {p.name: (p.pos, p.rot) for p in parts}
  index = {id(c): i for i, c in enumerate(connectors)}
  coinciding = {k for pair in mating.coinciding_connector_pairs(connectors, pose) for k in pair}
  for c in connectors:
    label = f"connector {c.name!r}"
    mates = by_type.get(c.mates)
    if not mates:
      raise errors.ModelFormatError(
          path, label, f"mates type {c.mates!r} but no connector has that type; types present: {sorted(by_type)}")
    for m in mates:
      if m.mates != c.type:
        raise errors.ModelFormatError(
            path, label, f"mates {m.name!r} (type {m.type!r}), which mates {m.mates!r} instead of {c.type!r}")
      if m.twists != c.twists:
        raise errors.ModelFormatError(path, label, f"twists differ from its mate {m.name!r}")
    if index[id(c)] not in coinciding:
      raise errors.ModelFormatError(
          path, label, "no connector of its mate type coincides with it in the assembled pose "
          "(same position, same up axis, forward within an allowed twist)")


def coinciding_pairs(spec):
  """Part index pairs (i < j) joined by a mating connector pair that coincides when assembled."""
  index = {p.name: i for i, p in enumerate(spec.parts)}
  return sorted({tuple(sorted((index[spec.connectors[a].part], index[spec.connectors[b].part])))
                 for a, b in spec.assembled_connector_pairs()})


def _anchor_folders(root, model_dir):
  """Makes the <compiler>'s asset folders absolute (the file's own folder where it names
  none), so that the document compiles from memory as it does from its file."""
  compiler = root.find("compiler")
  if compiler is None:
    compiler = ET.SubElement(root, "compiler")
  for key in ("meshdir", "texturedir", "assetdir"):
    if compiler.get(key) is not None and not os.path.isabs(compiler.get(key)):
      compiler.set(key, str((model_dir / compiler.get(key)).resolve()))
  if compiler.get("assetdir") is None:
    for key in ("meshdir", "texturedir"):
      if compiler.get(key) is None:
        compiler.set(key, str(model_dir.resolve()))


def read_document(path: str | os.PathLike) -> ET.Element:
  """The parsed <mujoco> element of a furniture file, asset folders made absolute.

  Args:
    path: the model file.
  Returns:
    An xml.etree.ElementTree.Element.
  Raises:
    ModelFormatError: no such file, XML that is not well-formed, or another root element.
  """
  path = pathlib.Path(path)
  if not path.is_file():
    raise errors.ModelFormatError(path, "<file>", "no such file")
  try:
    root = ET.parse(path).getroot()
  except ET.ParseError as e:
    raise errors.ModelFormatError(path, "<file>", f"not well-formed XML: {e}") from None
  if root.tag != "mujoco":
    raise errors.ModelFormatError(path, f"<{root.tag}>", "root element must be <mujoco>")
  _anchor_folders(root, path.parent)
  return root


def spec_from_document(root: ET.Element, path: str | os.PathLike,
                       scale: float = 1.0) -> furniture_spec.FurnitureSpec:
  """Validates a furniture document (read_document's, perhaps scaled) into its FurnitureSpec.

  Args:
    root: the <mujoco> element; the spec keeps it (and its part elements) as they are.
    path: the model file it was read from, named in errors.
    scale: the size factor `root` was scaled by against the file.
  Returns:
    The FurnitureSpec.
  Raises:
    ModelFormatError: on any fault, naming the file and the element.
  """
  path = pathlib.Path(path)
  _check_names_unique(root, path)
  model = _compile(root, path)
  texts = _read_texts(root, path)
  parts = _read_parts(root, model, path)
  connectors = _read_connectors(parts, texts, path)
  _check_mates(parts, connectors, path)
  compiler = root.find("compiler")
  return furniture_spec.FurnitureSpec(
      name=root.get("model") or path.stem,
      path=str(path),
      parts=tuple(parts),
      connectors=tuple(sorted(connectors, key=lambda c: c.name)),
      metadata=parse_key_values(texts.get(FURNITURE_TEXT, ""), path, f"<text name={FURNITURE_TEXT!r}>"),
      assets=root.find("asset") if root.find("asset") is not None else ET.Element("asset"),
      compiler=dict(compiler.attrib) if compiler is not None else {},
      document=root, scale=float(scale))


def load_spec(path: str | os.PathLike) -> furniture_spec.FurnitureSpec:
  """Reads and validates a furniture file into its FurnitureSpec (at the file's own size).

  Args:
    path: the model file.
  Returns:
    The FurnitureSpec.
  Raises:
    ModelFormatError: on any fault, naming the file and the element.
  """
  return spec_from_document(read_document(path), path)
