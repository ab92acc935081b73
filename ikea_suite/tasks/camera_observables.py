"""Image observables: RGB, depth, part segmentation, part boxes and a goal image per camera.

`CameraRig` is an entity without bodies. Attached to the arena, it adds
`<camera>_<output>` observables (keys `cameras/front_rgb`, ...) for the
chosen cameras. Every camera renders once per control step however many
outputs read it, and nothing renders when no camera is chosen (no rig).
"""

import mujoco
import numpy as np
from dm_control import composer
from dm_control import mjcf
from dm_control.composer.observation import observable
from dm_env import specs

from ikea_suite import config
from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.tasks import cameras


def named_cameras(arena, robot):
  """Cameras by name: the arena's (front, top, side) and any the robot offers via `cameras`."""
  named = dict(arena.cameras)
  for name, element in robot.cameras.items():
    if name in named:
      raise errors.IkeaSuiteError(f"robot camera {name!r} clashes with an arena camera")
    named[name] = element
  return named


class _SpecObservable(observable.Generic):
  """A Generic observable with a fixed, declared array spec."""

  def __init__(self, fn, array_spec):
    super().__init__(fn)
    self._declared_spec = array_spec

  @property
  def array_spec(self):
    return self._declared_spec


class CameraRig(composer.Entity):
  """Renders the chosen cameras; one instance per environment."""

  def _build(self, arena, furniture, robot, cameras, outputs, image_size, goal_image):
    """`cameras`, `outputs` (names), `image_size` ((height, width), px) and `goal_image`:
    the checked options of a config.TaskConfig."""
    available = named_cameras(arena, robot)
    for name in cameras:
      if name not in available:
        raise errors.UnknownNameError("camera", name, available)
    self._mjcf_root = mjcf.RootElement(model="cameras")
    self._arena, self._furniture, self._robot = arena, furniture, robot
    self._elements = {name: available[name] for name in cameras}
    self._kinds = tuple(k for k in cameras_kinds(outputs))
    self._boxes = "part_boxes" in outputs
    self._goal = bool(goal_image) and bool(self._kinds)
    self._height, self._width = image_size
    # MuJoCo's offscreen buffer bounds the image size.
    offscreen = getattr(arena.mjcf_model.visual, "global")
    offscreen.offwidth = max(self._width, offscreen.offwidth or 640)
    offscreen.offheight = max(self._height, offscreen.offheight or 480)
    # Shadow maps dominate software rendering; small images need no finer one than 4 texels/pixel.
    quality = arena.mjcf_model.visual.quality
    quality.shadowsize = int(np.clip(4 * max(self._height, self._width), 512,
                                     quality.shadowsize or 4096))
    self._episode = 0
    self._renderers = {}
    self._frames, self._frames_key = {}, None
    self._goal_frames, self._goal_episode = {}, None

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def image_kinds(self):
    return self._kinds

  def _build_observables(self):
    observables = composer.Observables(self)
    for name in self._elements:
      for kind in self._kinds:
        observables.add_observable(f"{name}_{kind}", _SpecObservable(
            lambda physics, name=name, kind=kind: self._frame(physics, name)[kind],
            self._spec(kind)))
        if self._goal:
          observables.add_observable(f"{name}_goal_{kind}", _SpecObservable(
              lambda physics, name=name, kind=kind: self._goal_frame(physics, name)[kind],
              self._spec(kind)))
      if self._boxes:
        num_parts = len(self._furniture.parts)
        observables.add_observable(f"{name}_part_boxes", _SpecObservable(
            lambda physics, name=name: self.part_boxes(physics, name),
            specs.BoundedArray((num_parts, 4), np.float64, -1.0,
                               float(max(self._height, self._width) - 1))))
    return observables

  def _spec(self, kind):
    shape = (self._height, self._width)
    if kind == "rgb":
      return specs.BoundedArray(shape + (3,), np.uint8, 0, 255)
    if kind == "depth":
      return specs.BoundedArray(shape, np.float32, 0.0, np.inf)
    return specs.BoundedArray(shape, np.int32, cameras.ROBOT_ID, len(self._furniture.parts) - 1)

  # -- composer hooks ------------------------------------------------------------

  def after_compile(self, physics, random_state):
    self._renderers = {}   # a new physics needs new GL scenes
    self._frames_key = self._goal_episode = None
    model = physics.model
    self._labels = cameras.segmentation_labels(physics, self._furniture, self._robot,
                                               self._arena.floor)
    part_of_body = np.full(model.nbody, -1)
    part_of_body[self._furniture.body_ids] = np.arange(len(self._furniture.body_ids))
    visible = (part_of_body[model.geom_bodyid] >= 0) & (model.geom_group < 3)
    self._box_geoms = np.flatnonzero(visible)
    self._box_geom_part = part_of_body[model.geom_bodyid[self._box_geoms]]
    self._camera_ids = {name: physics.bind(el).element_id for name, el in self._elements.items()}

  def initialize_episode(self, physics, random_state):
    self._episode += 1

  # -- rendering -----------------------------------------------------------------

  def renderer(self, physics, name):
    """The cameras.MultiKindCamera that draws camera `name` for `physics` (made on first use)."""
    if name not in self._renderers:
      self._renderers[name] = cameras.MultiKindCamera(
          physics, self._height, self._width, self._camera_ids[name], self._labels)
    return self._renderers[name]

  def _blank(self):
    """What each output shows before the first episode: composer reads every observable once
    when the environment is built and drops the values at reset. Rendering then would make
    an OpenGL context in a process that may fork next (gymnasium's AsyncVectorEnv builds an
    environment in the parent to read its spaces), and a forked child cannot use the GL
    driver state it inherits: its first context waits forever."""
    return {kind: np.zeros(self._spec(kind).shape, self._spec(kind).dtype)
            for kind in self._kinds}

  def _frame(self, physics, name):
    if self._episode == 0:
      return self._blank()
    key = (self._episode, float(physics.data.time))
    if key != self._frames_key:
      self._frames, self._frames_key = {}, key
    if name not in self._frames:
      self._frames[name] = self.renderer(physics, name).render_kinds(self._kinds)
    return self._frames[name]

  def _goal_frame(self, physics, name):
    if self._episode == 0:
      return self._blank()
    if self._goal_episode != self._episode:
      self._goal_frames = self.render_assembled(physics)
      self._goal_episode = self._episode
    return self._goal_frames[name]

  def render_assembled(self, physics):
    """Every camera's images with the furniture in its assembled pose; physics is left as it was."""
    model, data = physics.model.ptr, physics.data.ptr
    what = mujoco.mjtState.mjSTATE_INTEGRATION
    saved = np.empty(mujoco.mj_stateSize(model, what))
    mujoco.mj_getState(model, data, saved, what)
    origin = self._arena.support.origin   # on the floor, or on a work table's top
    for part in self._furniture.parts:
      spec = part.spec
      part.set_pose(physics, position=origin + spec.pos, quaternion=geometry.mat_to_quat(spec.rot))
    physics.forward()
    frames = {name: self.renderer(physics, name).render_kinds(self._kinds)
              for name in self._elements}
    mujoco.mj_setState(model, data, saved, what)
    physics.forward()
    return frames

  def part_boxes(self, physics, name):
    """(num_parts, 4) boxes [x_min, y_min, x_max, y_max] in pixels of camera `name`."""
    return cameras.part_boxes(physics, self._camera_ids[name], self._height, self._width,
                              self._box_geoms, self._box_geom_part, len(self._furniture.parts))


def cameras_kinds(outputs):
  """The image kinds among `outputs`, in canonical order."""
  return [kind for kind in config.IMAGE_KINDS if kind in outputs]


def attach(task, task_config):
  """Attaches a CameraRig to the task's arena when the config (config.TaskConfig) chooses
  cameras; returns it or None."""
  if not task_config.cameras:
    return None
  rig = CameraRig(task.arena, task.furniture, task.robot, cameras=task_config.cameras,
                  outputs=task_config.camera_outputs, image_size=task_config.image_size,
                  goal_image=task_config.goal_image)
  task.arena.attach(rig)
  return rig
