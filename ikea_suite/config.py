"""The options of ikea_suite.load() as frozen dataclasses: the only defaults, the only checks.

`TaskConfig` holds the task's options (time steps, alignment thresholds, rewards,
time limit, arena, furniture scale, scene, part placement, randomization,
cameras); each robot kind has its own dataclass, to which the robot class points
(`Robot.CONFIG`): `CursorConfig`, and `ArmConfig` with a subclass per arm that
sets its base position; each robot config's WORK_SCALE is the furniture scale
the robot loads at when no scale is given; `GymConfig` holds the gymnasium adapter's own options.

Constructing a config checks every field (an OptionValueError or UnknownNameError
naming the value and what is valid) and stores it normalised: numbers as
floats, vectors and ranges as tuples, `randomize` as a {factor: value} dict. So
a config that exists is valid. A field whose default depends on the furniture
or the robot is None until `TaskConfig.resolved` fills it in; the task keeps
the resolved config (`env.task.config`, `env.task.robot.config`).

Each field's metadata holds its meaning and unit, which `option_rows()` lists
for the generated options table of the docs.

Checks that need a built scene stay where the scene is: camera names (the
robot adds its own), the arena against the robot kind, a spread against an
arm's reach, a physics time step against an arm's servos, and furniture
against the work table (suite.load).
"""

import dataclasses
import os
import typing

import numpy as np

from ikea_suite import errors
from ikea_suite import options as check
from ikea_suite import physics_settings
from ikea_suite.arenas import floor
from ikea_suite.arenas import presets
from ikea_suite.props import scaling
from ikea_suite.robots import control_modes

# -- values the defaults are made of -------------------------------------------------

# Default episode length: a start-up allowance plus a fixed budget per part (500 control
# steps at 20 Hz), so larger furniture gets proportionally longer episodes.
TIME_LIMIT_BASE = 30.0          # s
TIME_LIMIT_PER_PART = 25.0      # s
DISTANCE_THRESHOLD = 0.02       # m between connectors at scale 1; scales with the furniture
SCATTER_SPREAD = 0.9            # m, width of the ring the Cursor's parts are scattered in
REWARDS = ("sparse", "dense")
IMAGE_KINDS = ("rgb", "depth", "segmentation")
CAMERA_OUTPUTS = IMAGE_KINDS + ("part_boxes",)
MAX_IMAGE_SIZE = 2048           # px, per side of a camera image
# An agent that acts less often than once a second cannot servo a part onto its mate;
# the bound also keeps the substeps of one control step within MuJoCo's int count.
MAX_CONTROL_TIMESTEP = 1.0
MAX_SEED = 2**32 - 1            # numpy's RandomState, which composer seeds, takes 32-bit seeds
# Default Cartesian stiffness of impedance mode: 1500 N/m and 60 N m/rad, ten times
# libfranka's Cartesian impedance example (150 N/m, 10 N m/rad,
# examples/cartesian_impedance_control.cpp, a soft hand-guiding setting) so that a 1 kg
# part sags 6.5 mm and the tool settles within 2-3 mm of its target.
IMPEDANCE_STIFFNESS = (1500.0, 60.0)
# Where an arm's base may stand (base_pos), relative to the surface it stands on. z >= 0:
# below it the base is buried in the floor or the table. z <= 0.3: from there every arm
# still puts its tool, pointing down, 3 cm above the surface at the part built onto
# (its ROOT_DISTANCE ahead) within 2 mm by IK (reach_check); 0.2 m higher the Panda, Jaco
# and Baxter miss it by 2 to 7 cm. |x|, |y| <= 3: the arm's parts, up to a metre from its
# base, stay on the 8 m floor, inside the backdrop walls 4 m out.
BASE_XY_LIMIT = 3.0             # m
BASE_HEIGHT_LIMIT = 0.3         # m
# The furniture scale a robot loads at when load() gets none: the scale its expert
# assembles at. The Cursor reaches everywhere and takes full-size furniture. An arm takes
# half size: at 0.5 a 55 cm table top is 27.5 cm and every part of the small furniture
# lies within the arm's reach on the work area in front of its base, the way
# FurnitureBench assembles miniature furniture (its expert sweeps ran at 0.5, 3 of 4
# connections for the Sawyer's Lack table at 1.0).
FULL_SCALE = 1.0
ARM_WORK_SCALE = 0.5


