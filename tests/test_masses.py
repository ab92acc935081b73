"""Part masses: constructions, the inertial the files carry, and plausible totals per category."""

import pathlib

import mujoco
import numpy as np
import pytest
import trimesh

import ikea_suite
from ikea_suite import cli
from ikea_suite.design import blueprint as bp
from ikea_suite.design import construction as cons
from ikea_suite.design import mass_properties as mp
from ikea_suite.design import mass_ranges
from ikea_suite.design import mass_report
from ikea_suite.design import part_geoms
from ikea_suite.design import shapes
from ikea_suite.props import catalog
from ikea_suite.props import model_format


def _specs():
  return [catalog.spec(name) for name in catalog.entries()]


def test_every_catalog_model_weighs_what_its_category_allows_for_its_size():
  outside = {s.name: mass_ranges.check(s) for s in _specs()}
  outside = {name: message for name, message in outside.items() if message}
  unexpected = {n: m for n, m in outside.items() if n not in mass_ranges.OUTSIDE}
  assert not unexpected, "\n".join(unexpected.values())
  # The documented exceptions must still be exceptions, or the list has gone stale.
  assert set(outside) == set(mass_ranges.OUTSIDE), sorted(set(mass_ranges.OUTSIDE) - set(outside))


def test_ranges_come_from_the_reference_figures_and_scale_with_surface():
  # docs/physics.md: a 55 x 55 x 45 cm side table 3-5 kg, an 80 x 28 x 202 cm bookcase 25-45 kg.
  low, high = mass_ranges.plausible("dresser", (0.80, 0.48, 0.78))
  assert low == pytest.approx(30 / mass_ranges.MARGIN) and high == pytest.approx(45 * mass_ranges.MARGIN)
  small = mass_ranges.plausible("bookcase", (0.4, 0.28, 1.06))
  large = mass_ranges.plausible("bookcase", (0.8, 0.28, 2.02))
  ratio = mass_ranges.surface((0.4, 0.28, 1.06)) / mass_ranges.surface((0.8, 0.28, 2.02))
  assert np.allclose(np.array(small) / np.array(large), ratio)
  assert set(mass_ranges.CATEGORIES) == set(catalog.categories())


def test_the_lack_style_side_table_weighs_like_the_real_one():
  spec = catalog.spec("table_four_leg_lack")
  top = spec.parts[spec.part_index("top")].mass
  assert 2.0 <= top <= 3.0          # docs/physics.md: a 55 x 55 x 5 cm honeycomb top 2-3 kg
  assert 150 <= top / (0.55 * 0.55 * 0.05) <= 300   # docs/physics.md: 150-300 kg/m^3 effective
  assert 3.0 <= spec.mass <= 5.0    # docs/physics.md: the side table 3-5 kg (listed at 3.6 kg)
  # A solid board of that size at particleboard density would weigh about 10 kg.
  solid = mp.solid_box((0.55, 0.55, 0.05), cons.PARTICLEBOARD_DENSITY).mass
  assert solid > 3 * top


def test_steel_shelving_weighs_its_metal_not_its_bounding_box():
  spec = catalog.spec("shelving_posts_steel_wide")
  shelf = spec.parts[spec.part_index("shelf0")].mass
  # 1.0 x 0.5 m of 0.8 mm sheet plus 2 cm lips round it, at 7850 kg/m^3.
  sheet = 7850 * 0.0008 * (1.0 * 0.5 + 2 * (1.0 + 0.5) * 0.0192)
  assert shelf == pytest.approx(sheet, rel=0.01)
  assert shelf < 5.0    # as a solid metal box rather than a folded sheet it would be 27 kg


def _geom(type_, size, construction, pos=(0, 0, 0), rot=None):
  return bp.Geom(type_, size, pos=pos, rot=np.eye(3) if rot is None else rot,
                 construction=construction)


def test_round_tube_matches_the_thick_walled_cylinder_formula():
  r, length, t = 0.02, 0.7, 0.0015
  props = mp.geom_properties(_geom("cylinder", (r, length / 2), cons.STEEL_TUBE), {})
  ri = r - t
  mass = 7850 * np.pi * (r ** 2 - ri ** 2) * length
  assert props.mass == pytest.approx(mass)
  assert props.inertia[2, 2] == pytest.approx(mass * (r ** 2 + ri ** 2) / 2)
  assert props.inertia[0, 0] == pytest.approx(mass * (3 * (r ** 2 + ri ** 2) + length ** 2) / 12)


