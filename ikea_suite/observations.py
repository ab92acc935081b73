"""The observation vocabulary: one key, dtype, bounds, unit and meaning per observation.

Every environment of the suite names its observations from this table: the dm_env
environment (`ikea_suite.load`), the gymnasium adapter and the batched environment's
vector env. A key is `<group>/<name>`, and neither part names a furniture model or a
robot, so a policy keeps its inputs when it moves to other furniture or from the CPU
to the batched environment (shapes still follow the part count):

- `furniture/`: the parts' world poses. Privileged: a real robot does not know them.
- `task/`: assembly progress (the scene graph, used connectors, the suggested pair).
  Also privileged.
- `robot/`: what the robot knows of itself (proprioception), whatever the robot. The
  tool pose is `robot/tcp_positions` / `robot/tcp_quaternions` for every robot (the
  Cursor's tool point is the cursor itself), one row per arm or cursor.
- `cameras/`: images, `<camera>_<output>` (`cameras/front_rgb`, `cameras/wrist_rgb`).

So "what a real robot would know" is `robot/*` plus `cameras/*`.

Bounds are the values' own where they have them (quaternions, flags, part indices,
images); positions and velocities are bounded by `MAX_VALUE`, beyond which MuJoCo
declares the state diverged and the episode ends. So every gymnasium Box is finite.
"""

import dataclasses
import fnmatch
from collections.abc import Mapping
from typing import Any

import numpy as np
from dm_env import specs

from ikea_suite import errors

# MuJoCo's mjMAXVAL: a qpos or qvel entry beyond it is a diverged state (mj_checkPos,
# mj_checkVel warn), which ends the episode.
MAX_VALUE = 1e10

GROUPS = ("furniture", "task", "robot", "cameras")

# Bound placeholders resolved per furniture: the largest part index.
LAST_PART = "last_part"


@dataclasses.dataclass(frozen=True)
class Entry:
  """One observation (or, with a `*` in `key`, a family of camera observations).

  Attributes:
    key: `<group>/<name>`; `*` stands for a camera name.
    dtype: numpy dtype name of the values.
    low, high: bounds of every entry (LAST_PART: the furniture's largest part index).
    unit: unit of the values ("" for a pure number or a flag).
    meaning: one line.
  """
  key: str
  dtype: str
  low: Any
  high: Any
  unit: str
  meaning: str


ENTRIES = (
    Entry("furniture/part_positions", "float64", -MAX_VALUE, MAX_VALUE, "m",
          "world position of each part's body frame, (parts, 3)"),
    Entry("furniture/part_quaternions", "float64", -1.0, 1.0, "",
          "world orientation of each part, w x y z, (parts, 4)"),
    Entry("task/connections", "float64", 0.0, 1.0, "",
          "scene graph: 1 where two parts are connected directly, (parts, parts)"),
    Entry("task/connectors_used", "float64", 0.0, 1.0, "",
          "1 for each connector already in a connection, (connectors,)"),
    Entry("task/next_pair", "float64", -1.0, LAST_PART, "part index",
          "suggested [moving part, target part]; -1 when none is open, (2,)"),
    Entry("robot/tcp_positions", "float64", -MAX_VALUE, MAX_VALUE, "m",
          "world position of each tool centre point (arm) or cursor, (tools, 3)"),
    Entry("robot/tcp_quaternions", "float64", -1.0, 1.0, "",
          "world orientation of each tool, w x y z, (tools, 4)"),
    Entry("robot/held_parts", "float64", -1.0, LAST_PART, "part index",
          "part each cursor holds, -1 for none (Cursor), (2,)"),
    Entry("robot/joint_positions", "float64", -MAX_VALUE, MAX_VALUE, "rad or m",
          "arm joint positions, every arm in order (arms), (joints,)"),
    Entry("robot/joint_velocities", "float64", -MAX_VALUE, MAX_VALUE, "rad/s or m/s",
          "arm joint velocities (arms), (joints,)"),
    Entry("robot/gripper_opening", "float64", 0.0, 1.0, "",
          "each gripper's opening, 1 open .. 0 closed (arms), (arms,)"),
    Entry("cameras/*_rgb", "uint8", 0, 255, "",
          "colour image of camera *, (height, width, 3)"),
    Entry("cameras/*_depth", "float32", 0.0, MAX_VALUE, "m",
          "distance along the view axis from camera *, (height, width)"),
    Entry("cameras/*_segmentation", "int32", None, None, "label",
          "part index per pixel (negative: robot, static scene, background), (height, width)"),
    Entry("cameras/*_part_boxes", "float64", -1.0, None, "px",
          "each part's image box [x_min, y_min, x_max, y_max], -1 when unseen, (parts, 4)"),
)

_EXACT = {e.key: e for e in ENTRIES if "*" not in e.key}
_PATTERNS = [e for e in ENTRIES if "*" in e.key]