# -- randomization factors -----------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Factor:
  """A domain-randomization factor (tasks/randomization.py applies them).

  Attributes:
    kind: "range" (a (low, high) range drawn from each episode), "amount" (a largest
      shift or saturation) or "switch" (on or off).
    default: its value when switched on by name.
    meaning: what it varies, with the unit.
    low, high: bounds of a range's ends or of an amount.
    why: the reason for a bound, said when a value is refused.
    whole: whether a range takes whole numbers only.
  """
  kind: str
  default: typing.Any
  meaning: str
  low: float = 0.0
  high: float = np.inf
  why: str = ""
  whole: bool = False


MAX_LIGHTS = 4
# Twice Earth's gravity: domain randomization spans the gravity a robot meets, not
# other planets'; the Sawyer expert and the Cursor oracle still assemble the Lack table
# at 2 g.
MAX_GRAVITY = 2 * 9.81
# A part's mass and inertia scaled to 0 make MuJoCo's mass matrix singular
# (mjWARN_INERTIA at reset; from about 1e-12 on for the Lack table's legs). The Cursor
# oracle and the Sawyer expert assemble the Lack table alike from 0.001 to 1;
# 0.01, a hundredth of a part's designed mass, keeps a factor of ten from the lightest
# tried.
MIN_MASS_SCALE = 0.01

RANDOMIZATION_FACTORS = {
    "gravity": Factor("range", (9.0, 10.6), "gravity magnitude, m/s^2 (pointing down)",
                      high=MAX_GRAVITY, why="0 to twice Earth's gravity"),
    "friction": Factor("range", (0.5, 1.5), "multiplier of each part's and the floor's friction"),
    "part_mass": Factor("range", (0.5, 2.0), "multiplier of each part's mass and inertia",
                        low=MIN_MASS_SCALE,
                        why="a part without mass makes MuJoCo's mass matrix singular"),
    "part_damping": Factor("range", (0.0, 0.5),
                           "damping of each part's free joint, N s/m and N m s/rad"),
    "light_count": Factor("range", (1, 4), "number of lights switched on", high=MAX_LIGHTS,
                          why="the scene has that many lights", whole=True),
    "light_position": Factor("amount", 0.5,
                             "largest shift of each light's position and direction, m"),
    "light_color": Factor("amount", 0.3,
                          "largest saturation of each light's random hue (0: white)"),
    "light_intensity": Factor("range", (0.6, 1.4), "multiplier of each light's brightness"),
    "floor": Factor("switch", True,
                    "floor pattern among 4 procedural ones in the scene's colours, random tint"),
    "background": Factor("switch", True,
                         "backdrop walls, pattern among 4 in the scene's colours, random tint"),
    "part_color": Factor("switch", True, "a random colour for each part"),
    "part_material": Factor("switch", True,
                            "random specular, shininess and reflectance of each part"),
    "camera_jitter": Factor("amount", 0.05,
                            "largest shift of each arena camera and its look-at point, m"),
}
PHYSICS_FACTORS = ("gravity", "friction", "part_mass", "part_damping")
RANDOMIZATION_GROUPS = {
    "physics": PHYSICS_FACTORS,
    "visual": tuple(f for f in RANDOMIZATION_FACTORS if f not in PHYSICS_FACTORS),
    "all": tuple(RANDOMIZATION_FACTORS)}


