"""The converter from the original IKEA environment's format, on models the tests write themselves."""

import re

import mujoco
import numpy as np
import pytest
import trimesh

import ikea_suite
from ikea_suite import errors
from ikea_suite.design import decompose
from ikea_suite.design import validate
from ikea_suite.design.original import assemble
from ikea_suite.design.original import cli
from ikea_suite.design.original import convert
from ikea_suite.design.original import names
from ikea_suite.design.original import reader
from ikea_suite.props import layout
from ikea_suite.props import model_format
from tests import original_models


@pytest.fixture(autouse=True)
def coacd_cache(tmp_path, monkeypatch):
  monkeypatch.setenv(decompose.CACHE_ENV, str(tmp_path / "coacd"))


def test_site_names_give_groups_twists_and_tag():
  parsed = names.parse("leg-table,0,90,180,270,conn_site1", "f.xml")
  assert (parsed.type, parsed.mate_type, parsed.tag) == ("leg-table", "table-leg", "1")
  assert parsed.twists_deg == (0.0, 90.0, 180.0, 270.0)
  assert names.parse("0-1,conn_site", "f.xml").twists_deg == ()   # any twist
  assert names.parse("leg-top,,conn_site0", "f.xml").twists_deg == ()   # empty field skipped
  assert names.parse("a-b,,90,,conn_site3", "f.xml").twists_deg == (90.0,)
  assert names.parse("a-b,-90,450,conn_site2", "f.xml").twists_deg == (90.0, 270.0)
  assert names.is_connector("a-b,conn_site2") and not names.is_connector("top_bottom_site")


@pytest.mark.parametrize("bad, why", [
    ("legtable,0,conn_site1", "two connector groups"),
    ("leg-table-x,conn_site1", "two connector groups"),
    ("leg-table,ninety,conn_site1", "'ninety' is not an angle"),
    ("conn_site1", "last comma-separated field"),
])
def test_malformed_site_names_are_named_in_the_error(bad, why):
  with pytest.raises(errors.ConversionError, match=why) as info:
    names.parse(bad, "f.xml")
  assert bad in str(info.value)


def test_the_originals_forward_y_becomes_our_forward_x(tmp_path):
  model = reader.read(original_models.table(tmp_path))
  solved = assemble.solve(model)
  top = next(b for b in model.bodies if b.name == "top")
  site = next(s for s in top.sites if s.name.endswith("conn_site1"))
  ours = next(c for c in solved.connectors if c.site == site.name)
  np.testing.assert_allclose(ours.rot[:, 0], site.rot[:, 1], atol=1e-12)   # forward
  np.testing.assert_allclose(ours.rot[:, 2], site.rot[:, 2], atol=1e-12)   # up
  np.testing.assert_allclose(ours.rot[:, 0], [0, -1, 0], atol=1e-12)


def _poses(path):
  spec = model_format.load_spec(str(path))
  return {p.name: (p.pos, p.rot) for p in spec.parts}


def test_a_file_whose_poses_are_not_assembled_is_solved_from_its_connectors(tmp_path):
  assembled = convert.convert(original_models.table(tmp_path / "a"), tmp_path / "out_a")
  moved = convert.convert(original_models.table(tmp_path / "b", assembled=False), tmp_path / "out_b")
  reference, solved = _poses(assembled.path), _poses(moved.path)
  np.testing.assert_allclose(reference["top"][0], [0, 0, original_models.TOP_Z], atol=1e-6)
  corners = sorted(tuple(np.round(solved[f"leg{i}"][0], 6)) for i in range(4))
  expected = sorted((x, y, original_models.LEG_HALF) for x, y in original_models.CORNERS)
  np.testing.assert_allclose(corners, expected, atol=1e-6)
  for name, (pos, rot) in solved.items():   # upright, turned a whole number of quarter turns
    np.testing.assert_allclose(rot[:, 2], [0, 0, 1], atol=1e-6, err_msg=name)
    yaw = np.degrees(np.arctan2(rot[1, 0], rot[0, 0]))
    assert abs(yaw / 90 - round(yaw / 90)) < 1e-6, (name, yaw)
  for i in (0, 1, 3):   # turned 10 degrees in the file: back to the nearest allowed twist
    np.testing.assert_allclose(solved[f"leg{i}"][1], np.eye(3), atol=1e-6)
  assert len(moved.pairs) == 4 and moved.num_connectors == 8


