"""Scene presets: named looks of the floor arena after the paper's backgrounds.

Each preset sets the sky, a procedural floor texture, optional backdrop
walls, the headlight and the directional lights at build time. Per-episode
variation on top of a preset is the job of `tasks.randomization`.
"""

import dataclasses

import numpy as np

from ikea_suite.arenas import floor
from ikea_suite.arenas import work_table

# load(arena=...): the open floor, or a work table in front of an arm (arenas/work_table.py).
ARENAS = ("floor", "work_table")

WALL_DISTANCE = 4.0   # metres from the origin, at the floor's edge
WALL_HEIGHT = 3.0


@dataclasses.dataclass(frozen=True)
class Light:
  pos: tuple
  dir: tuple
  diffuse: tuple
  castshadow: bool = False


@dataclasses.dataclass(frozen=True)
class ScenePreset:
  """A scene look. Textures are MuJoCo builtins, so nothing is loaded from disk."""
  sky: tuple                 # (top colour, bottom colour) of the gradient skybox
  floor: dict                # attributes of the floor's 2D builtin texture
  floor_repeat: tuple = (8, 8)
  floor_reflectance: float = 0.05
  walls: dict = None         # attributes of the walls' builtin texture; None = open sky
  ambient: tuple = (0.35, 0.35, 0.35)   # headlight
  headlight: tuple = (0.5, 0.5, 0.5)
  lights: tuple = ()         # replaces the arena's key and fill lights; () keeps them


def _tiles(rgb1, rgb2, mark_rgb):
  return dict(builtin="checker", rgb1=rgb1, rgb2=rgb2, mark="edge", markrgb=mark_rgb)


def _speckle(rgb, dots, amount):
  return dict(builtin="flat", rgb1=rgb, rgb2=rgb, mark="random", markrgb=dots, random=amount)


PRESETS = {
    # The arena as built: grey checker floor under a blue-grey sky.
    "default": None,
    # Bright, clean: pale floor tiles, white walls, cool overhead light.
    "lab": ScenePreset(
        sky=((0.85, 0.88, 0.92), (0.6, 0.62, 0.66)),
        floor=_tiles((0.55, 0.56, 0.58), (0.52, 0.53, 0.55), (0.4, 0.41, 0.43)),
        floor_repeat=(16, 16),
        walls=_tiles((0.66, 0.67, 0.69), (0.64, 0.65, 0.67), (0.55, 0.56, 0.58)),
        ambient=(0.3, 0.31, 0.33), headlight=(0.35, 0.35, 0.37),
        lights=(Light((0.0, -1.0, 3.0), (0.0, 0.3, -1.0), (0.45, 0.47, 0.5), True),
                Light((1.5, 1.5, 2.5), (-0.5, -0.5, -1.0), (0.2, 0.21, 0.23)))),
    # Speckled concrete, dark walls, one warm lamp from the side.
    "garage": ScenePreset(
        sky=((0.3, 0.3, 0.3), (0.15, 0.15, 0.15)),
        floor=_speckle((0.45, 0.45, 0.43), (0.3, 0.3, 0.29), 0.25), floor_reflectance=0.0,
        walls=_speckle((0.32, 0.33, 0.35), (0.24, 0.25, 0.26), 0.2),
        ambient=(0.22, 0.21, 0.2), headlight=(0.35, 0.33, 0.3),
        lights=(Light((2.0, -1.0, 2.5), (-0.7, 0.3, -1.0), (0.7, 0.6, 0.45), True),)),
    # Warm wooden floor boards and beige walls.
    "interior": ScenePreset(
        sky=((0.9, 0.85, 0.75), (0.6, 0.55, 0.48)),
        floor=dict(builtin="checker", rgb1=(0.36, 0.26, 0.17), rgb2=(0.33, 0.24, 0.15),
                   mark="random", markrgb=(0.27, 0.19, 0.12), random=0.08),
        floor_repeat=(2, 24), floor_reflectance=0.1,
        walls=_speckle((0.62, 0.58, 0.5), (0.58, 0.54, 0.47), 0.05),
        ambient=(0.3, 0.27, 0.24), headlight=(0.36, 0.33, 0.3),
        lights=(Light((1.0, -1.5, 3.0), (-0.3, 0.5, -1.0), (0.5, 0.42, 0.32), True),
                Light((-1.5, 1.0, 2.5), (0.5, -0.3, -1.0), (0.3, 0.26, 0.2)))),
    # Dark steel plate floor, blue-grey walls, sodium-yellow light.
    "industrial": ScenePreset(
        sky=((0.35, 0.38, 0.42), (0.12, 0.13, 0.15)),
        floor=_tiles((0.3, 0.31, 0.33), (0.26, 0.27, 0.29), (0.18, 0.18, 0.2)), floor_repeat=(6, 6),
        floor_reflectance=0.15,
        walls=_tiles((0.28, 0.34, 0.4), (0.25, 0.3, 0.36), (0.2, 0.22, 0.25)),
        ambient=(0.25, 0.24, 0.2), headlight=(0.4, 0.38, 0.3),
        lights=(Light((0.0, 0.0, 3.5), (0.0, 0.1, -1.0), (0.75, 0.6, 0.3), True),
                Light((-2.0, -2.0, 2.0), (0.6, 0.6, -0.6), (0.2, 0.2, 0.25)))),
    # Moonlight: dark blue sky, faint bluish key light.
    "night": ScenePreset(
        sky=((0.04, 0.05, 0.12), (0.01, 0.01, 0.03)),
        floor=_tiles((0.16, 0.17, 0.2), (0.13, 0.14, 0.17), (0.1, 0.1, 0.12)),
        ambient=(0.08, 0.09, 0.14), headlight=(0.15, 0.16, 0.22),
        lights=(Light((-1.0, -1.0, 3.0), (0.3, 0.3, -1.0), (0.25, 0.28, 0.45), True),)),
    # Even, shadowless light: bright headlight, no directional lights.
    "ambient": ScenePreset(
        sky=((0.8, 0.8, 0.8), (0.7, 0.7, 0.7)),
        floor=dict(builtin="flat", rgb1=(0.6, 0.6, 0.6), rgb2=(0.6, 0.6, 0.6)),
        floor_reflectance=0.0,
        ambient=(0.6, 0.6, 0.6), headlight=(0.5, 0.5, 0.5), lights=None),
}


