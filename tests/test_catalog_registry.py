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


def _good_text():
  return (paths.furniture_dir() / f"{GOOD}.xml").read_text().replace(
      f'model="{GOOD}"', 'model="mine"')


# Each file breaks in one way; the reason invalid_models() gives names the fault.
BROKEN = {
    "bogus_encoding": ('<?xml version="1.0" encoding="bogus-enc"?><mujoco/>',
                       "cannot be decoded: unknown encoding: bogus-enc"),
    "binary": (b"\x00\xff\xfe\x89PNG\x00", "not well-formed XML"),
    "empty": ("", "not well-formed XML: no element found"),
    "slash_in_body": (lambda t: t.replace('name="leg0"', 'name="le/g0"')
                      .replace('body2="leg0"', 'body2="le/g0"'),
                      "dm_control cannot build its parts: .*identifier cannot contain a '/'.*le/g0"),
    "slash_in_site": (lambda t: t.replace('"top_top_leg_slot_0"', '"top/slot0"')
                      .replace("connector:top_top_leg_slot_0", "connector:top/slot0"),
                      "dm_control cannot build its parts: .*cannot contain a '/'.*top/slot0"),
    "slash_in_model": (lambda t: t.replace('model="mine"', 'model="a/b"'),
                       "dm_control cannot build its parts: Identifier cannot contain '/': got a/b"),
    "default_class": (lambda t: t.replace(
        "<asset>", '<default><default class="thin"><geom size="0.025 0.025 0.2"/></default>'
        '</default><asset>').replace('type="box" pos="0 0 0" quat="1 0 0 0" size="0.025 0.025 0.2"',
                                     'type="box" class="thin" pos="0 0 0" quat="1 0 0 0"'),
                      "dm_control cannot build its parts: XML Error: unknown default class name 'thin'"),
    "huge_box": (lambda t: t.replace('size="0.025 0.025 0.2"', 'size="1e6 1e6 1e6"', 1),
                 r"the assembled furniture is 2e\+06 x 2e\+06 x 2e\+06 m .* at most 4 m"),
    "far_part": (lambda t: t.replace('<body name="leg0" pos="0.25 0.25 0.2"',
                                     '<body name="leg0" pos="1e5 0.25 0.2"'),
                 r"the assembled furniture is 1e\+05 x 0.55 x 0.45 m"),
    "infinite_size": (lambda t: t.replace('size="0.025 0.025 0.2"', 'size="inf 1 1"', 1),
                      "<body name='leg0'>: collision geometry is not finite"),
    "huge_mass": (lambda t: t.replace('mass="0.18856"', 'mass="1e30"', 1),
                  r"<body name='leg0'>: 1e\+30 kg in a collision box of 0.05 x 0.05 x 0.4 m"),
    "nan_twists": (lambda t: t.replace("twists=0 90 180 270", "twists=nan", 1),
                   "twists='nan' must be angles in degrees"),
    "nameless_text": (lambda t: t.replace("<custom>", '<custom><text data="x=1"/>'),
                      "plain MuJoCo cannot load it: .*required attribute missing: 'name'"),
}


@pytest.fixture
def broken_dir(user_dir):
  """user_dir plus one file for each way of breaking a model (BROKEN)."""
  for name, (content, _) in BROKEN.items():
    if callable(content):
      content = content(_good_text())
    data = content if isinstance(content, bytes) else content.encode()
    (user_dir / f"{name}.xml").write_bytes(data)
  (user_dir / "a_folder.xml").mkdir()
  return user_dir


def test_each_broken_file_affects_only_itself(broken_dir):
  assert ikea_suite.register_models(broken_dir) == ["mine_good"]
  reasons = {m.name: str(m.error) for m in ikea_suite.invalid_models()
             if m.path.startswith(str(broken_dir))}
  assert set(reasons) == set(BROKEN) | {"mine_broken", "a_folder"}
  for name, (_, message) in BROKEN.items():
    assert re.search(message, reasons[name]), (name, reasons[name])
  assert reasons["a_folder"].endswith("a_folder.xml: <file>: no such file")
  names = ikea_suite.furniture_names()
  assert GOOD in names and "mine_good" in names and not set(BROKEN) & set(names)
  assert not any(f in BROKEN for f, _ in ikea_suite.ALL)
  for name in (GOOD, "mine_good"):
    ikea_suite.load(name, "cursor", seed=0).reset()
  with pytest.raises(ikea_suite.ModelFormatError, match="slash_in_body.xml.*cannot contain a '/'"):
    ikea_suite.load("slash_in_body", "cursor")
  with pytest.raises(ikea_suite.ModelFormatError, match="huge_box.xml.*at most 4 m"):
    ikea_suite.load(broken_dir / "huge_box.xml", "cursor")


def test_the_gymnasium_env_loads_beside_a_broken_directory(broken_dir):
  gymnasium = pytest.importorskip("gymnasium")
  import ikea_suite.gym  # noqa: F401  (registers the environments)
  ikea_suite.register_models(broken_dir)
  env = gymnasium.make("ikea_suite/Assembly-v0", furniture=GOOD, robot="cursor")
  env.reset(seed=0)
  env.close()


def test_a_site_material_travels_with_its_part(user_dir):
  """A part's sites may use materials, like its geoms: the part entity carries them."""
  (user_dir / "mine_good.xml").write_text(_good_text().replace(
      '<site name="leg0_leg_top_0"', '<site material="metal" name="leg0_leg_top_0"'))
  assert ikea_suite.register_models(user_dir) == ["mine_good"]
  ikea_suite.load("mine_good", "cursor", seed=0).reset()