def test_quirks_are_repaired_and_reported(tmp_path):
  result = convert.convert(original_models.table(tmp_path, quirks=True, assembled=False),
                           tmp_path / "out")
  notes = "\n".join(result.notes)
  assert "<body name='top'>: normalised quat (its length was 2)" in notes
  assert "normalised quat" in notes and "conn_site0'>" in notes
  assert "rgba='0.9,0.9,0.9,1' written with commas" in notes
  assert "dropped duplicate weld between 'top' and 'leg0'" in notes
  assert "dropped dead weld between 'leg0' and 'leg1'" in notes
  assert "site 'leg-shelf,conn_site9' on part 'leg3' has no partner" in notes
  assert result.num_parts == 5 and len(result.pairs) == 4
  spec = model_format.load_spec(str(result.path))   # a valid model in our format
  assert len(spec.parts) == 5 and len(spec.assembled_connector_pairs()) == 4


def test_a_disconnected_graph_is_rejected_naming_the_parts_and_the_site(tmp_path):
  with pytest.raises(errors.ConversionError,
                     match=r"parts \['c'\] cannot be reached from root part 'a'.*"
                           r"'c-d,0,180,conn_site1' on part 'c' has no partner: "
                           r"no site of type 'd-c'"):
    convert.convert(original_models.disconnected(tmp_path), tmp_path / "out")
  assert not (tmp_path / "out" / "shelf_broken.xml").exists()


def _masses(path):
  model = mujoco.MjModel.from_xml_path(str(path))
  return {model.body(i).name: model.body_mass[i] for i in range(1, model.nbody)}


def test_masses_come_from_the_original_or_from_our_material_table(tmp_path):
  source = original_models.table(tmp_path)
  kept = _masses(convert.convert(source, tmp_path / "kept").path)
  assert kept["top"] == pytest.approx(0.6 * 0.6 * 0.04 * 100)       # density 100 in the file
  assert kept["leg0"] == pytest.approx(0.04 * 0.04 * 0.4 * 500)
  birch = _masses(convert.convert(source, tmp_path / "birch", material="solid birch").path)
  density = convert.material_density("solid birch")
  assert birch["top"] == pytest.approx(0.6 * 0.6 * 0.04 * density)
  with pytest.raises(errors.OptionValueError, match="'oak'"):
    convert.convert(source, tmp_path / "x", material="oak")


def test_placeholder_masses_are_replaced_by_particleboard_and_reported(tmp_path):
  source = original_models.table(tmp_path, leg_density=5)   # a 40 cm leg of 3.2 g
  result = convert.convert(source, tmp_path / "repaired")
  masses = _masses(result.path)
  density = convert.material_density("particleboard")
  assert masses["leg0"] == pytest.approx(0.04 * 0.04 * 0.4 * density)
  assert masses["top"] == pytest.approx(0.6 * 0.6 * 0.04 * density)   # every part alike
  repair, = [n for n in result.notes if n.startswith("masses repaired")]
  assert "4 of 5 parts" in repair and "'leg0' weighs 3.2 g" in repair
  chosen = convert.convert(source, tmp_path / "birch", material="solid birch")
  assert not any(n.startswith("masses repaired") for n in chosen.notes)
  assert _masses(chosen.path)["leg0"] == pytest.approx(
      0.04 * 0.04 * 0.4 * convert.material_density("solid birch"))


