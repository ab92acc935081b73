"""Domain randomization of physics and visuals, drawn anew at the start of every episode.

`SceneRandomizer` is an entity without bodies attached to the arena. It binds
dm_control variations (`composer.variation`) to MJCF elements and applies
them through a `PhysicsVariator` in `initialize_episode`, so nothing is
recompiled and the same seed reproduces the same scene. Every factor is off
unless named; config.RANDOMIZATION_FACTORS gives each factor's meaning, the
value it takes when switched on by name, and its bounds. The extra lights,
floor materials and walls it needs are built only for the factors switched on.
"""

import mujoco
import numpy as np
from dm_control import composer
from dm_control import mjcf
from dm_control.composer import variation
from dm_control.composer.variation import colors
from dm_control.composer.variation import distributions
from dm_control.composer.variation import noises

from ikea_suite import config
from ikea_suite.arenas import presets


def patterns(rgb1, rgb2):
  """Procedural 2D textures in a scene's own two colours: checker, tiles, speckle, gradient."""
  rgb1, rgb2 = np.asarray(rgb1, dtype=float), np.asarray(rgb2, dtype=float)
  return (dict(builtin="checker", rgb1=rgb1, rgb2=rgb2),
          dict(builtin="checker", rgb1=rgb1, rgb2=rgb1, mark="edge", markrgb=0.7 * rgb2),
          dict(builtin="flat", rgb1=rgb1, rgb2=rgb1, mark="random", markrgb=0.8 * rgb2, random=0.3),
          dict(builtin="gradient", rgb1=rgb1, rgb2=rgb2))


def _colours(texture):
  return texture.rgb1 if texture.rgb1 is not None else (0.8,) * 3, (
      texture.rgb2 if texture.rgb2 is not None else (0.5,) * 3)


_EXTRA_LIGHTS = (((-1.5, -1.5, 3.0), (0.4, 0.4, -1.0)), ((1.5, 1.5, 3.0), (-0.4, -0.4, -1.0)),
                 ((0.0, 2.0, 3.0), (0.0, -0.5, -1.0)), ((-2.0, 0.0, 3.0), (0.5, 0.0, -1.0)))


def _random_color(saturation=(0.15, 0.75), value=(0.3, 0.95)):
  return colors.HsvVariation(_one(0.0, 1.0), _one(*saturation), _one(*value))


def _one(low, high):
  """One uniform number per draw, whatever the shape of the attribute it varies."""
  return distributions.Uniform(low, high, single_sample=True)


def _shift(amount):
  return noises.Additive(distributions.Uniform(-amount * np.ones(3), amount * np.ones(3)))