def randomization_factors(randomize) -> dict:
  """{factor: value} from the `randomize` option.

  Args:
    randomize: None or False (nothing), a factor or group name, a list or tuple of names,
      or a {factor: value} dict whose value None or False switches the factor off and
      True takes its default.
  Returns:
    The factors switched on, with checked values: (low, high) tuples, floats, or True.
  Raises:
    UnknownNameError: a name that is neither a factor nor a group.
    OptionValueError: a value of the wrong kind or out of its bounds.
  """
  valid = list(RANDOMIZATION_FACTORS) + list(RANDOMIZATION_GROUPS)
  if randomize is None or randomize is False:
    return {}
  if isinstance(randomize, str):
    randomize = [randomize]
  if isinstance(randomize, (list, tuple)):
    chosen = {}
    for name in randomize:
      if not isinstance(name, str):
        raise errors.OptionValueError(f"randomize names must be strings, got {name!r}; "
                                      f"valid: {', '.join(valid)}")
      if name not in valid:
        raise errors.UnknownNameError("randomization factor", name, valid)
      chosen.update({f: True for f in RANDOMIZATION_GROUPS.get(name, (name,))})
    randomize = chosen
  if not isinstance(randomize, dict):
    raise errors.OptionValueError(
        f"randomize must be None, a factor or group name, a list of names or a "
        f"{{factor: value}} dict, got {randomize!r}; names: {', '.join(valid)} "
        f"(randomize='all' switches every factor on)")
  factors = {}
  for name, value in randomize.items():
    if not isinstance(name, str) or name not in RANDOMIZATION_FACTORS:
      raise errors.UnknownNameError("randomization factor", name, RANDOMIZATION_FACTORS)
    if value is None or value is False:
      continue
    factor = RANDOMIZATION_FACTORS[name]
    factors[name] = _factor_value(name, factor, factor.default if value is True else value)
  return factors


def _factor_value(name, factor, value):
  label = f"randomization factor {name!r}"
  why = f" ({factor.why})" if factor.why else ""
  if factor.kind == "switch":
    if value is not True:
      raise errors.OptionValueError(f"{label} is on/off: True, False or None, got {value!r}")
    return True
  if factor.kind == "amount":
    if (not check.is_number(value) or not np.isfinite(value)
        or not factor.low <= value <= factor.high):
      raise errors.OptionValueError(f"{label} needs a finite amount >= {factor.low:g}, "
                                    f"got {value!r}")
    return float(value)
  is_value = check.is_integer if factor.whole else check.is_number
  if (not isinstance(value, (list, tuple, np.ndarray)) or len(value) != 2
      or not all(is_value(v) for v in value)):
    kind = "whole numbers" if factor.whole else "numbers"
    raise errors.OptionValueError(f"{label} needs a (low, high) range of {kind}, got {value!r}")
  low, high = value
  if not (np.isfinite(high) and factor.low <= low <= high <= factor.high):
    top = f" <= {factor.high:g}" if np.isfinite(factor.high) else " (finite)"
    raise errors.OptionValueError(
        f"{label} needs {factor.low:g} <= low <= high{top}{why}, got {value!r}")
  return (int(low), int(high)) if factor.whole else (float(low), float(high))


# -- the dataclasses ---------------------------------------------------------------------

def _option(default, meaning: str, unit: str = ""):
  """A dataclass field: an option with its only default and its metadata for the docs."""
  return dataclasses.field(default=default, metadata={"meaning": meaning, "unit": unit})