def test_mesh_collision_parts_collide_through_their_mesh_or_coacd_pieces(tmp_path):
  result = convert.convert(original_models.stool_with_mesh_collision(tmp_path), tmp_path / "out")
  model = mujoco.MjModel.from_xml_path(str(result.path))
  colliding = {}
  for g in range(model.ngeom):
    if model.geom_bodyid[g] and model.geom_contype[g]:
      colliding.setdefault(model.body(model.geom_bodyid[g]).name, []).append(model.geom_type[g])
  assert colliding["seat"] == [mujoco.mjtGeom.mjGEOM_MESH]           # convex: itself
  assert len(colliding["leg0"]) >= 2                                 # concave: coacd pieces
  assert any("decomposed into" in n for n in result.notes)
  masses = _masses(result.path)
  assert masses["seat"] == pytest.approx(0.4 * 0.3 * 0.03 * 500, rel=1e-3)
  assert masses["leg0"] == pytest.approx(600 * 0.04 * (0.3 * 0.04 + 0.04 * 0.36), rel=1e-3)


def test_the_initial_layout_is_kept_and_can_be_applied(tmp_path):
  result = convert.convert(original_models.table(tmp_path, quirks=True), tmp_path / "out")
  spec = model_format.load_spec(str(result.path))
  kept = layout.initial_layout(spec)
  assert sorted(kept) == ["leg0", "top"]
  np.testing.assert_allclose(kept["leg0"][1], np.array([1, 1, 0, 0]) / np.sqrt(2), atol=1e-5)
  env = ikea_suite.load(result.path, "cursor", seed=0)
  env.reset()
  with env.physics.reset_context():
    assert layout.apply_initial_layout(env.physics, env.task.furniture) == ["top", "leg0"]
  top = env.task.furniture.body_ids[spec.part_index("top")]
  np.testing.assert_allclose(env.physics.data.xpos[top], [0.6, 0.3, 0.02], atol=1e-9)


def test_the_command_converts_validates_assembles_and_tabulates(tmp_path, capsys):
  src = tmp_path / "src"
  original_models.table(src, name="table_side")
  original_models.table(src, name="table_moved", assembled=False, quirks=True)
  original_models.stool_with_mesh_collision(src)
  original_models.bookcase(src, assembled=False)
  original_models.disconnected(src)
  out = tmp_path / "converted"
  assert cli.main([str(src), "--out", str(out)]) == 1   # one model cannot be converted
  text = capsys.readouterr().out
  rows = {line.split("|")[0].strip(): [c.strip() for c in line.split("|")[1:]]
          for line in text.splitlines() if "|" in line}
  assert rows["model"] == ["parts", "connectors", "mated pairs", "validation", "oracle"]
  for name, parts, connectors, pairs in (("table_side", 5, 8, 4), ("table_moved", 5, 8, 4),
                                         ("stool_mesh", 3, 4, 2), ("bookcase_loops", 5, 12, 6)):
    assert rows[name][:4] == [str(parts), str(connectors), str(pairs), "ok"], rows[name]
    assert rows[name][4].startswith("ok, "), rows[name]
  assert rows["shelf_broken"][3] == "not converted"
  assert "shelf_broken: NOT CONVERTED" in text and "parts ['c'] cannot be reached" in text
  assert "table_moved: 6 repairs and notes" in text and "dropped duplicate weld" in text
  assert "4/5 models converted, validated and assembled" in text
  try:
    assert ikea_suite.register_models(out) == [
        "bookcase_loops", "stool_mesh", "table_moved", "table_side"]
    assert "table_moved" in ikea_suite.furniture_names()
    assert ikea_suite.load("stool_mesh", "cursor", seed=0).task.furniture.name == "stool_mesh"
  finally:
    ikea_suite.unregister_models(out)


def test_the_command_rejects_a_missing_source(tmp_path, capsys):
  assert cli.main([str(tmp_path / "nowhere.xml"), "--out", str(tmp_path / "out")]) == 2
  assert "nowhere.xml: <file>: no such file or folder" in capsys.readouterr().err


