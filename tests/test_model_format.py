"""Validation of furniture model files: each fault gets a ModelFormatError naming file and element."""


import numpy as np
import pytest

import ikea_suite
from ikea_suite.props import model_format
from ikea_suite.props import paths

VALID = """<mujoco model="two_boards">
  <custom>
    <text name="furniture" data="category=test; family=boards; variant=a"/>
    <text name="connector:a_end" data="type=a_end; mates=b_end; twists=0 180"/>
    <text name="connector:b_end" data="type=b_end; mates=a_end; twists=0 180"/>
  </custom>
  <worldbody>
    <body name="a" pos="0 0 0.1">
      <freejoint/>
      <geom name="a_board" type="box" size="0.1 0.05 0.01"/>
      <site name="a_end" pos="0.1 0 0" quat="0.7071068 0 0.7071068 0"/>
    </body>
    <body name="b" pos="0.2 0 0.1">
      <freejoint/>
      <geom name="b_board" type="box" size="0.1 0.05 0.01"/>
      <site name="b_end" pos="-0.1 0 0" quat="0.7071068 0 0.7071068 0"/>
    </body>
  </worldbody>
</mujoco>
"""


def write(tmp_path, text, name="model.xml"):
  path = tmp_path / name
  path.write_text(text)
  return str(path)


def load(tmp_path, text):
  return model_format.load_spec(write(tmp_path, text))


def test_valid_file_loads(tmp_path):
  spec = load(tmp_path, VALID)
  assert [p.name for p in spec.parts] == ["a", "b"]
  assert {c.name: c.mates for c in spec.connectors} == {"a_end": "b_end", "b_end": "a_end"}
  assert spec.metadata["category"] == "test"
  assert np.allclose(spec.connectors[0].twists, [0, np.pi])
  assert spec.mating_part_pairs() == [(0, 1)]


@pytest.mark.parametrize("edit, element, message", [
    (lambda t: t.replace('mates=b_end; twists', 'twists'), "connector:a_end", "missing 'mates='"),
    (lambda t: t.replace("mates=b_end", "mates=c_end"), "connector 'a_end'", "no connector has that type"),
    (lambda t: t.replace('name="b_board"', 'name="a_board"'), "<geom name='a_board'>", "duplicate name"),
    (lambda t: t.replace('size="0.1 0.05 0.01"/>\n      <site name="b_end"',
                         'size="0.1 0.05 0.01" contype="0" conaffinity="0"/>\n      <site name="b_end"'),
     "<body name='b'>", "no collision geometry"),
    (lambda t: t.replace('pos="0.1 0 0" quat="0.7071068 0 0.7071068 0"', 'pos="0.1 0 0" quat="1 0 1 0"'),
     "<site name='a_end'>", "not normalised"),
    (lambda t: t.replace('pos="-0.1 0 0"', 'pos="-0.05 0 0"'), "connector", "coincides"),
    (lambda t: t.replace("twists=0 180\"/>\n    <text name=\"connector:b_end\"",
                         "twists=0\"/>\n    <text name=\"connector:b_end\""), "connector 'a_end'", "twists differ"),
    (lambda t: t.replace("type=a_end; mates", "type=a_end; colour=red; mates"), "connector:a_end", "unknown fields"),
    (lambda t: t.replace("connector:b_end", "connector:b_missing"), "connector:b_missing", "not a site on any part"),
    (lambda t: t.replace("<mujoco", "<mujocoo").replace("</mujoco>", "</mujocoo>"), "<mujocoo>", "root element"),
    (lambda t: t.replace("</worldbody>", ""), "<file>", "not well-formed"),
    (lambda t: t.replace('quat="0.7071068 0 0.7071068 0"/>\n    </body>\n    <body name="b"',
                         'zaxis="1 0 0"/>\n    </body>\n    <body name="b"'), "<site name='a_end'>", "written as quat"),
    (lambda t: t.replace('<geom name="b_board"', '<body name="inner"><geom size="0.01"/></body><geom name="b_board"'),
     "<body name='b'>", "nested bodies"),
])
def test_format_faults_are_named(tmp_path, edit, element, message):
  text = edit(VALID)
  assert text != VALID, "the edit must change the model"
  with pytest.raises(ikea_suite.ModelFormatError) as info:
    load(tmp_path, text)
  error = str(info.value)
  assert "model.xml" in error and element in error and message in error, error


def test_missing_file_is_a_format_error(tmp_path):
  with pytest.raises(ikea_suite.ModelFormatError, match="no such file"):
    model_format.load_spec(str(tmp_path / "absent.xml"))


def test_mujoco_compile_errors_are_reported(tmp_path):
  with pytest.raises(ikea_suite.ModelFormatError, match="plain MuJoCo cannot load it"):
    load(tmp_path, VALID.replace('type="box" size="0.1 0.05 0.01"/>\n      <site name="b_end"',
                                 'type="box" size="0.1 0.05 0.01" material="nope"/>\n      <site name="b_end"'))


@pytest.mark.parametrize("path", sorted(paths.furniture_dir().glob("*.xml")), ids=lambda p: p.stem)
def test_every_committed_model_validates_and_loads_in_plain_mujoco(path):
  import mujoco
  spec = model_format.load_spec(str(path))
  model = mujoco.MjModel.from_xml_path(str(path))
  assert model.nbody == len(spec.parts) + 1
  assert len(spec.parts) >= 2 and spec.connectors


def test_a_document_compiles_from_memory_wherever_the_process_runs(tmp_path, monkeypatch):
  """read_document makes the file's asset folders absolute: the spec's document (which the
  sequencer and the scaled furniture compile) finds the meshes from any working folder."""
  import re
  import shutil
  source = paths.furniture_dir() / "table_four_leg_lack.xml"
  text = source.read_text()
  (tmp_path / "meshes").mkdir()
  meshes = re.findall(r'file="([^"]+)"', text)
  assert meshes
  for mesh in meshes:
    shutil.copy(paths.furniture_dir() / "meshes" / mesh, tmp_path / "meshes" / mesh)
  (tmp_path / "copy.xml").write_text(text)
  elsewhere = tmp_path / "elsewhere"
  elsewhere.mkdir()
  monkeypatch.chdir(elsewhere)
  spec = model_format.load_spec(str(tmp_path / "copy.xml"))
  assert spec.compiler["meshdir"] == str((tmp_path / "meshes").resolve())
  assert model_format.compile_model(spec).nmesh == len(set(meshes))
