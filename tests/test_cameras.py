"""Image observables: RGB, depth, part segmentation, boxes and the goal image."""


import numpy as np
import pytest

import ikea_suite
from ikea_suite import config
from ikea_suite import errors
from ikea_suite.arenas import floor
from ikea_suite.environment import Environment
from ikea_suite.props import catalog
from ikea_suite.props import furniture as furniture_lib
from ikea_suite.robots import cursor
from ikea_suite.tasks import assembly
from ikea_suite.tasks import camera_observables
from ikea_suite.tasks import cameras
from ikea_suite.tasks import framing

SIZE = 32
ALL_OUTPUTS = ("rgb", "depth", "segmentation", "part_boxes")


def _load(**options):
  options.setdefault("image_size", SIZE)
  return ikea_suite.load(ikea_suite.DEFAULT_FURNITURE, "cursor", seed=0, **options)


def test_cameras_are_off_by_default():
  env = _load()
  env.reset()
  assert not any(key.startswith("cameras/") for key in env.observation_spec())
  assert not any(entity.mjcf_model.model == "cameras"
                 for entity in env.task.arena.iter_entities())


def test_every_output_is_a_spec_valid_observable(gl):
  env = _load(cameras=("front", "top"), camera_outputs=ALL_OUTPUTS, image_size=(24, 40),
              goal_image=True)
  spec = env.observation_spec()
  timestep = env.reset()
  for _ in range(2):
    for name in ("front", "top"):
      for kind in ("rgb", "depth", "segmentation"):
        for key in (f"cameras/{name}_{kind}", f"cameras/{name}_goal_{kind}"):
          spec[key].validate(timestep.observation[key])
      boxes = f"cameras/{name}_part_boxes"
      spec[boxes].validate(timestep.observation[boxes])
    timestep = env.step(np.zeros(env.action_spec().shape))
  observation = timestep.observation
  assert observation["cameras/front_rgb"].shape == (24, 40, 3)
  assert observation["cameras/front_rgb"].dtype == np.uint8
  assert observation["cameras/front_depth"].shape == (24, 40)
  assert observation["cameras/front_segmentation"].dtype == np.int32
  assert observation["cameras/front_part_boxes"].shape == (len(env.task.furniture.parts), 4)


def test_segmentation_ids_follow_the_documented_convention(gl):
  # The side camera's low view shows the sky (background); the front looks down on the parts.
  env = _load(cameras=("top", "front", "side"), camera_outputs=("segmentation",), image_size=64)
  observation = env.reset().observation
  num_parts = len(env.task.furniture.parts)
  seen = set()
  for name in ("top", "front", "side"):
    labels = np.unique(observation[f"cameras/{name}_segmentation"])
    assert set(labels) <= {cameras.BACKGROUND_ID, cameras.FLOOR_ID, cameras.ROBOT_ID,
                           *range(num_parts)}
    seen |= set(labels)
  assert cameras.FLOOR_ID in seen and cameras.BACKGROUND_ID in seen
  assert cameras.ROBOT_ID in seen   # the cursors float in view
  assert len(seen & set(range(num_parts))) >= 3


def test_part_pixels_lie_inside_their_boxes(gl):
  env = _load(cameras=("front",), camera_outputs=("segmentation", "part_boxes"), image_size=64)
  observation = env.reset().observation
  segmentation = observation["cameras/front_segmentation"]
  boxes = observation["cameras/front_part_boxes"]
  checked = 0
  for part, box in enumerate(boxes):
    rows, columns = np.nonzero(segmentation == part)
    if not len(rows):
      continue
    checked += 1
    assert box[0] - 1 <= columns.min() and columns.max() <= box[2] + 1
    assert box[1] - 1 <= rows.min() and rows.max() <= box[3] + 1
    # Unoccluded parts lying flat fill most of their box's extent.
    assert columns.max() - columns.min() >= 0.5 * (box[2] - box[0]) - 2
  assert checked >= 3