class _Config:
  """Shared by every config dataclass: construction from load()'s keywords."""

  @classmethod
  def option_names(cls) -> tuple[str, ...]:
    """The option names this config takes, in field order."""
    return tuple(f.name for f in dataclasses.fields(cls))

  @classmethod
  def from_options(cls, **options: typing.Any):
    """The config of `options` (load()'s keywords), defaults for the rest.

    Raises:
      UnknownNameError: an option this config does not take.
    """
    cls._check_names(options)
    return cls(**options)

  @classmethod
  def of(cls, config=None, **options: typing.Any):
    """`config` (an instance of this class; None: the defaults) with `options` replaced.

    Raises:
      UnknownNameError: an option this config does not take.
      OptionValueError: a `config` of another class, or a bad option value.
    """
    if config is None:
      return cls.from_options(**options)
    if not isinstance(config, cls):
      raise errors.OptionValueError(f"config must be a {cls.__name__}, got {config!r}")
    cls._check_names(options)
    return dataclasses.replace(config, **options) if options else config

  @classmethod
  def _check_names(cls, options):
    for name in options:
      if name not in cls.option_names():
        raise errors.UnknownNameError("option", name, cls.option_names())

  def _set(self, name, value):
    object.__setattr__(self, name, value)   # normalising a frozen dataclass's own field


