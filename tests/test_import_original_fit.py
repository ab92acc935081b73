"""Importing the original's models: fitting the parts together (trimmed collision data),
the assembly sequence of what comes out and the Cursor oracle building it, on models the
project writes."""

import mujoco
import numpy as np
import pytest

import ikea_suite
from ikea_suite import cli as rollout
from ikea_suite.assembly import sequence
from ikea_suite.design import decompose
from ikea_suite.design import validate
from ikea_suite.design.original import cli
from ikea_suite.design.original import convert
from ikea_suite.experts import cursor_oracle
from ikea_suite.props import model_format
from ikea_suite.tasks import planner
from tests import original_models


@pytest.fixture(autouse=True)
def coacd_cache(tmp_path, monkeypatch):
  monkeypatch.setenv(decompose.CACHE_ENV, str(tmp_path / "coacd"))


def _masses(path):
  model = mujoco.MjModel.from_xml_path(str(path))
  return {model.body(i).name: model.body_mass[i] for i in range(1, model.nbody)}


def test_a_slide_that_would_push_into_a_third_part_is_not_made(tmp_path):
  result = convert.convert(original_models.post_over_shim(tmp_path), tmp_path / "out")
  assert not [n for n in result.notes if " slid " in n]
  poses = {p.name: p.pos for p in model_format.load_spec(str(result.path)).parts}
  gap = (poses["post"][2] - 0.1) - (poses["shim"][2] + 0.001)
  np.testing.assert_allclose(gap, 0.001, atol=1e-6)   # still 1 mm over the shim


def test_collision_boxes_that_overlap_in_the_files_own_data_are_trimmed_keeping_the_mass(tmp_path):
  result = convert.convert(original_models.box_with_wide_front(tmp_path, 0.005), tmp_path / "out")
  trims = [n for n in result.notes if "trimmed" in n]
  assert trims == [f"collision box 'front_geom0' of part 'front' trimmed 6.5 mm where the file's "
                   f"own collision shapes overlap part '{wall}' by 5.0 mm in the assembled pose "
                   "(1.5 mm of air left); the part keeps its mass" for wall in ("wall0", "wall1")]
  model = mujoco.MjModel.from_xml_path(str(result.path))
  np.testing.assert_allclose(model.geom("front_geom0").size, [0.1985, 0.01, 0.05], atol=1e-9)
  np.testing.assert_allclose(model.geom("front_geom0").pos, 0.0, atol=1e-9)   # both ends alike
  assert _masses(result.path)["front"] == pytest.approx(0.41 * 0.02 * 0.1 * 500)   # as written
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_an_overlap_deeper_than_a_trim_may_take_is_left_with_the_reason(tmp_path):
  result = convert.convert(original_models.box_with_wide_front(tmp_path, 0.02), tmp_path / "out")
  assert not [n for n in result.notes if " trimmed " in n]
  assert ("parts 'wall0' and 'front' overlap by 20.0 mm in the assembled pose ('wall0_geom0', "
          "'front_geom0'); not trimmed: deeper than the 15 mm a trim may take") in result.notes
  assert _masses(result.path)["front"] == pytest.approx(0.44 * 0.02 * 0.1 * 500)
  report = validate.check(result.path)
  assert any(p.startswith("overlap: wall") for p in report.problems), report.problems


def test_parts_in_a_corner_leave_it_along_the_diagonal_between_its_walls(tmp_path):
  # Each board touches the side and the back; along any axis it would slide on one of
  # them, so only the diagonal between the two walls is a free path.
  result = convert.convert(original_models.corner_shelf(tmp_path), tmp_path / "out")
  report = validate.check(result.path)
  assert report.ok, report.problems
  spec = model_format.load_spec(str(result.path))
  root = planner.root_part(spec)
  assert spec.parts[root].name == "side"
  steps = sequence.plan(spec, root, sequence.HOLD_LIFT)
  names = [spec.parts[s.part].name for s in steps]
  assert sorted(names) == ["back", "shelf0", "shelf1"] and names[-1] == "back"
  entry = np.asarray(steps[-1].waypoints[0])   # the back goes in last, along +x+y
  assert entry[0] > 0.05 and entry[2] == 0.0
  np.testing.assert_allclose(entry[0], entry[1], atol=1e-9)


def _board_and_plug(directory, site_y):
  """A board with a tab on its +x side, and a plug standing against that side clear of
  the tab; the plug's site sits `site_y` along it, where the board's site is not."""
  board = """
    <body name="board" pos="0 0 0.01">
      <geom name="noviz_collision_board_0" type="box" size="0.1 0.1 0.01" density="500"/>
      <geom name="noviz_collision_board_1" type="box" pos="0.115 0.09 0" size="0.015 0.01 0.01" density="500"/>
      <site name="board-plug,0,conn_site1" pos="0.1 -0.03 0" quat="0.7071068 0 0.7071068 0" size="0.01"/>
    </body>"""
  plug = original_models._box_body("plug", "0.11 -0.03 0.05", "0.01 0.07 0.05", [
      ("plug-board,0,conn_site1", f"-0.01 {site_y} -0.04", "0.7071068 0 0.7071068 0")])
  return original_models._write(directory, "board_plug", [board, plug])