def test_depth_is_in_metres(gl):
  env = _load(cameras=("top",), camera_outputs=("depth", "segmentation"), image_size=33)
  observation = env.reset().observation
  depth, labels = observation["cameras/top_depth"], observation["cameras/top_segmentation"]
  height = floor.CAMERAS["top"][0][2]
  assert labels[16, 16] == cameras.FLOOR_ID   # the centre is clear of parts
  assert depth[16, 16] == pytest.approx(height, rel=0.01)
  floor_depth = depth[labels == cameras.FLOOR_ID]
  assert floor_depth.min() >= height * 0.99
  # A part lying on the floor is nearer than the floor.
  assert depth[labels >= 0].max() < floor_depth.max()


def test_each_camera_renders_once_per_control_step(gl, monkeypatch):
  calls = []
  original = cameras.MultiKindCamera.render_kinds

  def counting(self, kinds):
    calls.append(tuple(kinds))
    return original(self, kinds)

  monkeypatch.setattr(cameras.MultiKindCamera, "render_kinds", counting)
  env = _load(cameras=("front", "side"), camera_outputs=ALL_OUTPUTS)
  env.reset()
  calls.clear()
  for _ in range(3):
    env.step(np.zeros(env.action_spec().shape))
  assert len(calls) == 3 * 2
  assert all(kinds == ("rgb", "depth", "segmentation") for kinds in calls)


