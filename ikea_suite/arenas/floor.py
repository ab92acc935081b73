"""A floor arena with lights and named cameras looking at the assembly area."""

from dm_control import composer

from ikea_suite.arenas import support as support_lib

CAMERAS = {
    # name: (position, point looked at)
    "front": ((0.0, -2.2, 1.5), (0.0, 0.0, 0.35)),
    "top": ((0.0, 0.0, 3.2), (0.0, 0.0, 0.0)),
    "side": ((2.2, 0.0, 1.4), (0.0, 0.0, 0.35)),
}


def _look_at(mjcf_root, name, pos, target):
  body = mjcf_root.worldbody.add("body", name=f"{name}_camera_target", pos=target)
  return mjcf_root.worldbody.add("camera", name=name, pos=pos, mode="targetbody", target=body,
                                 fovy=45)


class FloorArena(composer.Arena):
  """A large checkered floor, a skybox, two lights and front/top/side cameras."""

  def _build(self, name="floor", size=(4.0, 4.0)):
    super()._build(name=name)
    root = self._mjcf_root
    root.visual.headlight.set_attributes(ambient=(0.35, 0.35, 0.35), diffuse=(0.5, 0.5, 0.5),
                                         specular=(0.1, 0.1, 0.1))
    root.visual.map.znear = 0.01
    # Software GL: a 4096 shadow map and 4x multisampling cost ~6x the frame time.
    root.visual.quality.set_attributes(shadowsize=1024, offsamples=0)
    root.asset.add("texture", name="skybox", type="skybox", builtin="gradient",
                   rgb1=(0.55, 0.62, 0.70), rgb2=(0.15, 0.17, 0.20), width=256, height=256)
    grid = root.asset.add("texture", name="floor_grid", type="2d", builtin="checker",
                          rgb1=(0.32, 0.34, 0.37), rgb2=(0.27, 0.29, 0.32), width=256, height=256)
    material = root.asset.add("material", name="floor", texture=grid, texrepeat=(8, 8),
                              reflectance=0.05)
    self._floor = root.worldbody.add("geom", name="floor", type="plane", material=material,
                                     size=(size[0], size[1], 0.1), friction=(0.9, 0.005, 0.0001))
    root.worldbody.add("light", name="key", pos=(1.0, -1.5, 3.0), dir=(-0.3, 0.5, -1.0),
                       directional=True, castshadow=True, diffuse=(0.6, 0.6, 0.6))
    root.worldbody.add("light", name="fill", pos=(-1.5, 1.0, 2.5), dir=(0.5, -0.3, -1.0),
                       directional=True, castshadow=False, diffuse=(0.3, 0.3, 0.3))
    self._cameras = {name: _look_at(root, name, pos, target)
                     for name, (pos, target) in CAMERAS.items()}

  @property
  def floor(self):
    return self._floor

  @property
  def support(self):
    """Where parts lie at the start of an episode: the unbounded floor at z = 0."""
    return support_lib.FLOOR

  @property
  def mount_height(self):
    """Height (m) the robot's base is raised by: none, it stands on the floor."""
    return 0.0

  @property
  def support_geoms(self):
    """Geoms parts rest on (their friction is randomized with the parts')."""
    return [self._floor]

  @property
  def cameras(self):
    return self._cameras
