"""User model directories: register_models, load() by path, and malformed files kept to themselves."""

import re
import shutil

import pytest

import ikea_suite
from ikea_suite.props import catalog
from ikea_suite.props import paths

GOOD = "table_four_leg_lack"


@pytest.fixture
def user_dir(tmp_path):
  """A directory with one good model (a renamed copy of a catalog model) and one broken file."""
  source = paths.furniture_dir() / f"{GOOD}.xml"
  text = source.read_text()
  (tmp_path / "meshes").mkdir()
  for mesh in re.findall(r'file="([^"]+)"', text):
    shutil.copy(paths.furniture_dir() / "meshes" / mesh, tmp_path / "meshes" / mesh)
  (tmp_path / "mine_good.xml").write_text(text.replace(f'model="{GOOD}"', 'model="mine_good"'))
  (tmp_path / "mine_broken.xml").write_text("<mujoco><worldbody><body name='a'></worldbody>")
  yield tmp_path
  ikea_suite.unregister_models(tmp_path)


def test_a_registered_directory_adds_its_good_models_and_lists_the_broken_one(user_dir):
  assert "mine_good" not in ikea_suite.furniture_names()
  assert ikea_suite.register_models(user_dir) == ["mine_good"]
  names = ikea_suite.furniture_names()
  assert "mine_good" in names and GOOD in names and "mine_broken" not in names
  broken = [m for m in ikea_suite.invalid_models() if m.name == "mine_broken"]
  assert len(broken) == 1
  assert broken[0].path == str(user_dir / "mine_broken.xml")
  assert "not well-formed XML" in broken[0].reason
  env = ikea_suite.load("mine_good", "cursor", seed=0)
  assert len(env.task.furniture.parts) == catalog.entries()[GOOD].num_parts


def test_loading_the_broken_model_by_name_raises_its_own_format_error(user_dir):
  ikea_suite.register_models(user_dir)
  with pytest.raises(ikea_suite.ModelFormatError, match="mine_broken.xml.*not well-formed"):
    ikea_suite.load("mine_broken", "cursor")


def test_unregistering_removes_the_models(user_dir):
  ikea_suite.register_models(user_dir)
  ikea_suite.unregister_models(user_dir)
  assert "mine_good" not in ikea_suite.furniture_names()
  assert not any(m.name == "mine_broken" for m in ikea_suite.invalid_models())
  with pytest.raises(ikea_suite.UnknownNameError):
    ikea_suite.load("mine_good", "cursor")


def test_a_name_taken_by_the_catalog_is_invalid_not_a_replacement(user_dir):
  shutil.copy(user_dir / "mine_good.xml", user_dir / f"{GOOD}.xml")
  ikea_suite.register_models(user_dir)
  assert catalog.path_of(GOOD) == str(paths.furniture_dir() / f"{GOOD}.xml")
  clash = [m for m in ikea_suite.invalid_models() if m.path == str(user_dir / f"{GOOD}.xml")]
  assert clash and "already taken" in clash[0].reason


def test_load_accepts_a_model_file_path(user_dir):
  env = ikea_suite.load(user_dir / "mine_good.xml", "cursor", seed=0)
  assert env.task.furniture.name == "mine_good"
  env = ikea_suite.load(str(user_dir / "mine_good.xml"), "cursor", seed=0)
  assert env.task.furniture.name == "mine_good"


def test_load_of_a_bad_path_names_the_file(user_dir):
  with pytest.raises(ikea_suite.ModelFormatError, match="nothing_here.xml.*no such file"):
    ikea_suite.load(str(user_dir / "nothing_here.xml"))
  with pytest.raises(ikea_suite.ModelFormatError, match="not well-formed"):
    ikea_suite.load(user_dir / "mine_broken.xml")


def test_registering_a_missing_directory_names_it(tmp_path):
  with pytest.raises(ikea_suite.ModelFormatError, match="no_dir.*no such directory"):
    ikea_suite.register_models(tmp_path / "no_dir")


def test_registering_again_rescans_the_directory(user_dir):
  ikea_suite.register_models(user_dir)
  (user_dir / "mine_broken.xml").write_text(
      (user_dir / "mine_good.xml").read_text().replace('model="mine_good"', 'model="mine_fixed"'))
  assert ikea_suite.register_models(user_dir) == ["mine_broken", "mine_good"]
  assert not any(m.name == "mine_broken" for m in ikea_suite.invalid_models())
