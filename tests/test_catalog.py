"""The furniture catalog: size, names, filters, the mesh pipeline and the stale-models check."""

import shutil

import numpy as np
import pytest

import ikea_suite
from ikea_suite.assembly import sequence
from ikea_suite.design import build
from ikea_suite.design import family_models
from ikea_suite.design import decompose
from ikea_suite.design import shapes
from ikea_suite.props import catalog
from ikea_suite.props import model_format


def test_catalog_has_at_least_100_models_in_10_categories_from_2_to_14_parts():
  entries = catalog.entries().values()
  assert len(entries) >= 100
  assert len(catalog.categories()) >= 10
  parts = [e.num_parts for e in entries]
  assert min(parts) == 2 and max(parts) >= 14
  assert all(n <= model_format.MAX_PARTS for n in parts)
  assert catalog.counts() == {c: len(catalog.names(category=c)) for c in catalog.categories()}


def test_names_read_category_family_variant_and_match_the_metadata():
  for entry in catalog.entries().values():
    assert entry.name == f"{entry.category}_{entry.family}_{entry.variant}"
    assert entry.name.islower() and " " not in entry.name
    assert {entry.category, entry.family, f"parts_{entry.num_parts}"} <= entry.tags


def test_the_starter_models_keep_their_names():
  for name in ("table_four_leg_lack", "stool_round_frosta", "chair_back_ivar",
               "bookcase_shelf_unit_billy", "box_open_kuggis"):
    assert name in catalog.entries()


def test_filters_by_tag_category_and_part_count():
  small = catalog.names(max_parts=4)
  assert small and all(catalog.entries()[n].num_parts <= 4 for n in small)
  big = catalog.names(min_parts=12)
  assert big and all(catalog.entries()[n].num_parts >= 12 for n in big)
  beds = catalog.names(category="bed")
  assert beds and beds == catalog.names(tag="bed")
  concave = catalog.names(tag="concave")
  assert concave and set(concave) < set(catalog.names())
  assert ikea_suite.furniture_names(tag="chair", min_parts=6) == catalog.names(
      tag="chair", min_parts=6)
  assert ("table", "trestle") in catalog.families("table")


def test_representatives_are_one_model_per_category():
  reps = catalog.representatives()
  assert [catalog.entries()[n].category for n in reps] == catalog.categories()


def test_load_accepts_any_catalog_name():
  env = ikea_suite.load("desk_side_unit_w120_white", "cursor", seed=0)
  env.reset()
  assert len(env.task.furniture.parts) == catalog.entries()["desk_side_unit_w120_white"].num_parts


def _signature(part):
  """What a part is made of: its geoms (type, size, mesh, offsets), not where it sits."""
  return tuple((g.get("type"), g.get("size"), g.get("mesh"), g.get("pos"), g.get("quat"))
               for g in part.element.iter("geom"))


def _connector_set(spec, part, mirror=1):
  return sorted((c.type, tuple(np.round(c.pos * [mirror, 1, 1], 5)))
                + ((tuple(np.round(c.rot.ravel(), 4)),) if mirror == 1 else ())
                for c in spec.connectors if c.part == part.name)


def test_identical_parts_are_interchangeable():
  """Parts made alike carry the same connectors in the same places, so any fits any slot.

  The one exception is a carcass's left and right side panels: one board, drilled
  as mirror images (the shelves, back and plinth sit off-centre in depth; a
  one-door cabinet has hinge holes on one side only).
  """
  shared = mirrored = 0
  for entry in catalog.entries().values():
    spec = catalog.spec(entry.name)
    groups = {}
    for part in spec.parts:
      groups.setdefault(_signature(part), []).append(part)
    for parts in groups.values():
      reference = _connector_set(spec, parts[0])
      for other in parts[1:]:
        if _connector_set(spec, other) == reference:
          shared += 1
          continue
        assert parts[0].name.endswith("side0") and other.name.endswith("side1"), (
            entry.name, parts[0].name, other.name)
        shelves = sorted((kind, pos) for kind, pos, _ in reference if "hinge" not in kind)
        assert shelves and [c for c in _connector_set(spec, other, mirror=-1)
                            if "hinge" not in c[0]] == shelves, (entry.name, "sides not mirrored")
        mirrored += 1
  assert shared > 300 and mirrored < shared / 4


def test_models_directory_is_up_to_date():
  assert build.build_all(build.paths.furniture_dir(), check=True) == []


def test_stale_and_extra_files_are_detected_and_rebuilt(tmp_path):
  target = tmp_path / "furniture"
  shutil.copytree(build.paths.furniture_dir(), target)
  victim = target / "table_four_leg_lack.xml"
  victim.write_text(victim.read_text().replace("0.425", "0.426"))
  (target / "sofa_nobody_makes.xml").write_text("<mujoco/>")
  stale = build.build_all(target, check=True)
  assert "table_four_leg_lack.xml" in stale
  assert "sofa_nobody_makes.xml (no family makes it)" in stale
  build.build_all(target)
  assert build.build_all(target, check=True) == []
  assert not (target / "sofa_nobody_makes.xml").exists()


