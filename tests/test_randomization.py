"""Domain randomization, scene presets and curriculum placement."""

import numpy as np
import pytest

import ikea_suite
from ikea_suite import config
from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.arenas import presets
from ikea_suite.tasks import cameras
from ikea_suite.tasks import placement

FURNITURE = ikea_suite.DEFAULT_FURNITURE


def _load(seed=0, **options):
  return ikea_suite.load(FURNITURE, "cursor", seed=seed, **options)


def _scene_snapshot(env):
  """Everything the randomizer and the initializer may change."""
  model, data = env.physics.model, env.physics.data
  return [data.qpos.copy(), model.opt.gravity.copy(), model.body_mass.copy(),
          model.body_inertia.copy(), model.geom_friction.copy(), model.dof_damping.copy(),
          model.light_active.copy(), model.light_pos.copy(), model.light_dir.copy(),
          model.light_diffuse.copy(), model.mat_rgba.copy(), model.mat_specular.copy(),
          model.geom_matid.copy(), model.cam_pos.copy(), model.body_pos.copy()]


def test_parse_accepts_names_groups_and_dicts():
  parse = config.randomization_factors
  assert parse(None) == {}
  assert parse("friction") == {"friction": (0.5, 1.5)}
  assert set(parse("physics")) == set(config.PHYSICS_FACTORS)
  assert set(parse(["visual", "gravity"])) == set(config.RANDOMIZATION_GROUPS["visual"]) | {
      "gravity"}
  assert set(parse("all")) == set(config.RANDOMIZATION_FACTORS)
  factors = parse({"light_count": (2, 3), "floor": True, "part_mass": None,
                                 "camera_jitter": False})
  assert factors == {"light_count": (2, 3), "floor": True}


@pytest.mark.parametrize("randomize, error, message", [
    ("wind", errors.UnknownNameError, "gravity"),
    ({"frction": (0.5, 1.0)}, errors.UnknownNameError, "friction"),
    ({"friction": (1.5, 0.5)}, errors.OptionValueError, "friction"),
    ({"friction": 2.0}, errors.OptionValueError, "range"),
    ({"light_count": (1, 9)}, errors.OptionValueError, "light_count"),
    ({"camera_jitter": -0.1}, errors.OptionValueError, "camera_jitter"),
    ({"floor": 0.5}, errors.OptionValueError, "floor"),
])
def test_bad_randomization_options_raise(randomize, error, message):
  with pytest.raises(error, match=message):
    _load(randomize=randomize)


def test_default_is_unrandomized():
  snapshots = []
  for seed in (0, 1):
    env = _load(seed=seed)
    env.reset()
    snapshots.append(_scene_snapshot(env)[1:])   # all but qpos: placement is random
  for a, b in zip(*snapshots):
    np.testing.assert_array_equal(a, b)
  np.testing.assert_allclose(env.physics.model.opt.gravity, (0, 0, -9.81))


def test_same_seed_reproduces_the_randomized_episode():
  options = dict(randomize="all", preassembled=(0, 2), scene="garage")
  runs = []
  for seed in (7, 7, 8):
    env = _load(seed=seed, **options)
    snapshots = []
    for _ in range(2):   # two episodes: the second draw must repeat as well
      env.reset()
      for _ in range(3):
        env.step(np.full(env.action_spec().shape, 0.3))
      snapshots += _scene_snapshot(env)
    runs.append(snapshots)
  for a, b in zip(runs[0], runs[1]):
    np.testing.assert_array_equal(a, b)
  assert any(not np.array_equal(a, b) for a, b in zip(runs[0], runs[2]))


def test_physics_factors_stay_in_their_ranges():
  ranges = {"gravity": (8.0, 9.0), "friction": (0.5, 0.6), "part_mass": (1.5, 2.0),
            "part_damping": (0.1, 0.2)}
  plain = _load()
  plain.reset()
  env = _load(randomize=ranges)
  bodies = env.task.furniture.body_ids
  part_geoms = np.isin(env.physics.model.geom_bodyid, bodies)
  masses, gravities = set(), set()
  for _ in range(3):
    env.reset()
    model = env.physics.model
    gravity = model.opt.gravity
    assert gravity[:2] == pytest.approx((0, 0)) and 8.0 <= -gravity[2] <= 9.0
    gravities.add(float(gravity[2]))
    ratio = model.body_mass[bodies] / plain.physics.model.body_mass[bodies]
    assert np.all((ratio >= 1.5) & (ratio <= 2.0))
    inertia_ratio = model.body_inertia[bodies] / plain.physics.model.body_inertia[bodies]
    np.testing.assert_allclose(inertia_ratio, np.repeat(ratio[:, None], 3, axis=1))
    masses.add(tuple(ratio))
    friction = model.geom_friction[part_geoms, 0] / plain.physics.model.geom_friction[part_geoms, 0]
    assert np.all((friction >= 0.5) & (friction <= 0.6))
    for body in bodies:
      damping = model.dof_damping[model.body_dofadr[body]:model.body_dofadr[body] + 6]
      assert np.all((damping >= 0.1) & (damping <= 0.2))
  assert len(masses) == 3 and len(gravities) == 3   # drawn anew every episode


