"""Model validation (format, graph, overlap, stability), assembly sequences, and importing
a user's own furniture from meshes and connector definitions."""

import json

import numpy as np
import pytest
import trimesh

from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction
from ikea_suite.design import decompose
from ikea_suite.design import import_model
from ikea_suite.design import mjcf_writer
from ikea_suite.assembly import sequence
from ikea_suite.design import shapes
from ikea_suite.design import validate
from ikea_suite.props import catalog
from ikea_suite.props import model_format
from ikea_suite.tasks import planner


def test_every_catalog_model_is_valid():
  problems = {name: validate.check(catalog.path_of(name)).problems for name in catalog.names()}
  assert {name: p for name, p in problems.items() if p} == {}


def test_validate_command_reports_and_exits_zero(capsys):
  assert validate.main(["table_four_leg_lack", "chair_armrest_birch"]) == 0
  out = capsys.readouterr().out
  assert "ok   table_four_leg_lack" in out and "2/2 models valid" in out


def _board(size, material="birch"):
  return [bp.Geom("box", tuple(s / 2 for s in size), material=material,
                  construction=construction.BIRCH)]


def _stand(name, top_z=0.4, leg_x=0.2, top_offset=0.0, top_size=(0.5, 0.4, 0.03)):
  """A top on one leg: the leg stands at leg_x, the top's centre sits top_offset beside it."""
  furniture = bp.Blueprint(name, "table", "test", name.split("_")[-1], "test model")
  leg = furniture.add_part("leg", (leg_x, 0, top_z / 2), geoms=_board((0.05, 0.05, top_z)))
  top = furniture.add_part("top", (leg_x + top_offset, 0, top_z + 0.015), geoms=_board(top_size))
  furniture.connect(leg, top, (leg_x, 0, top_z), (0, 0, 1), (1, 0, 0), "leg_top", "top_slot")
  return furniture


def _check(furniture, tmp_path):
  return validate.check(mjcf_writer.write(furniture, tmp_path))


def test_a_top_balanced_on_a_thin_leg_topples(tmp_path):
  report = _check(_stand("table_test_topples", top_offset=0.2), tmp_path)
  assert any(p.startswith("stability:") for p in report.problems), report.problems


def test_interpenetrating_parts_are_reported(tmp_path):
  furniture = _stand("table_test_overlap", top_size=(0.5, 0.4, 0.03))
  furniture.part("top").pos[2] -= 0.02    # sinks 2 cm into the leg
  furniture.part("top").connectors[0].pos[2] += 0.02
  report = _check(furniture, tmp_path)
  assert any(p.startswith("overlap: leg and top") for p in report.problems), report.problems


def test_a_disconnected_assembly_graph_is_reported(tmp_path):
  furniture = _stand("table_test_apart")
  other = _stand("x", leg_x=-0.3)
  for part in other.parts:
    part.name = f"{part.name}2"
    for c in part.connectors:
      c.name = f"{part.name}_{c.type}"
    furniture.parts.append(part)
  # Wide feet so that both halves stand on their own.
  for part in furniture.parts:
    if part.name.startswith("leg"):
      part.geoms.append(bp.Geom("box", (0.15, 0.15, 0.005), pos=(0, 0, -0.195)))
  report = _check(furniture, tmp_path)
  assert any(p.startswith("graph: parts fall into 2") for p in report.problems), report.problems


def test_a_connector_without_a_mate_fails_the_format_check(tmp_path):
  furniture = _stand("table_test_orphan")
  furniture.part("top").connectors[0].mates = "nothing"
  report = _check(furniture, tmp_path)
  assert report.problems and report.problems[0].startswith("format:")


@pytest.mark.parametrize("name", ["bookcase_shelf_unit_w80_h106_white", "dresser_chest_four_white",
                                  "table_coffee_shelf_w90_birch", "bed_slatted_kids_white"])
def test_assembly_sequences_insert_every_part_along_a_free_path(name):
  spec = catalog.spec(name)
  root = planner.root_part(spec)
  steps = sequence.plan(spec, root)
  assert sorted(s.part for s in steps) == sorted(set(range(len(spec.parts))) - {root})
  for s in steps:
    assert np.allclose(s.waypoints[-1], 0) and len(s.waypoints) >= 2
  # Each part joins something already there.
  pairs = model_format.coinciding_pairs(spec)
  placed = {root}
  for s in steps:
    assert any((min(s.part, p), max(s.part, p)) in pairs for p in placed), spec.parts[s.part].name
    placed.add(s.part)


