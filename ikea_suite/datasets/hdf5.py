"""The demonstration file: robomimic's HDF5 layout plus subtask labels.

    data                         attrs: env_args (JSON: env_name, type ENV_TYPE, env_kwargs),
                                 total (samples), ikea_suite_version
    data/demo_<i>                attrs: seed, model_name, model_version, robot, num_samples, success
    data/demo_<i>/actions        (N, action dim) float64, as the policy sent them
    data/demo_<i>/rewards        (N,) float64
    data/demo_<i>/dones          (N,) uint8, 1 on the episode's last step
    data/demo_<i>/states         (N, S) float64, flattened MuJoCo state before each action
                                 (mjSTATE_INTEGRATION; data attr state_kind)
    data/demo_<i>/obs/<key>      observation before each action
    data/demo_<i>/next_obs/<key> observation after it
    data/demo_<i>/subtask/phase           (N,) bytes: the expert's phase
    data/demo_<i>/subtask/part            (N,) int64: the part it brings in, -1 none
    data/demo_<i>/subtask/next_pair       (N, 2) int64: planner's [moving, target] part
    data/demo_<i>/subtask/connected_pair  (N, 2) int64: connectors joined by this step, -1 none
    data/demo_<i>/subtask/connections     (N,) int64: connections made after this step
    mask/train, mask/valid       demo names (bytes), a seeded split

Observation keys keep the environment's names with "/" written as "." (HDF5
would read "/" as nested groups): `cameras/front_rgb` -> `obs/cameras.front_rgb`.
"""

import hashlib
import json
from collections.abc import Iterable
from typing import Any

import h5py
import numpy as np

import ikea_suite
from ikea_suite import environment
from ikea_suite.datasets import mj_state
from ikea_suite.datasets import recorder
from ikea_suite.props import catalog

FORMAT_VERSION = 1


def obs_key(name: str) -> str:
  """Environment observation name -> dataset name."""
  return name.replace("/", ".")


def env_name(key: str) -> str:
  """Dataset observation name -> environment observation name."""
  return key.replace(".", "/")


def model_version(furniture: str) -> str:
  """First 12 hex digits of the SHA-256 of the furniture's MJCF file.

  Args:
    furniture: a catalog name or model file path.
  Returns:
    12 lowercase hex digits.
  Raises:
    UnknownNameError, ModelFormatError: as catalog.path_of.
  """
  with open(catalog.path_of(furniture), "rb") as f:
    return hashlib.sha256(f.read()).hexdigest()[:12]


GYM_ID = "ikea_suite/Assembly-v0"

# robomimic's env_args `type` is an int naming the wrapper that rebuilds the environment
# (its EnvType: 1 robosuite, 2 gym, 3 iGibson). ikea_suite's is outside those values, so
# robomimic never takes the file for one of its own; robomimic_env rebuilds it.
ENV_TYPE = 100


def env_args(furniture: str, robot: str, options: dict[str, Any]) -> dict[str, Any]:
  """robomimic's env_args (its env_meta) that rebuild the environment.

  `env_kwargs` are the keyword arguments of `ikea_suite.load` (furniture,
  robot and options) and equally of `gymnasium.make(env_name, **env_kwargs)`;
  `robomimic_env.create_env_from_metadata(env_args)` gives robomimic's
  environment interface over it.

  Args:
    furniture: furniture name.
    robot: robot name.
    options: further load() options (tuples are stored as JSON lists).
  Returns:
    {"env_name": GYM_ID, "type": ENV_TYPE, "env_kwargs": {...}}.
  """
  kwargs = {"furniture": furniture, "robot": robot}
  kwargs.update({k: list(v) if isinstance(v, tuple) else v for k, v in options.items()})
  return {"env_name": GYM_ID, "type": ENV_TYPE, "env_kwargs": kwargs}


def load_env(args: dict[str, Any], **overrides: Any) -> environment.Environment:
  """Builds the environment described by `env_args` (options may be overridden).

  Args:
    args: env_args as written by env_args() or read by read_env_args().
    **overrides: load() options that replace the stored ones.
  Returns:
    The environment from ikea_suite.load.
  Raises:
    UnknownNameError, OptionValueError: as ikea_suite.load.
  """
  kwargs = {k: tuple(v) if isinstance(v, list) else v for k, v in args["env_kwargs"].items()}
  kwargs.update(overrides)
  return ikea_suite.load(**kwargs)