def _upper_yaw(path):
  solved = assemble.solve(reader.read(path))
  rot = solved.poses["upper"][1]
  return np.degrees(np.arctan2(rot[1, 0], rot[0, 0])) % 360, solved


@pytest.mark.parametrize("twists, yaw_in_file, expected", [
    (",0,90,180,270", 80.0, 90.0),     # the allowed twist nearest the file's orientation
    (",0,180", 80.0, 0.0),
    ("", 37.0, 37.0),                  # any twist: the file's own
])
def test_the_twist_nearest_the_files_orientation_is_chosen(tmp_path, twists, yaw_in_file, expected):
  yaw, solved = _upper_yaw(original_models.two_boards(tmp_path, twists, twists, yaw_in_file))
  assert yaw == pytest.approx(expected, abs=1e-6)
  np.testing.assert_allclose(solved.poses["upper"][0], [0, 0, 0.07], atol=1e-9)


def test_twists_of_mates_are_unified_and_made_symmetric(tmp_path):
  yaw, solved = _upper_yaw(original_models.two_boards(tmp_path, ",90", ",0,90", yaw_b=265.0))
  assert {c.twists_deg for c in solved.connectors} == {(0.0, 90.0, 270.0)}
  assert any("unified to [0.0, 90.0, 270.0]" in n for n in solved.notes)
  assert yaw == pytest.approx(270.0)


_PART = '<body name="{name}" pos="0 0 0.02">{body}</body>'
_BOX = '<geom name="noviz_collision_{name}_0" type="box" size="0.1 0.1 0.02"/>'
_SITE = '<site name="{site}" pos="0 0 0.02"/>'


@pytest.mark.parametrize("a_body, asset, why", [
    (_BOX.format(name="a") + '<body name="x"/>', "", "<body name='a'>: nested bodies"),
    ('<geom type="mesh" mesh="m"/>', '<mesh name="m" file="gone.stl"/>',
     "gone.stl' (an incomplete file)"),
    ('<geom type="box" size="0.1 0.1 0.02" contype="0" conaffinity="0"/>', "",
     "<body name='a'>: part has no collision geometry (no colliding primitive or mesh; "
     "an incomplete file)"),
    (_BOX.format(name="a") + '<geom type="plane" size="1 1 1"/>', "", "type 'plane' is not supported"),
    ('<geom type="box" size="0.1 0.1 0.02" xyaxes="1 0 0 0 1 0"/>', "", "written as xyaxes"),
    (_BOX.format(name="a") + '<geom type="box" size="0.1 0.1 0.02" quat="0 0 0 0"/>', "",
     "has zero length"),
])
def test_unconvertible_parts_are_named_with_the_reason(tmp_path, a_body, asset, why):
  a = _PART.format(name="a", body=a_body + _SITE.format(site="a-b,conn_site1"))
  b = _PART.format(name="b", body=_BOX.format(name="b") + _SITE.format(site="b-a,conn_site1"))
  path = tmp_path / "bad.xml"
  path.write_text(f"<mujoco><asset>{asset}</asset><worldbody>{a}{b}</worldbody></mujoco>")
  with pytest.raises(errors.ConversionError, match=re.escape(why)):
    convert.convert(path, tmp_path / "out")


@pytest.mark.parametrize("entry, why", [
    ("initpos.nobody=0 0 0 1 0 0 0", "names part 'nobody'"),
    ("initpos.top=0 0 0 1", "must be 7 numbers"),
    ("initpos.top=0 0 0 2 0 0 0", "is not unit length"),
])
def test_a_bad_initial_layout_entry_is_a_format_error(tmp_path, entry, why):
  result = convert.convert(original_models.table(tmp_path), tmp_path / "out")
  text = result.path.read_text().replace("; source=", f"; {entry}; source=")
  result.path.write_text(text)
  spec = model_format.load_spec(str(result.path))
  with pytest.raises(errors.ModelFormatError, match=why):
    layout.initial_layout(spec)