def test_goal_image_shows_the_assembled_furniture_and_leaves_physics_alone(gl):
  action = np.zeros(15)
  action[[0, 1, 9]] = (0.5, -0.3, 0.4)
  trajectories = []
  # 84 px, the size pixel policies use: the front camera frames the Cursor's whole ring,
  # so at 32 px a 5 cm leg is under a pixel wide.
  size = 84
  for options in ({}, dict(cameras=("front",), camera_outputs=("rgb", "segmentation"),
                           goal_image=True, image_size=size)):
    env = _load(**options)
    timestep = env.reset()
    first = timestep.observation
    for _ in range(5):
      timestep = env.step(action)
    trajectories.append(env.physics.data.qpos.copy())
  np.testing.assert_array_equal(*trajectories)
  goal = first["cameras/front_goal_segmentation"]
  np.testing.assert_array_equal(goal, timestep.observation["cameras/front_goal_segmentation"])
  goal_parts = set(np.unique(goal)) & set(range(len(env.task.furniture.parts)))
  assert len(goal_parts) >= 3   # the top and at least two legs, assembled at the origin
  assert not np.array_equal(first["cameras/front_goal_rgb"], first["cameras/front_rgb"])
  middle = slice(size // 4, 3 * size // 4)
  centre = goal[middle, middle]
  assert (centre >= 0).mean() > (first["cameras/front_segmentation"][middle, middle] >= 0).mean()


def test_bad_camera_options_name_the_valid_choices():
  with pytest.raises(errors.UnknownNameError, match="front, side, top"):
    _load(cameras=("back",))
  with pytest.raises(errors.UnknownNameError, match="part_boxes"):
    _load(cameras=("front",), camera_outputs=("normals",))
  for size in (0, (32,), (32, 32.5), "big"):
    with pytest.raises(errors.OptionValueError, match="image_size"):
      _load(cameras=("front",), image_size=size)


class _CursorWithCamera(cursor.Cursor):
  """A robot that contributes a named camera, as wrist cameras will."""

  def _build(self, **kwargs):
    super()._build(**kwargs)
    body = self.mjcf_model.find("body", "cursor0")
    self._camera = body.add("camera", name="eye", pos=(0, 0, 0.05), quat=(0, 1, 0, 0))

  @property
  def cameras(self):
    return {"cursor_eye": self._camera}


def test_a_robot_can_contribute_named_cameras(gl):
  arena = floor.FloorArena()
  furniture = furniture_lib.Furniture(catalog.spec(ikea_suite.DEFAULT_FURNITURE))
  robot = _CursorWithCamera()
  task = assembly.Assembly(arena=arena, furniture=furniture, robot=robot)
  assert set(camera_observables.named_cameras(arena, robot)) == {"front", "top", "side",
                                                                  "cursor_eye"}
  camera_observables.attach(task, config.TaskConfig(cameras=("cursor_eye", "top"),
                                                    image_size=SIZE))
  env = Environment(task, time_limit=1.0, random_state=0)
  observation = env.reset().observation
  assert observation["cameras/cursor_eye_rgb"].shape == (SIZE, SIZE, 3)
  assert not np.array_equal(observation["cameras/cursor_eye_rgb"], observation["cameras/top_rgb"])


@pytest.mark.parametrize("robot, camera", [("sawyer", "wrist"), ("baxter", "left_wrist")])
def test_arm_wrist_cameras_are_named_cameras(gl, robot, camera):
  env = ikea_suite.load(ikea_suite.DEFAULT_FURNITURE, robot, seed=0, cameras=(camera,),
                        camera_outputs=("rgb", "depth", "segmentation"), image_size=SIZE)
  observation = env.reset().observation
  assert observation[f"cameras/{camera}_rgb"].shape == (SIZE, SIZE, 3)
  assert np.isfinite(observation[f"cameras/{camera}_depth"]).all()
  # The gripper fills part of its own wrist view.
  assert (observation[f"cameras/{camera}_segmentation"] == cameras.ROBOT_ID).any()


@pytest.mark.parametrize("robot, arena", [("cursor", "floor"), ("sawyer", "floor"),
                                          ("panda", "floor"), ("jaco", "floor"),
                                          ("baxter", "floor"), ("panda", "work_table")])
def test_the_front_camera_frames_the_work_area(robot, arena):
  # Each robot at its work scale (load's default), over a few layouts: every part's centre
  # falls in the central 80% of the 84 px front image and the parts spread over most of
  # its width; on the work table its top reaches both sides of the image, as
  # FurnitureBench's front camera shows its table.
  size = 84
  env = ikea_suite.load(ikea_suite.DEFAULT_FURNITURE, robot, seed=0, arena=arena)
  pixels = []
  for _ in range(4):
    env.reset()
    physics = env.physics
    projection = cameras.camera_projection(
        physics, physics.model.name2id(framing.CAMERA, "camera"), size, size)
    centres, _ = env.task.furniture.part_poses(physics)
    points, in_front = cameras.project_points(centres, *projection, size, size)
    assert in_front.all()
    pixels.append(points / (size - 1))
  pixels = np.concatenate(pixels)
  assert pixels.min() >= 0.1 and pixels.max() <= 0.9
  assert np.ptp(pixels[:, 0]) > 0.6
  support = env.task.arena.support
  if support.bounded:
    hx, hy = support.half_size
    c, s = np.cos(support.yaw), np.sin(support.yaw)
    corners = (np.array([[hx, hy], [hx, -hy], [-hx, hy], [-hx, -hy]])
               @ np.array([[c, s], [-s, c]]) + np.asarray(support.centre))
    corners = np.hstack([corners, np.full((4, 1), support.height)])
    table, _ = cameras.project_points(corners, *projection, size, size)
    table /= size - 1
    assert table[:, 0].min() < 0.05 and table[:, 0].max() > 0.95


def test_framing_keeps_a_square_image_s_points_within_the_fill():
  points = np.array([[-1.0, -0.5, 0.0], [1.0, 0.5, 0.0], [0.3, 0.0, 0.4]])
  direction = np.array([0.0, -np.cos(np.pi / 4), np.sin(np.pi / 4)])
  position, target = framing.look_at(points, direction, fovy=45.0, fill=0.8)
  forward = (target - position) / np.linalg.norm(target - position)
  np.testing.assert_allclose(forward, -direction, atol=1e-9)
  right = np.cross(forward, [0.0, 0.0, 1.0])
  right /= np.linalg.norm(right)
  up = np.cross(right, forward)
  offsets = points - position
  depth = offsets @ forward
  tangents = np.stack([offsets @ right, offsets @ up], axis=1) / depth[:, None]
  limit = 0.8 * np.tan(np.radians(22.5))
  assert np.abs(tangents).max() <= limit + 1e-6
  assert np.abs(tangents).max() > 0.98 * limit        # no farther than it needs
  # Centred: the extremes sit symmetrically about the image's middle.
  assert abs(tangents[:, 0].max() + tangents[:, 0].min()) < 1e-3 * limit