@dataclasses.dataclass(frozen=True)
class TaskConfig(_Config):
  """The assembly task's options: every load() option that is not the robot's."""

  time_limit: float | None = _option(
      None, "episode length; None: 30 s plus 25 s per part", "s")
  control_timestep: float = _option(
      0.05, "time between actions (20 Hz, as the paper's environment), at most 1 s", "s")
  physics_timestep: float = _option(
      physics_settings.TIMESTEP,
      "MuJoCo's time step; control_timestep must be a whole multiple of it, and an arm's "
      "stiffest servo bounds it", "s")
  reward: str = _option(
      "sparse", "'sparse' (connection_reward, completion_bonus) or 'dense' (staged shaping)")
  connection_reward: float = _option(1.0, "sparse reward for each new connection")
  completion_bonus: float = _option(
      10.0, "sparse reward when the last part joins (the episode then ends)")
  distance_threshold: float | None = _option(
      None, "largest distance between two connectors that can connect; None: 0.02 m x scale",
      "m")
  up_threshold: float = _option(
      0.99, "smallest cosine between two connectors' up axes (0.99: about 8 degrees)")
  forward_threshold: float = _option(
      0.99, "smallest cosine between their forward axes at the best allowed twist")
  scale: float | None = _option(
      None, f"furniture size factor, {scaling.MIN_SCALE:g} to {scaling.MAX_SCALE:g}: lengths "
      "x scale, masses x scale^3, inertias x scale^5; None: the robot's work scale, the one "
      f"its expert assembles at: {FULL_SCALE:g} for the Cursor, {ARM_WORK_SCALE:g} for the "
      f"arms (small furniture within reach; scale={FULL_SCALE:g} gives them full size)")
  arena: str = _option(
      "floor", "'floor', or 'work_table' for arms: a 0.75 m table in front of the robot, "
      "which stands on a pedestal as high")
  scene: str = _option("default", "scene preset: sky, floor, walls and lights")
  spread: float | None = _option(
      None, "width of the band parts lie in; None: a 0.9 m ring for the Cursor, an arm's "
      "whole reach band", "m")
  preassembled: int | tuple[int, int] = _option(
      0, "connections made before the episode: a count, or an inclusive (low, high) range "
      "drawn each episode")
  yaw_range: float = _option(np.pi, "largest |yaw| of a part about its resting pose", "rad")
  randomize: typing.Any = _option(
      None, "domain randomization: None, a factor or group name (physics, visual, all), "
      "names, or a {factor: value} dict")
  cameras: tuple[str, ...] = _option(
      (), "cameras rendered as observations: the arena's front (framed on the work area), top, "
      "side; an arm's wrist")
  camera_outputs: tuple[str, ...] = _option(
      ("rgb",), "what each camera gives: rgb, depth, segmentation, part_boxes")
  image_size: int | tuple[int, int] = _option(
      84, "camera image size: one side, or (height, width)", "px")
  goal_image: bool = _option(False, "also give each camera's image of the assembled furniture")

  def __post_init__(self):
    if self.time_limit is not None:
      self._set("time_limit", check.positive("time_limit", self.time_limit))
    control = check.positive("control_timestep", self.control_timestep, MAX_CONTROL_TIMESTEP)
    physics = check.positive("physics_timestep", self.physics_timestep)
    substeps = control / physics
    if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
      raise errors.OptionValueError(
          f"control_timestep ({control!r}) must be a whole multiple of physics_timestep "
          f"({physics!r})")
    self._set("control_timestep", control)
    self._set("physics_timestep", physics)
    if not isinstance(self.reward, str) or self.reward not in REWARDS:
      raise errors.UnknownNameError("reward", self.reward, REWARDS)
    for name in ("connection_reward", "completion_bonus"):
      self._set(name, check.number(name, getattr(self, name)))
    if self.distance_threshold is not None:
      self._set("distance_threshold",
                check.positive("distance_threshold", self.distance_threshold))
    for name in ("up_threshold", "forward_threshold"):
      self._set(name, check.number(name, getattr(self, name), -1.0, 1.0, high_open=True))
    if self.scale is not None:
      if not check.is_number(self.scale) or not (
          scaling.MIN_SCALE <= self.scale <= scaling.MAX_SCALE):
        raise errors.OptionValueError(
            f"scale must be a number from {scaling.MIN_SCALE} to {scaling.MAX_SCALE} "
            f"(1 = full size) or None (the robot's work scale), got {self.scale!r}")
      self._set("scale", float(self.scale))
    check.choice("arena", self.arena, presets.ARENAS)
    if not isinstance(self.scene, str) or self.scene not in presets.PRESETS:
      raise errors.UnknownNameError("scene", self.scene, presets.PRESETS)
    if self.spread is not None:
      self._set("spread", _placement_number("spread", self.spread))
    self._set("yaw_range", _placement_number("yaw_range", self.yaw_range))
    self._set("preassembled", preassembled_range(self.preassembled))
    self._set("randomize", randomization_factors(self.randomize))
    cameras = check.names("cameras", self.cameras)
    outputs = check.names("camera_outputs", self.camera_outputs)
    for kind in outputs:
      if kind not in CAMERA_OUTPUTS:
        raise errors.UnknownNameError("camera output", kind, CAMERA_OUTPUTS)
    if cameras and not outputs:
      raise errors.OptionValueError(f"cameras {cameras!r} need camera_outputs, got none")
    self._set("cameras", cameras)
    self._set("camera_outputs", outputs)
    self._set("image_size", image_shape("image_size", self.image_size))
    self._set("goal_image", check.boolean("goal_image", self.goal_image))

  def furniture_scale(self, robot_config: "RobotConfig") -> float:
    """The scale the furniture is built at: `scale`, or the robot's WORK_SCALE where None.

    Args:
      robot_config: the robot's config (its class's WORK_SCALE is the default).
    Returns:
      The load(scale=...) factor.
    """
    return type(robot_config).WORK_SCALE if self.scale is None else self.scale

  def resolved(self, num_parts: int, scattered: bool, scale: float) -> "TaskConfig":
    """This config with the defaults that depend on the furniture and the robot filled in.

    Args:
      num_parts: the furniture's part count (the time limit grows with it).
      scattered: whether the parts are scattered around the furniture (a robot that reaches
        everywhere, the Cursor) rather than laid within an arm's reach.
      scale: the scale the furniture is built at (furniture_scale()).
    Returns:
      A TaskConfig whose scale, time_limit and distance_threshold are numbers, and whose
      spread is one for scattered parts (None for an arm: its whole reach band).
    Raises:
      OptionValueError: a `scale` that is not the one the furniture is built at.
    """
    if self.scale is not None and abs(self.scale - scale) > 1e-12:
      raise errors.OptionValueError(
          f"scale {self.scale!r} differs from the furniture's, which is built at {scale!r}")
    spread = SCATTER_SPREAD if self.spread is None and scattered else self.spread
    return dataclasses.replace(
        self,
        scale=float(scale),
        time_limit=(default_time_limit(num_parts) if self.time_limit is None
                    else self.time_limit),
        distance_threshold=(DISTANCE_THRESHOLD * scale if self.distance_threshold is None
                            else self.distance_threshold),
        spread=spread)

  @property
  def substeps(self) -> int:
    """Physics steps per control step."""
    return int(round(self.control_timestep / self.physics_timestep))

  @property
  def max_steps(self) -> int:
    """Control steps in an episode that reaches the time limit (of a resolved config)."""
    # dm_control ends the episode at the first step whose time reaches the limit.
    return int(np.ceil(self.time_limit / self.control_timestep - 1e-9))