def test_without_the_oracle_a_valid_model_passes(tmp_path, capsys):
  original_models.table(tmp_path / "src")
  assert cli.main([str(tmp_path / "src"), "--out", str(tmp_path / "out"), "--no-oracle",
                   "--material", "particleboard"]) == 0
  row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("table_test"))
  assert [c.strip() for c in row.split("|")][1:] == ["5", "8", "4", "ok", "skipped"]


def _board_with_visual_mesh(tmp_path, mesh):
  mesh.export(tmp_path / "visual.stl")
  a = _PART.format(name="a", body=_BOX.format(name="a") + _SITE.format(site="a-b,conn_site1")
                   + '<geom type="mesh" mesh="v" contype="0" conaffinity="0" density="0"/>')
  b = _PART.format(name="b", body=_BOX.format(name="b") + _SITE.format(site="b-a,conn_site1"))
  path = tmp_path / "boards.xml"
  path.write_text(f'<mujoco><asset><mesh name="v" file="visual.stl"/></asset>'
                  f"<worldbody>{a}{b}</worldbody></mujoco>")
  return path


def test_a_mesh_enclosing_no_volume_is_replaced_by_its_hull_so_mujoco_loads_it(tmp_path):
  box = trimesh.creation.box(extents=(0.2, 0.2, 0.04))
  double_sided = trimesh.Trimesh(box.vertices, np.concatenate([box.faces, box.faces[:, ::-1]]),
                                 process=False)   # every face twice, facing both ways
  result = convert.convert(_board_with_visual_mesh(tmp_path, double_sided), tmp_path / "out")
  assert any("mesh 'v' encloses no volume" in n and "convex hull" in n for n in result.notes)
  mujoco.MjModel.from_xml_path(str(result.path))


def test_a_flat_mesh_is_named_as_enclosing_no_volume(tmp_path):
  flat = trimesh.Trimesh([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0.1, 0.1, 0]], [[0, 1, 2], [1, 3, 2]])
  with pytest.raises(errors.ConversionError, match="<mesh name='v'>: encloses no volume \\(a flat"):
    convert.convert(_board_with_visual_mesh(tmp_path, flat), tmp_path / "out")


def test_mates_that_close_loops_are_kept_and_one_that_cannot_is_dropped(tmp_path):
  solved = assemble.solve(reader.read(original_models.bookcase(tmp_path, assembled=False)))
  assert len(solved.pairs) == 6 and not solved.notes
  np.testing.assert_allclose(solved.poses["side1"][0] - solved.poses["side0"][0], [0.8, 0, 0],
                             atol=1e-9)
  bad = assemble.solve(reader.read(original_models.bookcase(tmp_path, "bad", bad_loop=0.03)))
  assert len(bad.pairs) == 5
  assert [n for n in bad.notes if "do not meet" in n] == [
      "sites '1-2,0,180,conn_site2' and '2-1,0,180,conn_site5' do not meet when the parts are "
      "assembled through their other connectors (30.0 mm apart); dropped"]


def test_a_loop_mate_that_misses_by_a_tolerance_has_its_site_moved_onto_its_partner(tmp_path):
  path = original_models.bookcase(tmp_path, "near", bad_loop=0.01)
  solved = assemble.solve(reader.read(path))
  assert len(solved.pairs) == 6
  assert [n for n in solved.notes if "moved" in n] == [
      "site '2-1,0,180,conn_site5' moved 10.0 mm to meet '1-2,0,180,conn_site2': the file's "
      "sites miss each other by that much once the parts are assembled through their other "
      "connectors"]
  result = convert.convert(path, tmp_path / "out")
  assert len(result.pairs) == 6
  report = validate.check(result.path)
  assert report.ok, report.problems


