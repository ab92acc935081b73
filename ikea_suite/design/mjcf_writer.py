"""Writes a Blueprint as one self-describing furniture MJCF file (see model_format)."""

import pathlib
import xml.etree.ElementTree as ET

import numpy as np

from ikea_suite import geometry
from ikea_suite.design import materials
from ikea_suite.props import model_format


def _fmt(values):
  return " ".join(f"{v:.6g}" if abs(v) > 1e-12 else "0" for v in np.ravel(values))


def _quat(rot):
  return _fmt(geometry.mat_to_quat(rot))


def _add_geom(body, part, index, geom):
  attrs = {"name": f"{part.name}_geom{index}", "type": geom.type, "material": geom.material,
           "pos": _fmt(geom.pos), "quat": _quat(geom.rot),
           "density": f"{materials.DENSITY.get(geom.material, materials.DEFAULT_DENSITY):g}"}
  if geom.type == "mesh":
    attrs["mesh"] = geom.mesh
  else:
    attrs["size"] = _fmt(geom.size)
  if not geom.collide:
    attrs.update(contype="0", conaffinity="0", group="1", density="0")
  ET.SubElement(body, "geom", attrs)


def blueprint_to_xml(blueprint, mesh_files=None):
  """The MJCF text of a blueprint; `mesh_files` maps mesh asset names to file names."""
  root = ET.Element("mujoco", model=blueprint.name)
  ET.SubElement(root, "compiler", angle="radian", meshdir="meshes")
  custom = ET.SubElement(root, "custom")
  meta = (f"category={blueprint.category}; family={blueprint.family}; "
          f"variant={blueprint.variant}; description={blueprint.description}")
  ET.SubElement(custom, "text", name=model_format.FURNITURE_TEXT, data=meta)
  asset = ET.SubElement(root, "asset")
  for name, (rgba, specular, shininess) in materials.MATERIALS.items():
    ET.SubElement(asset, "material", name=name, rgba=_fmt(rgba),
                  specular=f"{specular:g}", shininess=f"{shininess:g}")
  for name, filename in sorted((mesh_files or {}).items()):
    ET.SubElement(asset, "mesh", name=name, file=filename)
  world = ET.SubElement(root, "worldbody")
  ET.SubElement(world, "geom", name="floor", type="plane", size="2 2 0.05", rgba="0.8 0.8 0.8 1")
  ET.SubElement(world, "light", pos="0 -1 3", dir="0 0.3 -1", directional="true")
  for part in blueprint.parts:
    body = ET.SubElement(world, "body", name=part.name, pos=_fmt(part.pos), quat=_quat(part.rot))
    ET.SubElement(body, "freejoint", name=part.name)
    for i, geom in enumerate(part.geoms):
      _add_geom(body, part, i, geom)
    for c in part.connectors:
      ET.SubElement(body, "site", name=c.name, pos=_fmt(c.pos), quat=_quat(c.rot),
                    size="0.01", rgba="1 0.2 0.2 0.6", group="3")
      twists = " ".join(f"{t:g}" for t in c.twists_deg)
      ET.SubElement(custom, "text", name=model_format.CONNECTOR_PREFIX + c.name,
                    data=f"type={c.type}; mates={c.mates}; twists={twists}")
  # Holds the furniture together when the file is simulated in plain MuJoCo;
  # ikea_suite ignores this block and declares its own inactive welds.
  equality = ET.SubElement(root, "equality")
  for a, b in _spanning_pairs(blueprint):
    ET.SubElement(equality, "weld", body1=a, body2=b)
  ET.indent(root, space="  ")
  return ET.tostring(root, encoding="unicode") + "\n"


def _spanning_pairs(blueprint):
  """Part pairs joined by connectors, one spanning tree (breadth first from part 0)."""
  owner = {}
  for part in blueprint.parts:
    for c in part.connectors:
      owner[c.name] = part.name
  neighbours = {p.name: [] for p in blueprint.parts}
  for a in blueprint.parts:
    for b in blueprint.parts:
      if a is not b and _mated(a, b):
        neighbours[a.name].append(b.name)
  seen, order, pairs = {blueprint.parts[0].name}, [blueprint.parts[0].name], []
  while order:
    current = order.pop(0)
    for nxt in neighbours[current]:
      if nxt not in seen:
        seen.add(nxt)
        order.append(nxt)
        pairs.append((current, nxt))
  return pairs


def _mated(a, b):
  for ca in a.connectors:
    pa = a.pos + a.rot @ ca.pos
    for cb in b.connectors:
      if ca.mates == cb.type and np.linalg.norm(pa - (b.pos + b.rot @ cb.pos)) < 1e-6:
        return True
  return False


def write(blueprint, directory, mesh_files=None):
  path = pathlib.Path(directory) / f"{blueprint.name}.xml"
  path.write_text(blueprint_to_xml(blueprint, mesh_files))
  return path