def names():
  return sorted(PRESETS)


def make_arena(scene, arena, base_pose=None):
  """A FloorArena, or a WorkTableArena in front of `base_pose`, dressed as preset `scene`.

  Args:
    scene: a preset name (names()), as config.TaskConfig checks it.
    arena: one of ARENAS, as config.TaskConfig checks it.
    base_pose: (position (3,), rotation (3, 3)) of the robot base, which the work table
      stands in front of; needed for arena="work_table" only.
  """
  if arena == "work_table":
    pos, rot = base_pose
    arena = work_table.WorkTableArena(base_xy=pos[:2], base_yaw=np.arctan2(rot[1, 0], rot[0, 0]))
  else:
    arena = floor.FloorArena()
  if PRESETS[scene] is not None:
    apply(arena, PRESETS[scene])
  return arena


def apply(arena, preset):
  """Rewrites the arena's sky, floor, walls, headlight and lights as `preset` says."""
  root = arena.mjcf_model
  root.find("texture", "skybox").set_attributes(rgb1=preset.sky[0], rgb2=preset.sky[1])
  floor_texture = root.find("texture", "floor_grid")
  for attribute in ("mark", "markrgb", "random"):
    setattr(floor_texture, attribute, None)
  floor_texture.set_attributes(**preset.floor)
  root.find("material", "floor").set_attributes(texrepeat=preset.floor_repeat,
                                                reflectance=preset.floor_reflectance)
  root.visual.headlight.set_attributes(ambient=preset.ambient, diffuse=preset.headlight)
  _set_lights(root, preset.lights)
  if preset.walls is not None:
    add_walls(root, "preset_wall", preset.walls, WALL_DISTANCE)


def _set_lights(root, lights):
  existing = [root.find("light", "key"), root.find("light", "fill")]
  if lights == ():
    return
  lights = lights or ()
  for index, light in enumerate(lights):
    element = existing[index] if index < len(existing) else root.worldbody.add(
        "light", name=f"preset_light_{index}", directional=True)
    element.set_attributes(pos=light.pos, dir=light.dir, diffuse=light.diffuse,
                           castshadow=light.castshadow)
  for element in existing[len(lights):]:
    element.active = False


def add_walls(root, name, texture, distance):
  """Four non-colliding backdrop walls around the origin; returns their material."""
  tex = root.asset.add("texture", name=name, type="2d", width=128, height=128, **texture)
  material = root.asset.add("material", name=name, texture=tex, texrepeat=(6, 2),
                            texuniform=False)
  half = WALL_HEIGHT / 2
  sides = ((0, distance, distance, 0.02), (0, -distance, distance, 0.02),
           (distance, 0, 0.02, distance), (-distance, 0, 0.02, distance))
  for i, (x, y, sx, sy) in enumerate(sides):
    root.worldbody.add("geom", name=f"{name}_{i}", type="box", pos=(x, y, half),
                       size=(sx, sy, half), material=material, contype=0, conaffinity=0, group=1)
  return material