def test_visual_factors_vary_within_their_ranges():
  env = _load(randomize={"light_count": (2, 3), "camera_jitter": 0.1, "floor": True,
                         "part_color": True})
  plain = _load()
  plain.reset()
  floor_id = env.physics.bind(env.task.arena.floor).element_id
  top_geom = int(np.flatnonzero(env.physics.model.geom_bodyid == env.task.furniture.body_ids[0])[0])
  floors, colours = set(), set()
  for _ in range(6):
    env.reset()
    model = env.physics.model
    assert model.nlight == config.MAX_LIGHTS
    assert 2 <= model.light_active.sum() <= 3
    assert np.abs(model.cam_pos - plain.physics.model.cam_pos).max() <= 0.1 + 1e-9
    floors.add(int(model.geom_matid[floor_id]))
    colours.add(tuple(model.mat_rgba[model.geom_matid[top_geom]]))
  assert len(floors) > 1 and len(colours) == 6


@pytest.mark.parametrize("scene", presets.names())
def test_every_scene_preset_builds(scene):
  env = _load(scene=scene)
  env.reset()
  env.step(np.zeros(env.action_spec().shape))


def test_unknown_scene_names_the_presets():
  with pytest.raises(errors.UnknownNameError, match="garage, industrial, interior, lab, night"):
    _load(scene="beach")


def test_presets_look_different(gl):
  brightness = {}
  for scene in ("lab", "night", "garage", "default"):
    env = _load(scene=scene, cameras=("front",), image_size=32)
    brightness[scene] = env.reset().observation["cameras/front_rgb"].astype(float).mean(axis=(0, 1))
  assert brightness["night"].sum() < 0.5 * brightness["lab"].sum()
  assert not np.allclose(brightness["garage"], brightness["default"], atol=3)


def test_visual_randomization_changes_images_and_keeps_labels(gl):
  options = dict(cameras=("front", "side"), camera_outputs=("rgb", "segmentation"),
                 image_size=32)
  plain = _load(**options).reset().observation
  varied = _load(randomize="visual", **options).reset().observation
  assert np.abs(plain["cameras/front_rgb"].astype(int) - varied["cameras/front_rgb"]).mean() > 5
  # Backdrop walls are background, never a part (the side camera's low view shows them;
  # the front one looks down on the work area).
  labels = set(np.unique(varied["cameras/side_segmentation"]))
  assert cameras.BACKGROUND_ID in labels and cameras.FLOOR_ID in labels


# -- curriculum placement -------------------------------------------------------


def _relative_pose(env, a, b):
  pos, rot = env.task.furniture.part_poses(env.physics)
  return rot[a].T @ (pos[b] - pos[a]), rot[a].T @ rot[b]


def test_preassembled_parts_start_welded_in_their_assembled_pose():
  env = _load(preassembled=3)
  spec = env.task.furniture.spec
  for _ in range(2):
    env.reset()
    state = env.task.state
    assert len(state.connections) == 3 and state.num_groups == len(spec.parts) - 3
    table = env.task.furniture.connectors
    for con_a, con_b in state.connections:
      a, b = int(table.part[con_a]), int(table.part[con_b])
      rel_pos, rel_rot = _relative_pose(env, a, b)
      design_rot = spec.parts[a].rot.T @ spec.parts[b].rot
      design_pos = spec.parts[a].rot.T @ (spec.parts[b].pos - spec.parts[a].pos)
      np.testing.assert_allclose(rel_pos, design_pos, atol=1e-6)
      np.testing.assert_allclose(rel_rot, design_rot, atol=1e-6)
    for _ in range(20):   # the welds hold while the group settles
      env.step(np.zeros(env.action_spec().shape))
    for con_a, con_b in state.connections:
      a, b = int(table.part[con_a]), int(table.part[con_b])
      rel_pos, _ = _relative_pose(env, a, b)
      expected = spec.parts[a].rot.T @ (spec.parts[b].pos - spec.parts[a].pos)
      np.testing.assert_allclose(rel_pos, expected, atol=5e-3)


