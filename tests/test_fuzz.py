"""Property-based fuzz of load() and step(): only IkeaSuiteErrors escape, and whatever is
accepted gives finite observations.

Actions are fuzzed on environments loaded once (the Cursor, and every arm in every control
mode, plus a Cursor whose episodes last two steps and which the test never resets, so that
actions also reach a fresh environment and one whose episode has ended); load() options are
fuzzed with a reset and two steps each, since a load takes 0.3-1 s. The number of examples
comes from the settings profile (tests/conftest.py): in CI 200 action sequences and 33 sets
of load() arguments besides the explicit examples; `--hypothesis-profile=long` for a long
local search (4,000 and 666).
"""

import functools
import math

import numpy as np
import pytest
from hypothesis import example
from hypothesis import given
from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import ikea_suite
from ikea_suite.robots import control_modes

ARMS = ("sawyer", "panda", "jaco", "baxter")
SHORT = "short episodes"   # the Cursor's episodes end after two steps: resets between actions
ACTION_ENVS = ([("cursor", None), ("cursor", SHORT)]
               + [(arm, mode) for arm in ARMS for mode in control_modes.MODES])
FURNITURE = "table_four_leg_lack"
ARM_SCALE = 0.5
STEPS_PER_EXAMPLE = 4


@functools.lru_cache(maxsize=None)
def action_env(robot, mode):
  """One environment per (robot, control mode), shared by every example."""
  if mode == SHORT:
    return ikea_suite.load(FURNITURE, robot, seed=0, time_limit=0.1)   # left fresh
  options = {} if mode is None else {"control_mode": mode, "scale": ARM_SCALE}
  env = ikea_suite.load(FURNITURE, robot, seed=0, **options)
  env.reset()
  return env


def _finite(timestep):
  values = [np.asarray(v) for v in timestep.observation.values()]
  reward = 0.0 if timestep.reward is None else timestep.reward
  return all(np.isfinite(v).all() for v in values if v.dtype.kind in "fiuc") and math.isfinite(reward)


def _accepted(action, shape):
  """Whether check_action takes `action`: a real float or integer array (or a flat list of
  Python ints and floats) of `shape`, every entry finite."""
  if isinstance(action, np.ndarray):
    array = action
  elif isinstance(action, list) and all(type(v) in (int, float) for v in action):
    array = np.asarray(action)
  else:
    return False
  if array.dtype.kind not in "fiu" or array.shape != shape:
    return False
  with np.errstate(over="ignore"):
    return bool(np.isfinite(array.astype(np.float64)).all())


def action_strategy(shape):
  """Actions of every kind a user might send, right and wrong."""
  size = int(np.prod(shape))
  real_dtypes = hnp.floating_dtypes() | hnp.integer_dtypes() | hnp.unsigned_integer_dtypes()
  wrong_shapes = hnp.array_shapes(min_dims=0, max_dims=3, max_side=size + 2).filter(
      lambda s: s != shape)
  return st.one_of(
      hnp.arrays(real_dtypes, shape),                                          # any real values
      hnp.arrays(np.float64, shape, elements=st.floats(-1.5, 1.5)),            # in range
      hnp.arrays(np.float64, wrong_shapes),
      hnp.arrays(hnp.boolean_dtypes() | hnp.complex_number_dtypes()
                 | hnp.unicode_string_dtypes(max_len=4) | hnp.byte_string_dtypes(max_len=4)
                 | hnp.datetime64_dtypes(), shape),
      st.lists(st.floats() | st.integers(-10, 10), min_size=size, max_size=size),
      st.lists(st.floats(-1, 1) | st.booleans() | st.none() | st.text(max_size=3),
               min_size=size, max_size=size),
      st.none() | st.text(max_size=5) | st.floats() | st.dictionaries(st.text(max_size=3),
                                                                      st.floats(), max_size=2),
  )


@st.composite
def env_and_actions(draw):
  robot, mode = draw(st.sampled_from(ACTION_ENVS))
  shape = action_env(robot, mode).action_spec().shape
  return robot, mode, draw(st.lists(action_strategy(shape), min_size=1,
                                    max_size=STEPS_PER_EXAMPLE))


@settings(max_examples=2 * settings.default.max_examples)
@given(env_and_actions())
def test_step_refuses_what_is_not_an_action_and_stays_finite_on_what_is(case):
  robot, mode, actions = case
  env = action_env(robot, mode)
  shape = env.action_spec().shape
  for action in actions:
    if _accepted(action, shape):
      timestep = env.step(action)
      assert _finite(timestep), (robot, mode, action, timestep.observation)
    else:
      with pytest.raises(ikea_suite.ActionError):
        env.step(action)


# load() options: plausible values for each, and values of every wrong kind.
JUNK = (st.none() | st.booleans() | st.integers(-(2 ** 40), 2 ** 40) | st.floats()
        | st.text(max_size=6) | st.lists(st.floats(-2, 2), max_size=4).map(tuple)
        | st.dictionaries(st.text(max_size=6), st.floats(0, 2), max_size=2))