class SceneRandomizer(composer.Entity):
  """Applies the chosen factors to the arena and the furniture at every episode start."""

  def _build(self, arena, furniture, factors):
    self._mjcf_root = mjcf.RootElement(model="randomizer")
    self._arena, self._furniture, self._factors = arena, furniture, dict(factors)
    self._variator = variation.PhysicsVariator()
    self._lights = arena.mjcf_model.find_all("light", exclude_attachments=True)
    if "light_count" in factors:
      for i in range(config.MAX_LIGHTS - len(self._lights)):
        pos, direction = _EXTRA_LIGHTS[i]
        self._lights.append(self._mjcf_root.worldbody.add(
            "light", name=f"extra_{i}", pos=pos, dir=direction, directional=True,
            diffuse=(0.3, 0.3, 0.3), castshadow=False))
    # Floor and wall patterns keep the scene preset's colours, so presets stay recognisable.
    root = arena.mjcf_model
    floor_patterns = patterns(*_colours(root.find("texture", "floor_grid")))
    self._floor_materials = []
    if "floor" in factors:
      self._floor_materials = [self._pattern_material(f"floor_{i}", pattern, (8, 8))
                               for i, pattern in enumerate(floor_patterns)]
    self._wall_materials = []
    if "background" in factors:
      walls = root.find("texture", "preset_wall") or root.find("texture", "skybox")
      wall_patterns = patterns(*_colours(walls))
      self._wall_materials.append(presets.add_walls(
          self._mjcf_root, "wall", wall_patterns[0], presets.WALL_DISTANCE - 0.05))
      self._wall_materials += [self._pattern_material(f"wall_{i}", pattern, (6, 2))
                               for i, pattern in enumerate(wall_patterns[1:])]
    self._bind_variations()

  def _pattern_material(self, name, pattern, repeat):
    texture = self._mjcf_root.asset.add("texture", name=name, type="2d", width=128, height=128,
                                        **pattern)
    return self._mjcf_root.asset.add("material", name=name, texture=texture, texrepeat=repeat)

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def factors(self):
    return dict(self._factors)

  def _part_geoms(self):
    return [g for part in self._furniture.parts for g in part.mjcf_model.find_all("geom")]

  def _part_materials(self):
    return [m for part in self._furniture.parts for m in part.mjcf_model.find_all("material")]

  def _bind_variations(self):
    f, bind = self._factors, self._variator.bind_attributes
    if "friction" in f:
      for geom in self._part_geoms() + list(self._arena.support_geoms):   # floor, table top
        bind(geom, friction=noises.Multiplicative(_one(*f["friction"])))
    if "part_damping" in f:
      for frame in self._furniture.part_frames:
        bind(frame.freejoint, damping=_one(*f["part_damping"]))
    for light in self._lights:
      if "light_position" in f:
        bind(light, pos=_shift(f["light_position"]), dir=_shift(f["light_position"]))
      if "light_color" in f or "light_intensity" in f:
        scale = _one(*f.get("light_intensity", (1.0, 1.0)))
        tint = colors.HsvVariation(_one(0.0, 1.0), _one(0.0, f.get("light_color", 0.0)), 1.0)
        bind(light, diffuse=noises.Multiplicative(scale * tint[:3]))
    for material in self._floor_materials + self._wall_materials:
      bind(material, rgba=_random_color(saturation=(0.0, 0.4), value=(0.8, 1.0)))
    for material in self._part_materials():
      if "part_color" in f:
        bind(material, rgba=_random_color())
      if "part_material" in f:
        bind(material, specular=_one(0.0, 0.8), shininess=_one(0.0, 0.9),
             reflectance=_one(0.0, 0.2))
    if "camera_jitter" in f:
      for camera in self._arena.cameras.values():
        bind(camera, pos=_shift(f["camera_jitter"]))
        if camera.target is not None:
          bind(camera.target, pos=_shift(f["camera_jitter"]))

  def after_compile(self, physics, random_state):
    model = physics.model
    self._gravity = model.opt.gravity.copy()
    self._part_bodies = np.array(physics.bind(self._furniture.part_frames).element_id)
    self._mass = model.body_mass[self._part_bodies].copy()
    self._inertia = model.body_inertia[self._part_bodies].copy()
    self._light_ids = np.array([physics.bind(light).element_id for light in self._lights])
    self._floor_id = physics.bind(self._arena.floor).element_id
    self._floor_ids = [physics.bind(m).element_id for m in self._floor_materials]
    walls = [g for g in self._mjcf_root.worldbody.find_all("geom") if g.name.startswith("wall")]
    self._wall_geoms = np.array(physics.bind(walls).element_id if walls else [], dtype=int)
    self._wall_ids = [physics.bind(m).element_id for m in self._wall_materials]

  def initialize_episode(self, physics, random_state):
    self._variator.apply_variations(physics, random_state)
    model, f = physics.model, self._factors
    if "gravity" in f:
      down = self._gravity / max(np.linalg.norm(self._gravity), 1e-9)
      model.opt.gravity[:] = down * random_state.uniform(*f["gravity"])
    if "part_mass" in f:
      scale = random_state.uniform(*f["part_mass"], size=len(self._part_bodies))
      model.body_mass[self._part_bodies] = self._mass * scale
      model.body_inertia[self._part_bodies] = self._inertia * scale[:, None]
      _refresh_derived_constants(physics)
    if "light_count" in f:
      count = random_state.randint(f["light_count"][0], f["light_count"][1] + 1)
      model.light_active[self._light_ids] = False
      model.light_active[random_state.choice(self._light_ids, count, replace=False)] = True
    if self._floor_ids:
      model.geom_matid[self._floor_id] = self._floor_ids[random_state.randint(len(self._floor_ids))]
    if self._wall_ids:
      model.geom_matid[self._wall_geoms] = self._wall_ids[random_state.randint(len(self._wall_ids))]


def _refresh_derived_constants(physics):
  """Recomputes what MuJoCo derives from masses at compile time (mj_setConst: inverse
  weights that scale every constraint's softness, subtree masses). Without it, the
  Cursor's firm grip and the welds keep the compiled parts' weights, and a part made
  2x lighter diverges within seconds. mj_setConst works on the data at qpos0, so the
  episode's state is kept aside and put back."""
  data = physics.data
  saved = {name: getattr(data, name).copy() for name in ("qpos", "qvel", "act", "ctrl",
                                                          "eq_active", "mocap_pos", "mocap_quat")}
  mujoco.mj_setConst(physics.model.ptr, data.ptr)
  for name, value in saved.items():
    getattr(data, name)[:] = value


def attach(task, factors):
  """Attaches a SceneRandomizer for `factors` (a TaskConfig's `randomize`: {factor: value})
  when any factor is on; returns it or None."""
  if not factors:
    return None
  randomizer = SceneRandomizer(task.arena, task.furniture, factors)
  task.arena.attach(randomizer)
  return randomizer