def _some_furniture(count=6):
  names = ikea_suite.furniture_names()
  return names[::max(1, len(names) // count)]


@pytest.mark.parametrize("furniture", _some_furniture())
def test_scattered_items_never_overlap(furniture):
  env = ikea_suite.load(furniture, "cursor", seed=3, preassembled=(0, 2))
  for _ in range(3):
    env.reset()
    physics = env.physics
    groups = env.task.state.group_labels()
    part_of_body = {int(b): i for i, b in enumerate(env.task.furniture.body_ids)}
    for contact in physics.data.contact[:physics.data.ncon]:
      a = part_of_body.get(int(physics.model.geom_bodyid[contact.geom1]))
      b = part_of_body.get(int(physics.model.geom_bodyid[contact.geom2]))
      if a is not None and b is not None:
        assert groups[a] == groups[b] or contact.dist > -1e-3


def test_preassembled_leaves_at_least_one_connection():
  env = _load(preassembled=50)
  env.reset()
  assert env.task.state.num_groups == 2


def test_the_last_part_start_leaves_one_part_loose_on_a_cycle():
  """preassembled = parts - 1 joins every part but one: on the plank bench, whose seat,
  end panels and stretcher form a cycle of connections, a random forest could leave two
  groups of two; the loose part is one whose removal leaves the rest connected, never the
  root (the seat, which everything is built onto)."""
  furniture = "bench_plank_pine"
  env = ikea_suite.load(furniture, "cursor", seed=4, preassembled=3)
  spec = env.task.furniture.spec
  table = env.task.furniture.connectors
  names = [part.name for part in spec.parts]
  choices = placement.last_part_choices(spec, table, placement.design_pairs(spec, table))
  assert [names[i] for i in choices] == ["end0", "end1", "stretcher"]
  loose_seen = set()
  for _ in range(12):
    env.reset()
    state = env.task.state
    groups = state.group_labels()
    labels, counts = np.unique(groups, return_counts=True)
    assert sorted(counts.tolist()) == [1, len(names) - 1]
    assert len(state.connections) == len(names) - 2
    loose_seen.add(names[int(np.flatnonzero(groups == labels[np.argmin(counts)])[0])])
  assert loose_seen == {"end0", "end1", "stretcher"}
  # A star of connections (a table's top and legs): only the legs can be last.
  table_env = _load()
  spec, table = table_env.task.furniture.spec, table_env.task.furniture.connectors
  legs = [i for i, part in enumerate(spec.parts) if i != table_env.task.root_part]
  assert placement.last_part_choices(spec, table, placement.design_pairs(spec, table)) == legs


def test_spread_and_yaw_range():
  env = _load(spread=0.0, yaw_range=0.0)
  furniture = env.task.furniture
  inner = placement.assembled_radius(furniture.spec) + 0.15
  env.reset()
  pos, rot = furniture.part_poses(env.physics)
  for index, part in enumerate(furniture.spec.parts):
    np.testing.assert_allclose(rot[index], placement.resting_rotation(part.bounds), atol=1e-9)
  distances = np.linalg.norm(pos[:, :2], axis=1)
  assert distances.min() >= inner - 1e-6
  wide = _load(spread=2.0)
  wide.reset()
  wide_pos, _ = wide.task.furniture.part_poses(wide.physics)
  assert np.linalg.norm(wide_pos[:, :2], axis=1).max() > distances.max()


@pytest.mark.parametrize("options, message", [
    (dict(preassembled=-1), "preassembled"), (dict(preassembled=(3, 1)), "preassembled"),
    (dict(spread=-0.5), "spread"), (dict(yaw_range="wide"), "yaw_range")])
def test_bad_placement_options_raise(options, message):
  with pytest.raises(errors.OptionValueError, match=message):
    _load(**options)


def test_yaw_is_applied_about_the_vertical():
  env = _load(yaw_range=0.3)
  env.reset()
  _, rot = env.task.furniture.part_poses(env.physics)
  for index, part in enumerate(env.task.furniture.spec.parts):
    yaw_rot = rot[index] @ placement.resting_rotation(part.bounds).T
    angle = geometry.mat_to_axis_angle(yaw_rot)
    assert abs(angle[2]) <= 0.3 + 1e-9 and np.allclose(angle[:2], 0, atol=1e-9)


def test_same_seed_renders_the_same_randomized_images(gl):
  options = dict(randomize="all", scene="interior", cameras=("front",), image_size=32,
                 camera_outputs=("rgb", "depth", "segmentation"))
  images = []
  for seed in (5, 5, 6):
    env = _load(seed=seed, **options)
    env.reset()
    observation = env.step(np.zeros(env.action_spec().shape)).observation
    images.append([observation[f"cameras/front_{kind}"] for kind in ("rgb", "depth",
                                                                      "segmentation")])
  for a, b in zip(images[0], images[1]):
    np.testing.assert_array_equal(a, b)
  assert not np.array_equal(images[0][0], images[2][0])