def test_blueprints_are_deterministic():
  first = build.generated_files()
  family_models.clear_cache()
  assert build.generated_files() == first


@pytest.mark.parametrize("mesh", [
    shapes.bevelled_board((0.5, 0.3, 0.02)), shapes.round_leg(0.02, 0.4),
    shapes.frame(0.4, 0.5, 0.02, 0.05), shapes.curved_board(0.42, 0.05, 0.3, 0.02),
    shapes.l_bracket(0.06, 0.05, 0.2, 0.004),
    shapes.extrude_polygon(shapes.t_profile(0.6, 0.7, 0.06, 0.05), 0.04)])
def test_shapes_are_closed_solids(mesh):
  assert mesh.is_watertight and mesh.is_volume and mesh.volume > 0
  assert np.allclose(mesh.bounds[0], -mesh.bounds[1], atol=1e-9)   # centred on the origin


def test_shape_extents_match_their_parameters():
  assert np.allclose(shapes.bevelled_board((0.5, 0.3, 0.02)).extents, (0.5, 0.3, 0.02))
  frame = shapes.frame(0.4, 0.5, 0.02, 0.05, plane="yz")
  assert np.allclose(frame.extents, (0.02, 0.4, 0.5))
  assert not frame.is_convex and shapes.bevelled_board((1, 1, 1)).is_convex


def test_concave_parts_are_decomposed_from_the_committed_cache(monkeypatch):
  def no_coacd(*args):
    raise AssertionError("coacd ran although the cache holds this mesh")
  monkeypatch.setattr(decompose, "_run_coacd", no_coacd)
  mesh = shapes.frame(0.42, 0.4, 0.02, 0.05)   # the frame back of chair_frame_back_oak
  pieces = decompose.convex_pieces(mesh)
  assert len(pieces) >= 4 and all(p.is_convex for p in pieces)


def test_a_cache_miss_runs_coacd_once_and_stores_the_result(tmp_path, monkeypatch):
  monkeypatch.setenv(decompose.CACHE_ENV, str(tmp_path))
  mesh = shapes.l_bracket(0.07, 0.05, 0.1, 0.005)
  pieces = decompose.convex_pieces(mesh)
  stored = list(tmp_path.glob("*.json"))
  assert len(stored) == 1 and stored[0].name.startswith(decompose.content_key(mesh)[:24])
  assert len(pieces) >= 2 and all(p.is_convex for p in pieces)
  # The pieces cover the L: together at least its volume, each inside its bounds.
  assert sum(p.volume for p in pieces) >= 0.95 * mesh.volume
  for p in pieces:
    assert np.all(p.bounds[0] >= mesh.bounds[0] - 1e-3) and np.all(p.bounds[1] <= mesh.bounds[1] + 1e-3)
  monkeypatch.setattr(decompose, "_run_coacd", lambda *a: pytest.fail("coacd ran twice"))
  again = decompose.convex_pieces(mesh)
  assert [p.vertices.tolist() for p in again] == [p.vertices.tolist() for p in pieces]


def test_content_key_depends_on_geometry_and_parameters():
  a = shapes.frame(0.4, 0.5, 0.02, 0.05)
  b = shapes.frame(0.4, 0.5, 0.02, 0.06)
  assert decompose.content_key(a) == decompose.content_key(shapes.frame(0.4, 0.5, 0.02, 0.05))
  assert decompose.content_key(a) != decompose.content_key(b)
  assert decompose.content_key(a) != decompose.content_key(a, {**decompose.PARAMS, "seed": 1})


def test_a_furniture_flows_as_one_spec_from_the_catalog_to_the_task_and_the_sequencer():
  spec = catalog.spec("table_four_leg_lack")
  assert catalog.spec("table_four_leg_lack") is spec   # read once, by the catalog's scan
  env = ikea_suite.load("table_four_leg_lack", "cursor", seed=0)
  assert env.task.furniture.spec is spec and env.task.furniture.scale == 1.0
  steps = sequence.plan(spec, env.task.root_part, sequence.HOLD_LIFT)
  assert sequence.plan(spec, env.task.root_part, sequence.HOLD_LIFT) is steps   # planned once
  assert env.task.assembly_order == (env.task.root_part,) + tuple(s.part for s in steps)
  small = ikea_suite.load("table_four_leg_lack", "cursor", seed=0, scale=0.5).task.furniture
  assert small.scale == 0.5 and small.spec.path == spec.path and small.spec is not spec
  with pytest.raises(ikea_suite.UnknownNameError):
    catalog.spec("no_such_table")
  with pytest.raises(ikea_suite.OptionValueError, match="scale must be"):
    catalog.spec("table_four_leg_lack", scale=9)