def default_time_limit(num_parts: int) -> float:
  """The default time_limit (s) of a furniture with `num_parts` parts."""
  return TIME_LIMIT_BASE + TIME_LIMIT_PER_PART * num_parts


def _placement_number(name, value):
  if not check.is_number(value) or not 0 <= value < np.inf:
    raise errors.OptionValueError(f"{name} must be a number >= 0, got {value!r}")
  return float(value)


def preassembled_range(preassembled) -> tuple[int, int]:
  """(low, high) connection counts from a count or an inclusive pair; raises otherwise."""
  pair = (preassembled, preassembled) if check.is_integer(preassembled) else preassembled
  if (not isinstance(pair, (list, tuple)) or len(pair) != 2
      or not all(check.is_integer(v) for v in pair) or not 0 <= pair[0] <= pair[1]):
    raise errors.OptionValueError(
        f"preassembled must be a count >= 0 or a (low, high) range of counts, "
        f"got {preassembled!r}")
  return int(pair[0]), int(pair[1])


def image_shape(name: str, size, square: bool = True) -> tuple[int, int]:
  """(height, width) from a pair of whole numbers in 1..MAX_IMAGE_SIZE, or from one side
  where `square` allows it; OptionValueError otherwise."""
  pair = (size, size) if square and check.is_integer(size) else size
  if (not isinstance(pair, (list, tuple)) or len(pair) != 2
      or not all(check.is_integer(s) and 1 <= s <= MAX_IMAGE_SIZE for s in pair)):
    raise errors.OptionValueError(
        f"{name} must be {'an int or ' if square else ''}(height, width) of ints in "
        f"1..{MAX_IMAGE_SIZE}, got {size!r}")
  return int(pair[0]), int(pair[1])


@dataclasses.dataclass(frozen=True)
class RobotConfig(_Config):
  """Base of the robots' option dataclasses."""

  # The furniture scale the robot loads at when load() gets none (TaskConfig.scale).
  WORK_SCALE: typing.ClassVar[float] = FULL_SCALE


@dataclasses.dataclass(frozen=True)
class CursorConfig(RobotConfig):
  """The Cursor's options (robots/cursor.py)."""

  move_speed: float = _option(0.5, "cursor speed at a move action of 1", "m/s")
  rotate_speed: float = _option(np.pi / 2, "cursor turn rate at a rotate action of 1", "rad/s")
  grasp_margin: float = _option(
      0.02, "how far outside a part's collision box the cursor still grabs it", "m")
  workspace: tuple = _option(
      ((-6.0, -6.0, 0.0), (6.0, 6.0, 3.0)), "(low corner, high corner) the cursors stay in",
      "m")
  radius: float = _option(0.025, "radius of the drawn cursor sphere", "m")

  def __post_init__(self):
    self._set("move_speed", check.positive("move_speed", self.move_speed))
    self._set("rotate_speed", check.positive("rotate_speed", self.rotate_speed))
    self._set("grasp_margin", check.non_negative("grasp_margin", self.grasp_margin))
    self._set("workspace", tuple(map(tuple, check.box("workspace", self.workspace).tolist())))
    self._set("radius", check.positive("radius", self.radius))


_BASE_POS_MEANING = ("world position of the arm's base (z from the floor, or from the work "
                     f"table's top); |x|, |y| <= {BASE_XY_LIMIT:g}, 0 <= z <= "
                     f"{BASE_HEIGHT_LIMIT:g}")