def train_valid_split(names: list[str], valid_fraction: float, seed: int = 0
                      ) -> tuple[list[str], list[str]]:
  """(train, valid) demo names; valid gets round(fraction x demos), at least 1 of 2+ demos.

  Args:
    names: demo names ("demo_<i>").
    valid_fraction: share of demos for validation, in [0, 1].
    seed: seed of the shuffle.
  Returns:
    (train names in the given order, valid names in index order).
  """
  order = np.random.default_rng(seed).permutation(len(names))
  count = int(round(valid_fraction * len(names)))
  if valid_fraction > 0 and len(names) > 1:
    count = max(count, 1)
  valid = sorted((names[i] for i in order[:count]), key=lambda n: int(n.split("_")[1]))
  return [n for n in names if n not in valid], valid


def write_demo(group: h5py.Group, episode: recorder.Episode, args: dict[str, Any],
               action_names: list[str] | None = None, compression: str | None = "gzip") -> None:
  """Writes one `Episode` into an (empty) demo group; actions get a `names` attribute.

  Args:
    group: the empty data/demo_<i> group.
    episode: the recorded episode.
    args: env_args of its environment (furniture and robot are stored as attributes).
    action_names: names of the action entries, or None.
    compression: h5py compression of states and observations, or None.
  """
  kwargs = args["env_kwargs"]
  group.attrs.update({"seed": episode.seed, "model_name": kwargs["furniture"],
                      "model_version": model_version(kwargs["furniture"]),
                      "robot": kwargs["robot"], "num_samples": episode.num_samples,
                      "success": episode.success})
  actions = group.create_dataset("actions", data=episode.actions)
  if action_names:
    actions.attrs["names"] = np.array(action_names, dtype="S")
  group.create_dataset("rewards", data=episode.rewards)
  group.create_dataset("dones", data=episode.dones.astype(np.uint8))
  group.create_dataset("states", data=episode.states, compression=compression)
  for name, frames in (("obs", episode.obs), ("next_obs", episode.next_obs)):
    sub = group.create_group(name)
    for key, values in frames.items():
      sub.create_dataset(obs_key(key), data=values, compression=compression)
  labels = group.create_group("subtask")
  for key, values in episode.subtask.items():
    labels.create_dataset(key, data=values)


def write(path: str, episodes: Iterable[recorder.Episode], args: dict[str, Any],
          valid_fraction: float = 0.1, action_names: list[str] | None = None) -> int:
  """Writes a demonstration file; returns the number of demos.

  Args:
    path: the .hdf5 file to create (overwritten).
    episodes: recorded episodes, stored as demo_0, demo_1, ... in this order.
    args: `env_args(...)` of the environment they come from.
    valid_fraction: share of demos listed in mask/valid (the rest in mask/train).
    action_names: names of the action entries (`env.task.action_names`).
  Returns:
    The number of demos written.
  """
  total, names = 0, []
  with h5py.File(path, "w") as f:
    data = f.create_group("data")
    for i, episode in enumerate(episodes):
      name = f"demo_{i}"
      write_demo(data.create_group(name), episode, args, action_names)
      names.append(name)
      total += episode.num_samples
    data.attrs.update({"env_args": json.dumps(args), "total": total,
                       "ikea_suite_version": package_version(), "format_version": FORMAT_VERSION,
                       "state_kind": mj_state.STATE_KIND_NAME})
    train, valid = train_valid_split(names, valid_fraction)
    f.create_dataset("mask/train", data=np.array(train, dtype="S"))
    f.create_dataset("mask/valid", data=np.array(valid, dtype="S"))
  return len(names)


def read_env_args(f: h5py.File) -> dict[str, Any]:
  """The `env_args` of an open demonstration file.

  Args:
    f: the file, open for reading.
  Returns:
    The dict env_args() made when the file was written.
  """
  return json.loads(f["data"].attrs["env_args"])


def demo_names(f: h5py.File) -> list[str]:
  """Demo group names in index order (demo_0, demo_1, ..., not string order).

  Args:
    f: the file, open for reading.
  Returns:
    The names under data/.
  """
  return sorted(f["data"].keys(), key=lambda n: int(n.split("_")[1]))


def package_version() -> str:
  """The installed ikea_suite's version ("unknown" when it runs from a source tree)."""
  from importlib import metadata
  try:
    return metadata.version("ikea_suite")
  except metadata.PackageNotFoundError:
    return "unknown"
