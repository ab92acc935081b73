"""Writes a Blueprint as one self-describing furniture MJCF file (see model_format).

Every part body gets an explicit `<inertial>` computed from the constructions
of its geoms (mass_properties): MuJoCo then ignores geom-derived inertia
(compiler `inertiafromgeom="auto"`), so geoms carry no density.
"""

import pathlib
import types
import xml.etree.ElementTree as ET

import numpy as np

from ikea_suite import geometry
from ikea_suite import physics_settings
from ikea_suite.assembly import mating
from ikea_suite.design import mass_properties
from ikea_suite.design import materials
from ikea_suite.props import model_format

MESH_FORMAT = "stl"   # binary STL: compact, and MuJoCo reads it directly
MESH_DIR = "meshes"


def _fmt(values):
  return " ".join(f"{v:.6g}" if abs(v) > 1e-12 else "0" for v in np.ravel(values))


def _quat(rot):
  return _fmt(geometry.mat_to_quat(rot))


def _add_geom(body, part, index, geom):
  attrs = {"name": f"{part.name}_geom{index}", "type": geom.type, "material": geom.material,
           "pos": _fmt(geom.pos), "quat": _quat(geom.rot)}
  if geom.type == "mesh":
    attrs["mesh"] = geom.mesh
  else:
    attrs["size"] = _fmt(geom.size)
  if not geom.collide:
    attrs.update(contype="0", conaffinity="0", group="1")
  if not geom.visible:
    del attrs["material"]
    attrs.update(group="3", rgba="0 0 0 0")
  ET.SubElement(body, "geom", attrs)


def _add_inertial(body, part, meshes):
  """The part's mass, centre of mass and full inertia tensor (about the centre of mass).

  Inertia is written with 8 significant digits: a thin sheet's principal moments
  nearly meet the triangle inequality (Ixx + Iyy >= Izz), which 6 digits can break.
  """
  props = mass_properties.part_properties(part, meshes)
  i = props.inertia
  full = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
  ET.SubElement(body, "inertial", pos=_fmt(props.com), mass=f"{props.mass:.6g}",
                fullinertia=" ".join(f"{v:.8g}" if abs(v) > 1e-12 else "0" for v in full))


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
  # The suite's physics, so the file behaves in plain MuJoCo as it does in the suite.
  ET.SubElement(root, "option", {k: f"{v:g}" if isinstance(v, float) else str(v)
                                 for k, v in physics_settings.OPTION.items()})
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
    _add_inertial(body, part, blueprint.meshes)
    for i, geom in enumerate(part.geoms):
      _add_geom(body, part, i, geom)
    for c in part.connectors:
      ET.SubElement(body, "site", name=c.name, pos=_fmt(c.pos), quat=_quat(c.rot),
                    size="0.01", rgba="1 0.2 0.2 0.6", group="3")
      twists = " ".join(f"{t:g}" for t in c.twists_deg)
      ET.SubElement(custom, "text", name=model_format.CONNECTOR_PREFIX + c.name,
                    data=f"type={c.type}; mates={c.mates}; twists={twists}")
  # Holds the furniture together when the file is simulated in plain MuJoCo: one
  # weld per pair of parts with coinciding mates, as the task welds them once
  # assembled. ikea_suite ignores this block and declares its own inactive welds.
  equality = ET.SubElement(root, "equality")
  for a, b in _mated_pairs(blueprint):
    ET.SubElement(equality, "weld", body1=a, body2=b, solref=_fmt(physics_settings.WELD_SOLREF),
                  solimp=_fmt(physics_settings.WELD_SOLIMP),
                  torquescale=f"{physics_settings.WELD_TORQUESCALE:g}")
  ET.indent(root, space="  ")
  return ET.tostring(root, encoding="unicode") + "\n"


def _mated_pairs(blueprint):
  """Names of part pairs joined by coinciding mating connectors, in part order."""
  connectors = [types.SimpleNamespace(part=p.name, type=c.type, mates=c.mates, pos=c.pos,
                                      rot=c.rot, twists=np.radians(c.twists_deg))
                for p in blueprint.parts for c in p.connectors]
  pose = {p.name: (p.pos, p.rot) for p in blueprint.parts}
  order = {p.name: i for i, p in enumerate(blueprint.parts)}
  pairs = {tuple(sorted((connectors[a].part, connectors[b].part), key=order.get))
           for a, b in mating.coinciding_connector_pairs(connectors, pose)}
  return sorted(pairs, key=lambda pair: (order[pair[0]], order[pair[1]]))


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