@dataclasses.dataclass(frozen=True)
class ArmConfig(RobotConfig):
  """A fixed-base arm's options (robots/manipulator.py); each arm's subclass sets base_pos."""

  WORK_SCALE: typing.ClassVar[float] = ARM_WORK_SCALE

  control_mode: str = _option(
      "task_space", "how actions drive the arm: " + ", ".join(control_modes.MODES))
  max_translation: float = _option(
      0.025, "tool target move per control step at a move action of 1 (task-space modes)", "m")
  max_rotation: float = _option(
      0.15, "tool target turn per control step at a rotate action of 1", "rad")
  base_pos: tuple = _option((-0.55, 0.0, 0.0), _BASE_POS_MEANING, "m")
  base_yaw: float = _option(0.0, "heading of the base about the vertical", "rad")
  wrist_camera: bool = _option(False, "give the wrist camera's images as observations")
  camera_size: tuple = _option((84, 84), "(height, width) of the wrist camera images", "px")
  impedance_stiffness: tuple | None = _option(
      None, "Cartesian (N/m, N m/rad) spring of control_mode 'impedance'; None: "
      f"{IMPEDANCE_STIFFNESS} there, and no spring in other modes")

  def __post_init__(self):
    mode = control_modes.check(self.control_mode)
    self._set("max_translation", check.positive("max_translation", self.max_translation))
    self._set("max_rotation", check.positive("max_rotation", self.max_rotation))
    base = check.vector("base_pos", self.base_pos, (3,))
    if (np.abs(base[:2]) > BASE_XY_LIMIT).any() or not 0.0 <= base[2] <= BASE_HEIGHT_LIMIT:
      raise errors.OptionValueError(
          f"base_pos must have |x|, |y| <= {BASE_XY_LIMIT:g} m (the arm's parts stay on the "
          f"floor) and z from 0 (standing on the floor or table; below, it is buried in it) "
          f"to {BASE_HEIGHT_LIMIT:g} m (higher, the arms cannot reach down to the parts), "
          f"got {tuple(base.tolist())!r}")
    self._set("base_pos", tuple(base.tolist()))
    self._set("base_yaw", check.number("base_yaw", self.base_yaw))
    self._set("wrist_camera", check.boolean("wrist_camera", self.wrist_camera))
    size = self.camera_size
    if (not isinstance(size, (list, tuple, np.ndarray)) or len(size) != 2 or not all(
        check.is_number(s) and 1 <= s <= MAX_IMAGE_SIZE and s == round(s) for s in size)):
      raise errors.OptionValueError(f"camera_size must be two whole numbers of pixels from 1 "
                                    f"to {MAX_IMAGE_SIZE}, got {size!r}")
    self._set("camera_size", tuple(int(s) for s in size))
    stiffness = self.impedance_stiffness
    if mode != control_modes.IMPEDANCE:
      if stiffness is not None:
        raise errors.OptionValueError(
            f"impedance_stiffness applies to control_mode='impedance' only, got "
            f"control_mode={mode!r}")
      return
    stiffness = check.vector("impedance_stiffness",
                             IMPEDANCE_STIFFNESS if stiffness is None else stiffness, (2,))
    if not (stiffness > 0).all():
      raise errors.OptionValueError(f"impedance_stiffness must be two numbers > 0 "
                                    f"(N/m, N m/rad), got {stiffness.tolist()!r}")
    self._set("impedance_stiffness", tuple(stiffness.tolist()))


@dataclasses.dataclass(frozen=True)
class SawyerConfig(ArmConfig):
  base_pos: tuple = _option((-0.55, 0.0, 0.0), _BASE_POS_MEANING, "m")


@dataclasses.dataclass(frozen=True)
class PandaConfig(ArmConfig):
  base_pos: tuple = _option((-0.5, 0.0, 0.0), _BASE_POS_MEANING, "m")


