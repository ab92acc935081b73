"""Writes a Blueprint as one self-describing furniture MJCF file (see model_format)."""

import pathlib
import xml.etree.ElementTree as ET

import numpy as np

from ikea_suite import geometry
from ikea_suite.design import materials
from ikea_suite.props import model_format

MESH_FORMAT = "stl"   # binary STL: compact, and MuJoCo reads it directly
MESH_DIR = "meshes"
WELD_SOLREF = "0.01 1"   # as stiff as the task's welds (ikea_suite.tasks.welds)


def _fmt(values):
  return " ".join(f"{v:.6g}" if abs(v) > 1e-12 else "0" for v in np.ravel(values))


def _quat(rot):
  return _fmt(geometry.mat_to_quat(rot))


def _density(geom):
  if geom.density is not None:
    return geom.density
  return materials.DENSITY.get(geom.material, materials.DEFAULT_DENSITY)


def _add_geom(body, part, index, geom):
  attrs = {"name": f"{part.name}_geom{index}", "type": geom.type, "material": geom.material,
           "pos": _fmt(geom.pos), "quat": _quat(geom.rot),
           "density": f"{_density(geom):g}"}
  if geom.type == "mesh":
    attrs["mesh"] = geom.mesh
  else:
    attrs["size"] = _fmt(geom.size)
  if not geom.collide:
    attrs.update(contype="0", conaffinity="0", group="1", density="0")
  if not geom.visible:
    del attrs["material"]
    attrs.update(group="3", rgba="0 0 0 0")
  ET.SubElement(body, "geom", attrs)


def mesh_file_names(blueprint):
  """Mesh asset name -> file name (under meshdir) of every mesh the blueprint uses."""
  return {name: f"{name}.{MESH_FORMAT}" for name in blueprint.meshes}


def mesh_bytes(mesh):
  return mesh.export(file_type=MESH_FORMAT)


def blueprint_to_xml(blueprint, mesh_files=None):
  """The MJCF text of a blueprint; `mesh_files` maps mesh asset names to file names
  (default: the blueprint's own meshes, see `mesh_file_names`)."""
  if mesh_files is None:
    mesh_files = mesh_file_names(blueprint)
  root = ET.Element("mujoco", model=blueprint.name)
  ET.SubElement(root, "compiler", angle="radian", meshdir=MESH_DIR)
  custom = ET.SubElement(root, "custom")
  meta = (f"category={blueprint.category}; family={blueprint.family}; "
          f"variant={blueprint.variant}; description={blueprint.description}"
          + "".join(f"; {key}={value}" for key, value in blueprint.metadata.items()))
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
  # Holds the furniture together when the file is simulated in plain MuJoCo: one
  # weld per pair of parts with coinciding mates, as if every joint were screwed.
  # ikea_suite ignores this block and declares its own inactive welds.
  equality = ET.SubElement(root, "equality")
  for a, b in _mated_pairs(blueprint):
    ET.SubElement(equality, "weld", body1=a, body2=b, solref=WELD_SOLREF)
  ET.indent(root, space="  ")
  return ET.tostring(root, encoding="unicode") + "\n"


def _mated_pairs(blueprint):
  """Names of part pairs joined by coinciding mating connectors, in part order."""
  parts = blueprint.parts
  return [(a.name, b.name) for i, a in enumerate(parts) for b in parts[i + 1:] if _mated(a, b)]


def _mated(a, b):
  for ca in a.connectors:
    pa = a.pos + a.rot @ ca.pos
    for cb in b.connectors:
      if ca.mates == cb.type and np.linalg.norm(pa - (b.pos + b.rot @ cb.pos)) < 1e-6:
        return True
  return False


def model_files(blueprint):
  """Relative path -> bytes of every file the model needs: its XML and its meshes."""
  files = {f"{blueprint.name}.xml": blueprint_to_xml(blueprint).encode()}
  for name, filename in mesh_file_names(blueprint).items():
    files[f"{MESH_DIR}/{filename}"] = mesh_bytes(blueprint.meshes[name])
  return files


def write(blueprint, directory):
  """Writes the model and its meshes under `directory`; returns the XML path."""
  directory = pathlib.Path(directory)
  for relative, data in model_files(blueprint).items():
    (directory / relative).parent.mkdir(parents=True, exist_ok=True)
    (directory / relative).write_bytes(data)
  return directory / f"{blueprint.name}.xml"