@pytest.mark.parametrize("compiler", ["", '\n  <compiler angle="degree"/>'])
def test_eulers_are_radians_as_in_the_originals_base_unless_the_file_says_degree(tmp_path, compiler):
  path = original_models.bench_with_euler_rail(tmp_path, compiler=compiler)
  seat = next(b for b in reader.read(path).bodies if b.name == "seat")
  np.testing.assert_allclose(seat.geoms[0].rot[:, 2], [0, -1, 0], atol=1e-6)   # the bar lies along y
  result = convert.convert(path, tmp_path / "out")
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_parts_whose_sites_leave_a_gap_or_overlap_are_slid_along_the_mate_until_they_touch(tmp_path):
  path = original_models.table(tmp_path, site_shifts={0: 0.004, 1: -0.006})
  result = convert.convert(path, tmp_path / "out")
  slid = {n.split("'")[1]: n for n in result.notes if " slid " in n}
  assert set(slid) == {"leg0", "leg1"}
  assert "to close a gap" in slid["leg0"] and "out of a 6.0 mm penetration" in slid["leg1"]
  poses = _poses(result.path)
  bottoms = [poses[f"leg{i}"][0][2] - original_models.LEG_HALF for i in range(4)]
  np.testing.assert_allclose(bottoms, 0.0, atol=2e-4)   # every leg reaches the floor again
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_parts_without_connector_sites_are_named_as_such(tmp_path):
  path = original_models.disconnected(tmp_path, bare=True)
  with pytest.raises(errors.ConversionError) as info:
    convert.convert(path, tmp_path / "out")
  # Reported alone: with a part that has no sites, the rest of the graph is not judged.
  assert str(info.value).endswith(
      "<worldbody>: parts ['c'] have no connector sites, so nothing can connect them "
      "(an incomplete file)")


def test_a_slide_that_opens_a_loop_moves_the_loop_site_to_meet_again(tmp_path):
  result = convert.convert(original_models.bookcase(tmp_path, poke=0.004), tmp_path / "out")
  assert any("shelf1" in n and "out of a 4.0 mm penetration" in n for n in result.notes)
  assert "site '2-1_0_180_conn_site3' moved 4.0 mm to meet '1-2_0_180_conn_site1' after the slides" \
      in result.notes
  assert len(result.pairs) == 6
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_sites_are_paired_so_that_one_pose_of_the_part_meets_them_all(tmp_path):
  solved = assemble.solve(reader.read(original_models.frame_facing_back(tmp_path)))
  assert sorted(solved.pairs) == [("base-frame,0,conn_site0", "frame-base,0,conn_site1"),
                                  ("base-frame,0,conn_site1", "frame-base,0,conn_site0")]
  assert not solved.notes
  pos, rot = solved.poses["frame"]
  np.testing.assert_allclose(pos, [0, 0, 0.14], atol=1e-9)   # centred on the base, not 30 cm off
  np.testing.assert_allclose(rot, np.diag([-1, -1, 1]), atol=1e-9)
  report = validate.check(convert.convert(original_models.frame_facing_back(tmp_path),
                                          tmp_path / "out").path)
  assert report.ok, report.problems


def test_a_site_written_facing_the_wrong_way_does_not_place_its_part(tmp_path):
  solved = assemble.solve(reader.read(original_models.bookcase(tmp_path, flip=2)))
  assert solved.root == "side0" and len(solved.pairs) == 5
  assert [n for n in solved.notes if "do not meet" in n] == [
      "sites '0-2,0,180,conn_site2' and '2-0,0,180,conn_site4' do not meet when the parts are "
      "assembled through their other connectors (their up axes or allowed twists disagree); "
      "dropped"]
  for name, (pos, rot) in solved.poses.items():   # every part where the file has it
    np.testing.assert_allclose(rot, np.eye(3), atol=1e-9, err_msg=name)
  np.testing.assert_allclose(solved.poses["shelf2"][0], [0, 0, 0.7], atol=1e-9)