def test_an_overlap_made_by_pairing_connectors_against_the_files_geometry_is_not_trimmed(tmp_path):
  # Where the file has it the plug touches the board; its site sits 48 mm along it from
  # the board's, so mated by name it slides 48 mm into the tab: a trim would hide that.
  result = convert.convert(_board_and_plug(tmp_path, -0.048), tmp_path / "out")
  assert not [n for n in result.notes if " trimmed " in n]
  assert ("parts 'board' and 'plug' overlap by 8.0 mm in the assembled pose ('board_geom1', "
          "'plug_geom0'); not trimmed: in the file's own poses they fit together 0.0 mm apart, "
          "48 mm and 0 deg from where their connectors put them, so a connector pairs them in a "
          "way the file's geometry does not support (sites named for the wrong end?)") \
      in result.notes
  report = validate.check(result.path)
  assert any(p.startswith("overlap: ") for p in report.problems), report.problems


def _plan(path):
  spec = model_format.load_spec(str(path))
  steps = sequence.plan(spec, planner.root_part(spec), sequence.HOLD_LIFT)
  return spec, {spec.parts[s.part].name: np.asarray(s.waypoints) for s in steps}


def test_a_part_that_fits_with_no_air_leaves_by_sliding_along_the_faces_it_touches(tmp_path):
  # The post touches all four walls of its socket: no path keeps air round it.
  result = convert.convert(original_models.post_in_socket(tmp_path), tmp_path / "out")
  assert validate.check(result.path).ok
  _, paths = _plan(result.path)
  entry = paths["post"][0]
  assert entry[2] > 0.05 and np.allclose(entry[:2], 0.0)   # straight up out of the socket
  assert cli.oracle_result(result.path, seed=0).startswith("ok, ")


def test_splayed_legs_leave_their_sleeves_along_their_own_tilted_axes(tmp_path):
  result = convert.convert(original_models.stool_with_sleeves(tmp_path), tmp_path / "out")
  report = validate.check(result.path)
  assert report.ok, report.problems
  spec, paths = _plan(result.path)
  assert sorted(paths) == ["leg0", "leg1", "leg2", "leg3"]
  for name, waypoints in paths.items():
    part = spec.parts[spec.part_index(name)]
    axis = part.rot[:, 2]   # the leg's long axis, 20 degrees off vertical
    assert np.degrees(np.arccos(abs(axis[2]))) == pytest.approx(20.0, abs=0.1)
    assert len(waypoints) == 2   # one straight leg, along the leg, out and down
    direction = waypoints[0] / np.linalg.norm(waypoints[0])
    np.testing.assert_allclose(direction, -axis, atol=1e-6)
  assert cli.oracle_result(result.path, seed=0).startswith("ok, ")


def test_convex_collision_meshes_that_overlap_are_cut_keeping_the_mass_and_the_look(tmp_path):
  result = convert.convert(original_models.box_with_wide_mesh_front(tmp_path, 0.003),
                           tmp_path / "out")
  cuts = [n for n in result.notes if " cut " in n]
  assert cuts == [f"collision convex mesh 'front_geom{i}' of part 'front' cut 4.5 mm across "
                  f"the overlap{kept} where the file's own collision shapes overlap part "
                  f"'{wall}' by 3.0 mm in the assembled pose (1.5 mm of air left); the part "
                  "keeps its mass" for i, kept, wall in ((0, " (its visible mesh unchanged)", "wall0"),
                                                         (1, "", "wall1"))]
  model = mujoco.MjModel.from_xml_path(str(result.path))
  seen, colliding = model.geom("front_geom0"), model.geom("front_geom1")
  assert not seen.contype and not seen.conaffinity and seen.group != colliding.group == 3
  width = lambda g: 2 * model.geom_aabb[g.id, 3:].max()
  assert width(seen) == pytest.approx(0.406, abs=1e-6)
  assert width(colliding) == pytest.approx(0.406 - 2 * 0.0045, abs=1e-6)   # cut at both ends
  assert _masses(result.path)["front"] == pytest.approx(0.406 * 0.02 * 0.1 * 500)
  report = validate.check(result.path)
  assert report.ok, report.problems


def test_an_assembly_hanging_from_a_light_bracket_is_held_by_its_heaviest_part(tmp_path):
  # Held by the few-gram bracket the assembly is built onto, the 2 kg board turns it out
  # of place for good; the oracle's base cursor moves its grip to the board.
  result = convert.convert(original_models.bracket_with_boards(tmp_path), tmp_path / "out")
  report = validate.check(result.path)
  assert report.ok, report.problems
  env = ikea_suite.load(str(result.path), "cursor", seed=0)
  oracle = cursor_oracle.CursorOracle(env)
  summary = rollout.run_episode(env, oracle)
  spec = env.task.furniture.spec
  assert spec.parts[env.task.root_part].name == "bracket"
  assert summary["success"], summary
  assert spec.parts[oracle._holding_part()].name == "board_long"
