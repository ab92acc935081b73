"""Bring your own furniture: part meshes (STL/OBJ) plus connector definitions -> a model.

    python -m ikea_suite.design.import_model my_table.json --out models/furniture

The JSON file names the furniture and lists its parts and connections:

    {"name": "table_custom_mine", "category": "table", "family": "custom", "variant": "mine",
     "description": "my table",
     "parts": [{"name": "top", "mesh": "top.stl", "pos": [0, 0, 0.72],
                "quat": [1, 0, 0, 0], "material": "wood_light", "scale": 0.001}, ...],
     "connections": [{"a": "leg0", "b": "top", "pos": [0.3, 0.2, 0.7], "up": [0, 0, 1],
                      "forward": [1, 0, 0], "type_a": "leg_top", "type_b": "top_leg_slot",
                      "twists": [0, 90, 180, 270]}, ...]}

Meshes are in the part's own frame (metres after `scale`); `pos` and `quat`
place each part in the assembled furniture, floor at z = 0. Each connection
puts a connector on both parts at one world frame (`up` is the connector's
z axis, `forward` its x axis; `twists` are the allowed turns about up in
degrees, [] for any). A part's optional "construction" names what it is made
of, one of the solid constructions of construction.py ("particleboard",
"solid pine", "solid birch", "solid oak", "MDF"; default particleboard, the
usual flat-pack board): its mass is the mesh's volume at that density. A convex
mesh collides as itself; a concave one
through coacd convex pieces, cached by content hash (see decompose). The
written model then goes through the same validation as the catalog.
"""

import argparse
import json
import pathlib
import sys

import numpy as np
import trimesh

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import decompose
from ikea_suite.design import materials
from ikea_suite.design import mjcf_writer
from ikea_suite.design import part_geoms
from ikea_suite.design import validate


def load_mesh(path, scale=1.0):
  """A single watertight-or-not triangle mesh from an STL or OBJ file, scaled to metres."""
  mesh = trimesh.load(str(path), force="mesh")
  if not isinstance(mesh, trimesh.Trimesh) or not len(mesh.faces):
    raise errors.ImportSpecError(f"{path}: no triangle mesh in the file")
  mesh.apply_scale(scale)
  return mesh


def part_geometry(furniture, mesh, prefix, material, construction=cons.PARTICLEBOARD):
  """Visual mesh plus collision: the mesh itself when convex, else its coacd pieces."""
  if mesh.is_convex:
    name = part_geoms.register_mesh(furniture, mesh, prefix)
    return [bp.Geom("mesh", mesh=name, material=material, construction=construction)]
  return part_geoms.concave(furniture, mesh, prefix, material, construction)


def blueprint_from_spec(spec, base_dir="."):
  """A Blueprint from the JSON-like dict described in this module's docstring."""
  base_dir = pathlib.Path(base_dir)
  for key in ("name", "category", "family", "variant", "parts", "connections"):
    if key not in spec:
      raise errors.ImportSpecError(f"furniture spec needs '{key}'")
  if not spec["name"].startswith(f"{spec['category']}_{spec['family']}_"):
    raise errors.ImportSpecError(f"name {spec['name']!r} should read category_family_variant")
  furniture = bp.Blueprint(spec["name"], spec["category"], spec["family"], spec["variant"],
                           spec.get("description", spec["name"]))
  for item in spec["parts"]:
    material = item.get("material", "wood_light")
    if material not in materials.MATERIALS:
      raise errors.ImportSpecError(f"part {item['name']!r}: material {material!r} is not one of "
                       f"{sorted(materials.MATERIALS)}")
    construction = item.get("construction", cons.PARTICLEBOARD.name)
    if construction not in cons.SOLIDS:
      raise errors.ImportSpecError(f"part {item['name']!r}: construction {construction!r} is not one of "
                       f"{sorted(cons.SOLIDS)}")
    mesh = load_mesh(base_dir / item["mesh"], item.get("scale", 1.0))
    rot = geometry.quat_to_mat(np.asarray(item.get("quat", (1, 0, 0, 0)), float))
    furniture.add_part(item["name"], item["pos"], rot,
                       part_geometry(furniture, mesh, item["name"], material,
                                     cons.SOLIDS[construction]))
  names = {p.name for p in furniture.parts}
  for c in spec["connections"]:
    for key in ("a", "b"):
      if c[key] not in names:
        raise errors.ImportSpecError(f"connection names part {c[key]!r}; parts are {sorted(names)}")
    furniture.connect(furniture.part(c["a"]), furniture.part(c["b"]), c["pos"], c["up"],
                      c["forward"], c["type_a"], c["type_b"], tuple(c.get("twists", (0,))))
  return furniture


def import_model(spec_path, out_dir):
  """Writes the model described by a JSON file into `out_dir`; returns (xml path, report)."""
  spec_path = pathlib.Path(spec_path)
  furniture = blueprint_from_spec(json.loads(spec_path.read_text()), spec_path.parent)
  path = mjcf_writer.write(furniture, out_dir)
  return path, validate.check(path)


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("spec", help="furniture JSON file (mesh paths relative to it)")
  parser.add_argument("--out", required=True, help="directory for the model and its meshes")
  args = parser.parse_args(argv)
  path, report = import_model(args.spec, args.out)
  print(f"wrote {path} (coacd cache: {decompose.cache_dir()})")
  print("valid" if report.ok else "INVALID:\n  " + "\n  ".join(report.problems))
  return 0 if report.ok else 1


if __name__ == "__main__":
  sys.exit(main())