@dataclasses.dataclass(frozen=True)
class JacoConfig(ArmConfig):
  base_pos: tuple = _option((-0.45, 0.0, 0.0), _BASE_POS_MEANING, "m")


@dataclasses.dataclass(frozen=True)
class BaxterConfig(ArmConfig):
  base_pos: tuple = _option((-0.6, 0.0, 0.06), _BASE_POS_MEANING, "m")


ARM_CONFIGS = {"sawyer": SawyerConfig, "panda": PandaConfig, "jaco": JacoConfig,
               "baxter": BaxterConfig}


@dataclasses.dataclass(frozen=True)
class GymConfig(_Config):
  """The gymnasium adapter's own options (ikea_suite.gym.AssemblyEnv)."""

  render_mode: str | None = _option(None, "None, or 'rgb_array' for render() frames")
  render_camera: str = _option("front", "arena camera render() draws: front, top or side")
  render_size: tuple = _option((240, 320), "(height, width) of render() frames", "px")

  def __post_init__(self):
    if self.render_mode is not None and not (
        isinstance(self.render_mode, str) and self.render_mode == "rgb_array"):
      raise errors.UnknownNameError("render mode", self.render_mode, ("rgb_array",))
    if not isinstance(self.render_camera, str) or self.render_camera not in floor.CAMERAS:
      raise errors.UnknownNameError("camera", self.render_camera, floor.CAMERAS)
    self._set("render_size", image_shape("render_size", self.render_size, square=False))


# -- load()'s own arguments -------------------------------------------------------------

def furniture_argument(furniture):
  """`furniture` if it is a name or a path; OptionValueError otherwise."""
  if not isinstance(furniture, (str, os.PathLike)):
    raise errors.OptionValueError(
        f"furniture must be a catalog name (str; see furniture_names()) or a model file "
        f"path, got {furniture!r}")
  return furniture


def seed_argument(seed):
  """`seed` as an int in [0, MAX_SEED], or None; OptionValueError otherwise."""
  if seed is not None and not (check.is_integer(seed) and 0 <= seed <= MAX_SEED):
    raise errors.OptionValueError(
        f"seed must be None or a whole number from 0 to {MAX_SEED} (2**32 - 1), got {seed!r}")
  return None if seed is None else int(seed)


# -- the docs table ------------------------------------------------------------------------

class OptionRow(typing.NamedTuple):
  """One option for the docs table."""
  scope: str      # "task", "cursor", "arm" or "gym"
  name: str
  default: str    # the default as text; arms that differ are named
  meaning: str    # one line, with the unit


def option_rows() -> list[OptionRow]:
  """Every option of load() and the gymnasium adapter, from the dataclasses' fields.

  Returns:
    Rows in field order: the task's, the Cursor's, the arms' (a default that differs
    between arms is given per arm), the gymnasium adapter's.
  """
  rows = []
  for scope, configs in (("task", {"": TaskConfig}), ("cursor", {"": CursorConfig}),
                         ("arm", ARM_CONFIGS), ("gym", {"": GymConfig})):
    first = next(iter(configs.values()))
    for field in dataclasses.fields(first):
      defaults = {robot: _default_text(next(f for f in dataclasses.fields(cls)
                                            if f.name == field.name))
                  for robot, cls in configs.items()}
      if len(set(defaults.values())) == 1:
        default = next(iter(defaults.values()))
      else:
        default = "; ".join(f"{robot} {text}" for robot, text in defaults.items())
      unit = field.metadata["unit"]
      meaning = field.metadata["meaning"] + (f" [{unit}]" if unit else "")
      rows.append(OptionRow(scope, field.name, default, meaning))
  return rows


def _default_text(field) -> str:
  value = field.default
  if isinstance(value, float):
    return "pi" if value == np.pi else ("pi/2" if value == np.pi / 2 else repr(value))
  return repr(value)