def test_composite_inertia_matches_a_mesh_of_the_same_solid():
  # A box made of two halves, moved off-centre and turned, against trimesh's own integration.
  rot = bp.rot_z(0.4) @ bp.rot_x(0.3)
  pos = np.array([0.1, -0.2, 0.3])
  halves = [mp.solid_box((0.2, 0.3, 0.4), 600, center=(-0.1, 0, 0)),
            mp.solid_box((0.2, 0.3, 0.4), 600, center=(0.1, 0, 0))]
  ours = mp.combine(halves).moved(pos, rot)
  mesh = trimesh.creation.box((0.4, 0.3, 0.4))
  transform = np.eye(4)
  transform[:3, :3], transform[:3, 3] = rot, pos
  mesh.apply_transform(transform)
  truth = trimesh.triangles.mass_properties(mesh.triangles, density=600)
  assert ours.mass == pytest.approx(truth["mass"])
  assert np.allclose(ours.com, truth["center_mass"])
  assert np.allclose(ours.inertia, truth["inertia"], atol=1e-9)


def test_a_concave_part_weighs_its_mesh_volume():
  mesh = shapes.frame(0.42, 0.4, 0.02, 0.05)
  furniture = bp.Blueprint("x", "chair", "f", "v", "")
  part = furniture.add_part("back", (0, 0, 0),
                            geoms=part_geoms.concave(furniture, mesh, "f", "birch", cons.BIRCH))
  props = mp.part_properties(part, furniture.meshes)
  assert props.mass == pytest.approx(mesh.volume * cons.BIRCH_DENSITY)


def test_plates_and_honeycomb_reject_shapes_they_cannot_be():
  with pytest.raises(ValueError, match="too thin"):
    mp.geom_properties(_geom("box", (0.2, 0.2, 0.002), cons.HONEYCOMB_BOARD), {})
  with pytest.raises(ValueError, match="cannot be built"):
    mp.geom_properties(_geom("cylinder", (0.1, 0.1), cons.STEEL_SHEET), {})
  part = bp.Part("p", np.zeros(3), geoms=[bp.Geom("box", (0.1, 0.1, 0.1))])
  with pytest.raises(ValueError, match="no mass"):
    mp.part_properties(part, {})


@pytest.mark.parametrize("name", ["table_four_leg_lack", "shelving_posts_steel_wide",
                                  "desk_side_unit_w160_dark", "chair_frame_back_oak"])
def test_plain_mujoco_and_the_environment_use_the_files_inertial(name):
  spec = catalog.spec(name)
  model = mujoco.MjModel.from_xml_path(spec.path)
  env = ikea_suite.load(name, "cursor", seed=0)
  ids = env.task.furniture.body_ids
  for k, part in enumerate(spec.parts):
    written = float(part.element.find("inertial").get("mass"))
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, part.name)
    assert model.body_mass[body] == pytest.approx(written)
    assert env.physics.model.body_mass[ids[k]] == pytest.approx(written)
    assert np.allclose(env.physics.model.body_inertia[ids[k]], model.body_inertia[body])
    assert np.allclose(env.physics.model.body_ipos[ids[k]], model.body_ipos[body])


def test_catalog_entries_carry_the_mass():
  entry = catalog.entries()["table_four_leg_lack"]
  assert entry.mass == pytest.approx(model_format.load_spec(entry.path).mass)


def test_mass_table_reports_the_largest_welded_ratio():
  table = mass_report.rows()
  assert [r["name"] for r in table] == list(catalog.entries())
  top = mass_report.largest_ratio(table)
  spec = catalog.spec(top["name"])
  heavy, light = (spec.parts[spec.part_index(name)] for name in top["pair"].split(" / "))
  assert top["ratio"] == pytest.approx(heavy.mass / light.mass) and top["ratio"] > 1.0
  print(f"largest welded-neighbour mass ratio: {top['ratio']:.1f}:1 in {top['name']} "
        f"({top['pair']})")
  # docs/catalog.md holds this table; tests/test_docs.py checks that it is current.


def test_docs_category_table_gives_each_categorys_mass_span():
  page = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "models.md").read_text()
  for category, members in mass_report.by_category(mass_report.rows()).items():
    masses = [r["mass"] for r in members]
    row = next(line for line in page.splitlines()
               if line.startswith(f"| {category} | {len(members)} |"))
    assert f"| {min(masses):.1f}–{max(masses):.1f} |" in row, (category, row)


def test_cli_lists_the_catalog_with_masses(capsys):
  assert cli.main(["--list"]) == 0
  out = capsys.readouterr().out
  assert len(out.splitlines()) == len(catalog.entries()) + 1
  assert "table_four_leg_lack" in out and "3.6" in out