def test_sequences_put_shelves_in_before_the_closing_side_panel():
  spec = catalog.spec("bookcase_shelf_unit_w80_h106_white")
  order = [spec.parts[s.part].name for s in sequence.plan(spec, planner.root_part(spec))]
  assert order.index("side1") > max(order.index(n) for n in order if n.startswith("shelf"))


def _write_mesh(mesh, path):
  mesh.export(str(path))
  return path.name


def test_import_own_furniture_from_meshes_and_connectors(tmp_path, monkeypatch):
  monkeypatch.setenv(decompose.CACHE_ENV, str(tmp_path / "cache"))
  # A small side table: a top, two panel legs, and a concave U-shaped stretcher in mm.
  top = _write_mesh(trimesh.creation.box((500, 400, 30)), tmp_path / "top.stl")
  leg = _write_mesh(trimesh.creation.box((30, 350, 420)), tmp_path / "leg.obj")
  u = shapes.extrude_polygon([(-182, 0), (182, 0), (182, 80), (152, 80), (152, 30), (-152, 30),
                              (-152, 80), (-182, 80)], 40, plane="xz")
  stretcher = _write_mesh(u, tmp_path / "stretcher.stl")
  spec = {"name": "table_custom_side", "category": "table", "family": "custom", "variant": "side",
          "parts": [{"name": "top", "mesh": top, "pos": [0, 0, 0.435], "scale": 0.001},
                    {"name": "leg0", "mesh": leg, "pos": [-0.2, 0, 0.21], "scale": 0.001},
                    {"name": "leg1", "mesh": leg, "pos": [0.2, 0, 0.21], "scale": 0.001},
                    {"name": "stretcher", "mesh": stretcher, "pos": [0, 0, 0.1], "scale": 0.001,
                     "material": "metal"}],
          "connections": [
              {"a": "leg0", "b": "top", "pos": [-0.2, 0, 0.42], "up": [0, 0, 1],
               "forward": [1, 0, 0], "type_a": "leg_top", "type_b": "top_leg_slot",
               "twists": [0, 180]},
              {"a": "leg1", "b": "top", "pos": [0.2, 0, 0.42], "up": [0, 0, 1],
               "forward": [1, 0, 0], "type_a": "leg_top", "type_b": "top_leg_slot",
               "twists": [0, 180]},
              {"a": "stretcher", "b": "leg0", "pos": [-0.185, 0, 0.1], "up": [-1, 0, 0],
               "forward": [0, 0, 1], "type_a": "stretcher_end", "type_b": "leg_stretcher_slot"}]}
  # leg1 carries the same stretcher slot as leg0 so the legs stay interchangeable.
  spec["connections"].append({"a": "stretcher", "b": "leg1", "pos": [0.185, 0, 0.1],
                              "up": [1, 0, 0], "forward": [0, 0, 1], "type_a": "stretcher_end",
                              "type_b": "leg_stretcher_slot"})
  (tmp_path / "side.json").write_text(json.dumps(spec))
  out = tmp_path / "models"
  assert import_model.main([str(tmp_path / "side.json"), "--out", str(out)]) == 0
  loaded = model_format.load_spec(str(out / "table_custom_side.xml"))
  assert [p.name for p in loaded.parts] == ["top", "leg0", "leg1", "stretcher"]
  # The concave U collides through several convex pieces; the boxes through themselves.
  stretcher_geoms = list(loaded.parts[3].element.iter("geom"))
  colliding = [g for g in stretcher_geoms if g.get("contype") != "0"]
  assert len(colliding) >= 3 and len(list((tmp_path / "cache").glob("*.json"))) == 1
  assert len(list(loaded.parts[0].element.iter("geom"))) == 1


def test_import_rejects_unknown_parts_and_materials(tmp_path):
  top = _write_mesh(trimesh.creation.box((0.5, 0.4, 0.03)), tmp_path / "top.stl")
  spec = {"name": "table_custom_bad", "category": "table", "family": "custom", "variant": "bad",
          "parts": [{"name": "top", "mesh": top, "pos": [0, 0, 0.4], "material": "gold"}],
          "connections": []}
  with pytest.raises(ValueError, match="material 'gold'"):
    import_model.blueprint_from_spec(spec, tmp_path)
  spec["parts"][0]["material"] = "birch"
  spec["connections"] = [{"a": "top", "b": "leg", "pos": [0, 0, 0], "up": [0, 0, 1],
                          "forward": [1, 0, 0], "type_a": "x", "type_b": "y"}]
  with pytest.raises(ValueError, match="names part 'leg'"):
    import_model.blueprint_from_spec(spec, tmp_path)