def test_a_slide_leaves_behind_parts_also_mated_to_parts_that_stay(tmp_path):
  # The back overlaps both sides; the right side hangs beyond it in the solved tree
  # but is held by the shelves too, so it stays while the back slides out.
  path = original_models.cabinet_with_back(tmp_path)
  solved = assemble.solve(reader.read(path))
  assert ("back", "side1") in [(a.body, b.body) for a, b in solved.tree]
  result = convert.convert(path, tmp_path / "out")
  slid = [n for n in result.notes if " slid " in n]
  assert len(slid) == 1 and slid[0].startswith("part 'back' slid 13.0 mm")
  assert slid[0].endswith("['side1'] stayed, as they are mated to parts that do not move")
  assert "site '1-3_0_180_conn_site1' moved 13.0 mm to meet '3-1_0_180_conn_site1' after the " \
      "slides" in result.notes
  poses = _poses(result.path)
  np.testing.assert_allclose(poses["side1"][0] - poses["side0"][0], [0.8, 0, 0], atol=1e-9)
  np.testing.assert_allclose(poses["back"][0][1] - poses["side0"][0][1], 0.153, atol=1e-5)
  assert len(result.pairs) == 6
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_an_assembly_that_cannot_stand_upright_is_set_down_on_the_side_it_rests_on(tmp_path):
  result = convert.convert(original_models.wall_shelf(tmp_path), tmp_path / "out")
  turned = [n for n in result.notes if n.startswith("the assembly cannot stand upright")]
  assert len(turned) == 1 and "turned 90 deg" in turned[0], result.notes
  # Laid on the boxes' open fronts: the column, on the boxes' backs, ends up on top.
  poses = _poses(result.path)
  assert poses["column"][0][2] > max(poses[f"box{k}"][0][2] for k in range(3)) + 0.03
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_an_assembly_that_stands_is_not_turned(tmp_path):
  result = convert.convert(original_models.table(tmp_path), tmp_path / "out")
  assert not [n for n in result.notes if "cannot stand upright" in n]
  for name, (pos, rot) in _poses(result.path).items():
    np.testing.assert_allclose(rot, np.eye(3), atol=1e-9, err_msg=name)



def test_names_that_the_files_assembled_layout_contradicts_are_read_as_laid_out(tmp_path):
  path = original_models.misnamed_chair(tmp_path)
  model = reader.read(path)
  solved = assemble.solve(model)
  read_as = [n for n in solved.notes if " read as " in n]
  # Each rail's two sites take the other's name (the one at the back also the half turn),
  # and each of the back's sites gains the half turn it meets the rails at.
  assert len(read_as) == 6, solved.notes
  assert read_as[0].startswith("site 'back-side,0,conn_site0' on part 'back' read as "
                               "'back-side,0,180,conn_site0': the file lays it on "
                               "'side-front,0,conn_site2' of part 'rail0', turned 180 degrees")
  assert len(solved.pairs) == 4
  for body in model.bodies:   # every part where the file has it: rails not reversed
    pos, rot = solved.poses[body.name]
    np.testing.assert_allclose(pos, body.pos, atol=1e-9, err_msg=body.name)
    np.testing.assert_allclose(rot, np.eye(3), atol=1e-9, err_msg=body.name)
  report = validate.check(convert.convert(path, tmp_path / "out").path)
  assert report.ok, report.problems
  # A file whose layout agrees with its names is read as written.
  assert not [n for n in assemble.solve(reader.read(original_models.table(tmp_path / "t"))).notes
              if " read as " in n]