def key(group: str, name: str) -> str:
  """The vocabulary key of observation `name` in `group` (one of GROUPS).

  Args:
    group: "furniture", "task", "robot" or "cameras".
    name: the observation's name within its group.

  Returns:
    `<group>/<name>`.

  Raises:
    UnknownNameError: an unknown group.
  """
  if group not in GROUPS:
    raise errors.UnknownNameError("observation group", group, GROUPS)
  return f"{group}/{name}"


def entry(name: str) -> Entry:
  """The vocabulary entry of observation key `name` (camera keys by their pattern).

  Args:
    name: an observation key, e.g. "furniture/part_positions" or "cameras/front_rgb".

  Returns:
    Its Entry.

  Raises:
    UnknownNameError: a key outside the vocabulary.
  """
  if name in _EXACT:
    return _EXACT[name]
  # Goal images are the same outputs of the goal pose: `cameras/front_goal_rgb`.
  for candidate in _PATTERNS:
    if fnmatch.fnmatchcase(name, candidate.key):
      return candidate
  raise errors.UnknownNameError("observation key", name, [e.key for e in ENTRIES])


def _bound(value, default, num_parts):
  if value is None:
    return default
  if value == LAST_PART:
    return float(num_parts - 1)
  return value


def spec(name: str, shape: tuple[int, ...], num_parts: int,
         declared: specs.Array | None = None) -> specs.BoundedArray:
  """The bounded dm_env spec of observation `name` with `shape`.

  Args:
    name: an observation key.
    shape: the observation's shape.
    num_parts: parts of the furniture (bounds part indices).
    declared: the spec the observable declares itself, if any: bounds it gives are kept
      where the vocabulary leaves them open (image sizes, segmentation labels).

  Returns:
    A specs.BoundedArray with the vocabulary's dtype and finite bounds.
  """
  e = entry(name)
  dtype = np.dtype(e.dtype)
  declared_low = declared_high = None
  if isinstance(declared, specs.BoundedArray):
    declared_low, declared_high = declared.minimum, declared.maximum
  if np.issubdtype(dtype, np.integer):
    info = np.iinfo(dtype)
    fallback_low, fallback_high = info.min, info.max
  else:
    fallback_low, fallback_high = -MAX_VALUE, MAX_VALUE
  low = _bound(e.low, declared_low if declared_low is not None else fallback_low, num_parts)
  high = _bound(e.high, declared_high if declared_high is not None else fallback_high,
                num_parts)
  low = np.broadcast_to(np.asarray(low, dtype=dtype), shape)
  high = np.broadcast_to(np.asarray(high, dtype=dtype), shape)
  # np.inf in a declared bound (depth) has no place in a finite space.
  if not np.issubdtype(dtype, np.integer):
    low = np.maximum(low, -MAX_VALUE).astype(dtype)
    high = np.minimum(high, MAX_VALUE).astype(dtype)
  return specs.BoundedArray(shape=tuple(shape), dtype=dtype, minimum=low, maximum=high,
                            name=name)


def bounded_specs(observation_spec: Mapping[str, specs.Array],
                  num_parts: int) -> dict[str, specs.BoundedArray]:
  """The environment's observation specs with the vocabulary's dtypes and bounds.

  Args:
    observation_spec: key -> spec as composer infers or the observables declare them.
    num_parts: parts of the furniture.

  Returns:
    key -> specs.BoundedArray, in the same order.

  Raises:
    IkeaSuiteError: a spec whose dtype is not the vocabulary's (a bug in an observable).
  """
  out = {}
  for name, s in observation_spec.items():
    bounded = spec(name, s.shape, num_parts, declared=s)
    if np.dtype(s.dtype) != bounded.dtype:
      raise errors.IkeaSuiteError(
          f"observation {name!r} has dtype {np.dtype(s.dtype)}, the vocabulary says "
          f"{bounded.dtype}")
    out[name] = bounded
  return out


def vocabulary_rows(robot: str = "cursor", furniture: str | None = None,
                    **options: Any) -> list[tuple[str, str, str, str, str]]:
  """The observation table of one robot, read off a built environment: for the docs.

  Args:
    robot: robot name (`ikea_suite.robot_names()`).
    furniture: furniture model name; None: the suite's default.
    **options: load() options (cameras=("front",) adds the camera rows).

  Returns:
    [(key, shape, dtype, unit, meaning)], in the environment's order; shapes as the
    environment gives them for this furniture.
  """
  # Read from a loaded environment so the table cannot drift from what load() returns;
  # load() sits above this module, hence the late import.
  import ikea_suite   # pylint: disable=import-outside-toplevel
  env = ikea_suite.load(furniture or ikea_suite.DEFAULT_FURNITURE, robot, **options)
  try:
    rows = []
    for name, s in env.observation_spec().items():
      e = entry(name)
      meaning = e.meaning
      if "*" in e.key:   # name the camera the row is about
        head, tail = e.key.split("*")
        meaning = meaning.replace("*", name[len(head):len(name) - len(tail)])
      rows.append((name, str(tuple(s.shape)), str(np.dtype(s.dtype)), e.unit, meaning))
    return rows
  finally:
    env.close()