SMALL = st.floats(1e-4, 2.0)
PLAUSIBLE = {
    "time_limit": st.floats(0.05, 200),
    "control_timestep": st.sampled_from([0.01, 0.02, 0.05, 0.1]),
    "physics_timestep": st.sampled_from([0.0005, 0.001, 0.002, 0.005]),
    "connection_reward": st.floats(-10, 10),
    "completion_bonus": st.floats(-10, 100),
    "reward": st.sampled_from(["sparse", "dense"]),
    "distance_threshold": st.floats(1e-4, 0.5),
    "up_threshold": st.floats(-1, 0.999),
    "forward_threshold": st.floats(-1, 0.999),
    "scale": st.floats(0.2, 2.0),
    "scene": st.sampled_from(["default", "studio", "nope"]),
    "arena": st.sampled_from(["floor", "work_table"]),
    "spread": st.floats(0, 3),
    "preassembled": st.integers(0, 5) | st.tuples(st.integers(0, 3), st.integers(0, 5)),
    "yaw_range": st.floats(0, 7),
    "randomize": st.sampled_from(["physics", "visual", "all", ["gravity"], {"friction": (0.5, 1.5)},
                                  {"part_mass": (0.5, 2.0)}, {"gravity": (9.0, 10.0)}]),
    # No camera that renders: a frame costs more than the rest of an example.
    "cameras": st.sampled_from([(), ("nope",)]),
    "camera_outputs": st.sampled_from([("rgb",), ("rgb", "depth"), ("nope",)]),
    "image_size": st.integers(8, 96),
    "goal_image": st.booleans(),
    "move_speed": SMALL, "rotate_speed": SMALL, "grasp_margin": st.floats(0, 0.1),
    "radius": st.floats(0.005, 0.1),
    "workspace": st.just(((-3.0, -3.0, 0.0), (3.0, 3.0, 2.0))),
    "control_mode": st.sampled_from(control_modes.MODES + ("nope",)),
    "max_translation": st.floats(1e-4, 0.1), "max_rotation": st.floats(1e-3, 0.5),
    "base_pos": st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-0.2, 0.5)),
    "base_yaw": st.floats(-7, 7),
    "wrist_camera": st.just(False),
    "camera_size": st.tuples(st.integers(8, 64), st.integers(8, 64)),
    "impedance_stiffness": st.none() | st.floats(10, 2000),
}
CURSOR_OPTIONS = ("move_speed", "rotate_speed", "grasp_margin", "radius", "workspace")
ARM_OPTIONS = ("control_mode", "max_translation", "max_rotation", "base_pos", "base_yaw",
               "wrist_camera", "camera_size", "impedance_stiffness")


@st.composite
def load_arguments(draw):
  robot = draw(st.sampled_from(("cursor",) + ARMS))
  furniture = draw(st.sampled_from([FURNITURE, "stool_round_frosta"]))
  own = CURSOR_OPTIONS if robot == "cursor" else ARM_OPTIONS
  names = [n for n in PLAUSIBLE if n not in CURSOR_OPTIONS + ARM_OPTIONS] + list(own)
  chosen = draw(st.lists(st.sampled_from(names), unique=True, max_size=3))
  options = {name: draw(PLAUSIBLE[name] | JUNK) for name in chosen}
  if robot != "cursor" and "scale" not in options:
    options["scale"] = ARM_SCALE
  seed = draw(st.none() | st.integers(0, 2 ** 31) | JUNK)
  return furniture, robot, seed, options


# Inputs that load()'s option checks (types and ranges of the options and the seed) must
# refuse with an IkeaSuiteError, each with the exception it raises where unchecked.
OPTION_CHECK_FAILURES = (
    ((FURNITURE, "cursor", 0, {"randomize": True}), "TypeError: 'bool' object is not iterable"),
    ((FURNITURE, "cursor", 0, {"randomize": 5}), "TypeError: 'int' object is not iterable"),
    ((FURNITURE, "cursor", 0, {"image_size": None}), "TypeError: 'NoneType' object is not iterable"),
    ((FURNITURE, "cursor", 0, {"cameras": 5}), "TypeError: 'int' object is not iterable"),
    ((FURNITURE, "cursor", 0, {"preassembled": None}), "TypeError: 'NoneType' object is not iterable"),
    ((FURNITURE, "cursor", "abc", {}), "TypeError: Cannot cast scalar from dtype('<U3') to int64"),
    ((FURNITURE, "cursor", 1.5, {}), "TypeError: Cannot cast scalar from dtype('float64') to int64"),
    ((FURNITURE, "cursor", -1, {}), "ValueError: Seed must be between 0 and 2**32 - 1"),
    ((FURNITURE, "cursor", 2 ** 32, {}), "ValueError: Seed must be between 0 and 2**32 - 1"),
    ((FURNITURE, "cursor", (), {}), "ValueError: Seed must be non-empty"),
    ((FURNITURE, "cursor", 0, {"scene": {}}), "TypeError: unhashable type: 'dict'"),
    ((FURNITURE, "cursor", 0, {"randomize": {"part_mass": (0.0, 0.0)}}),
     "PhysicsError: mjWARN_INERTIA, in reset()"),
    ((FURNITURE, "cursor", 0, {"control_timestep": 192540537678.0}),
     "TypeError: mj_step(): incompatible function arguments (more substeps than an int), in step()"),
)


def _option_check_examples(test):
  for arguments, _ in OPTION_CHECK_FAILURES:
    test = example(arguments)(test)
  return test


@settings(max_examples=max(10, settings.default.max_examples // 3))
@given(load_arguments())
@_option_check_examples
def test_load_raises_only_suite_errors_and_what_loads_steps_finite(arguments):
  furniture, robot, seed, options = arguments
  try:
    env = ikea_suite.load(furniture, robot, seed=seed, **options)
  except ikea_suite.IkeaSuiteError:
    return
  try:
    env.reset()
    zero = np.zeros(env.action_spec().shape)
    for _ in range(2):
      assert _finite(env.step(zero)), arguments
  except ikea_suite.IkeaSuiteError:
    return
  finally:
    env.close()