def test_an_assembly_a_little_off_level_is_set_down_on_all_its_feet(tmp_path):
  # The back ends 2 mm above the floor: upright the chair rests on its front panel alone,
  # its centre of mass behind it; tilted 0.3 degrees it stands on both panels.
  result = convert.convert(original_models.misnamed_chair(tmp_path, short_back=0.002),
                           tmp_path / "out")
  turned = [n for n in result.notes if n.startswith("the assembly cannot stand upright")]
  assert len(turned) == 1 and "set down on all its feet, tilted 0.3 deg" in turned[0], result.notes
  poses = _poses(result.path)
  assert poses["back"][0][2] > poses["front"][0][2] + 0.09   # still upright
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_subfolders_are_read_and_each_incomplete_file_reported_with_its_reason_alone(tmp_path, capsys):
  src = tmp_path / "src"
  original_models.table(src)
  original_models.table(src / "variants", name="table_test")   # same name, another folder
  original_models.disconnected(src / "incomplete", name="shelf_bare", bare=True)
  original_models.table(src / "incomplete", name="table_no_mesh")
  (src / "incomplete" / "table_no_mesh" / "top.stl").unlink()
  out = tmp_path / "out"
  assert cli.main([str(src), "--out", str(out), "--no-oracle"]) == 1
  text = capsys.readouterr().out
  rows = {line.split("|")[0].strip(): [c.strip() for c in line.split("|")[1:]]
          for line in text.splitlines() if "|" in line}
  assert list(rows)[1:] == ["table_test", "incomplete/shelf_bare", "incomplete/table_no_mesh",
                            "variants/table_test"]
  assert rows["table_test"][3] == rows["variants/table_test"][3] == "ok"
  assert (out / "table_test.xml").is_file() and (out / "variants" / "table_test.xml").is_file()
  reasons = {line.split(":")[0]: line.split("): ", 1)[1] for line in text.splitlines()
             if "NOT CONVERTED" in line}
  assert reasons == {
      "incomplete/shelf_bare": "<worldbody>: parts ['c'] have no connector sites, so nothing "
                               "can connect them (an incomplete file)",
      "incomplete/table_no_mesh": "<mesh name='top'>: no mesh file "
                                  f"'{src / 'incomplete' / 'table_no_mesh' / 'top.stl'}' "
                                  "(an incomplete file)"}
  assert "2/4 models converted, validated and assembled" in text


def test_without_recursion_only_the_folders_own_files_are_read(tmp_path, capsys):
  original_models.table(tmp_path / "src")
  original_models.disconnected(tmp_path / "src" / "incomplete", bare=True)
  assert cli.main([str(tmp_path / "src"), "--out", str(tmp_path / "out"), "--no-oracle",
                   "--no-recursive"]) == 0
  assert "1/1 models converted" in capsys.readouterr().out


def test_several_seeds_are_summed_up_in_one_oracle_cell(tmp_path, monkeypatch, capsys):
  outcomes = {0: "ok, 700 steps", 1: "ok, 650 steps", 2: "FAIL, 3/4 connections"}
  monkeypatch.setattr(cli, "oracle_result", lambda path, seed: outcomes[seed])
  assert cli.oracle_results(tmp_path / "m.xml", [0, 1]) == "ok, 2/2 seeds, 650-700 steps"
  assert cli.oracle_results(tmp_path / "m.xml", [0, 1, 2]) == (
      "FAIL on 1/3 seeds: seed 2 FAIL, 3/4 connections")
  assert cli.oracle_results(tmp_path / "m.xml", [2]) == "FAIL, 3/4 connections"
  original_models.table(tmp_path / "src")
  assert cli.main([str(tmp_path / "src"), "--out", str(tmp_path / "out"), "--seed", "0", "1"]) == 0
  row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("table_test"))
  assert row.split("|")[-1].strip() == "ok, 2/2 seeds, 650-700 steps"


def test_a_file_cut_short_is_named_incomplete(tmp_path):
  text = original_models.table(tmp_path).read_text()
  path = tmp_path / "table_cut.xml"
  path.write_text(text[:text.index("<body name=\"leg2\"") + 30])   # ends inside a tag
  with pytest.raises(errors.ConversionError, match=r"not well-formed XML: .*\(it ends "
                     r"mid-element: an incomplete file\)"):
    convert.convert(path, tmp_path / "out")
  path.write_text(text.replace("<worldbody>", "<worldbody><oops>", 1))   # broken, not short
  with pytest.raises(errors.ConversionError) as info:
    convert.convert(path, tmp_path / "out")
  assert "incomplete" not in str(info.value)
