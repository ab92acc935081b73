"""`ikea-suite-export-lerobot`: a demonstration file as a LeRobotDataset v3.0 directory.

    ikea-suite-export-lerobot demos.hdf5 out_dir
    ikea-suite-export-lerobot demos.hdf5 out_dir --state-keys robot furniture
    ikea-suite-export-lerobot demos.hdf5 out_dir --environment-state-keys furniture task

Written directly with pyarrow and av, in the layout LeRobot's own writer
produces and its `LeRobotDataset` reads (tests/test_interop_lerobot.py loads
it with the lerobot package):

    meta/info.json                        codebase_version v3.0, fps, features, paths, counts
    meta/tasks.parquet                    pandas frame indexed by the task string, column
                                          task_index (LeRobot reads the task off the index)
    meta/episodes/chunk-000/file-000.parquet
                                          per episode: length, tasks, data and video
                                          locations, and `stats/<feature>/<stat>` columns
    meta/stats.json                       stats of every non-string feature
    data/chunk-000/file-000.parquet       one row per frame: observation.state,
                                          [observation.environment_state,] action,
                                          next.reward, next.done, timestamp, frame_index,
                                          episode_index, index, task_index
    videos/observation.images.<camera>/chunk-000/file-000.mp4
                                          every episode's frames of that camera, in order

Stats are min, max, mean, std, count and the quantiles q01, q10, q50, q90,
q99, per entry of a vector feature; per channel for a camera, in [0, 1] with
shape (3, 1, 1), as LeRobot keeps them. The dataset stats aggregate the
episodes' stats the way LeRobot does (exact mean and std, count-weighted
quantiles).

`observation.state` is what a real robot knows of itself by default (the
`robot` group: joint positions and velocities, tool poses, gripper opening);
`--state-keys` picks groups or single observations (see `key_group`). The
privileged state (part poses, assembly progress) can go into
`observation.environment_state`, LeRobot's name for the scene's state. Each
RGB camera observation (`cameras/<camera>_rgb`) becomes a video; depth and
segmentation are not exported. All episodes go into chunk 0, file 0.
"""

import argparse
import json
import os
import sys
from collections.abc import Sequence
from typing import Any

import av
import h5py
import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from ikea_suite import errors
from ikea_suite.datasets import hdf5

CODEBASE_VERSION = "v3.0"
DATA_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
VIDEO_PATH = "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4"
EPISODES_PATH = "meta/episodes/chunk-000/file-000.parquet"
TASKS_PATH = "meta/tasks.parquet"
DEFAULT_CODEC = "libx264"

# Observation groups (see key_group); cameras are videos, never state.
GROUPS = ("robot", "furniture", "task")
ALL = "all"
DEFAULT_STATE = ("robot",)
DEFAULT_ENVIRONMENT_STATE: tuple[str, ...] = ()

QUANTILES = (0.01, 0.10, 0.50, 0.90, 0.99)
QUANTILE_NAMES = tuple(f"q{int(round(q * 100)):02d}" for q in QUANTILES)


def key_group(key: str, robot: str) -> str:
  """The group of a demonstration file's observation key: robot, furniture, task or cameras.

  This is the one place that reads meaning from key names. A key is
  `<group>/<name>` (written `<group>.<name>` in the file): `cameras/...` are
  images; `robot/...` (or the robot's entity name, `sawyer/joint_positions`)
  are the robot's own sensors; `task/...` and keys without a prefix are
  assembly progress; any other prefix is the furniture's (its part poses),
  whatever the furniture is called.

  Args:
    key: an observation key, file (`robot.joint_positions`) or environment
      (`robot/joint_positions`) spelling.
    robot: the robot's name (env_kwargs["robot"]).
  Returns:
    "robot", "furniture", "task" or "cameras".
  """
  name = hdf5.env_name(key)
  if "/" not in name:
    return "task"
  head = name.split("/", 1)[0]
  if head == "cameras":
    return "cameras"
  if head in ("robot", robot):
    return "robot"
  if head == "task":
    return "task"
  return "furniture"


def _is_rgb(data: h5py.Dataset) -> bool:
  return data.dtype == np.uint8 and data.ndim == 4 and data.shape[-1] == 3


def select_keys(demo: h5py.Group, robot: str, selection: Sequence[str]) -> list[str]:
  """The observation keys (file spelling) that `selection` names, in the file's order.

  Args:
    demo: a data/demo_<i> group.
    robot: the robot's name.
    selection: group names ("robot", "furniture", "task"), "all" (the three groups) or
      observation keys (`robot/joint_positions`, file or environment spelling). Images
      cannot be chosen: they are exported as videos.
  Returns:
    Sorted keys, each once.
  Raises:
    UnknownNameError: a name that is neither a group nor a non-image observation key.
  """
  keys = [k for k in sorted(demo["obs"]) if not _is_rgb(demo["obs"][k])]
  chosen = set()
  for item in selection:
    if item == ALL:
      chosen.update(k for k in keys if key_group(k, robot) in GROUPS)
    elif item in GROUPS:
      chosen.update(k for k in keys if key_group(k, robot) == item)
    elif hdf5.obs_key(item) in keys:
      chosen.add(hdf5.obs_key(item))
    else:
      raise errors.UnknownNameError(
          "state key", item, [ALL, *GROUPS, *(hdf5.env_name(k) for k in keys)])
  return [k for k in keys if k in chosen]


def video_keys(demo: h5py.Group) -> dict[str, str]:
  """{video feature name: rgb obs key} of a demo's obs group.

  Args:
    demo: a data/demo_<i> group.
  Returns:
    {"observation.images.<camera>": "cameras.<camera>_rgb"} for every RGB camera.
  """
  videos = {}
  for key in sorted(demo["obs"]):
    if key_group(key, "") == "cameras" and _is_rgb(demo["obs"][key]):
      camera = hdf5.env_name(key).split("/", 1)[1].removesuffix("_rgb")
      videos[f"observation.images.{camera}"] = key
  return videos


def _names(demo: h5py.Group, keys: list[str]) -> list[str]:
  names = []
  for key in keys:
    size = int(np.prod(demo["obs"][key].shape[1:]))
    names += [f"{hdf5.env_name(key)}[{i}]" for i in range(size)]
  return names


def write_video(path: str, frames: np.ndarray, fps: int, codec: str) -> None:
  """Encodes RGB frames into an .mp4 (yuv420p), one frame per 1/fps seconds.

  Args:
    path: the file to write (its folder is created).
    frames: (frames, height, width, 3) uint8.
    fps: frames per second.
    codec: av encoder name ("libx264", "libsvtav1", ...).
  """
  os.makedirs(os.path.dirname(path), exist_ok=True)
  height, width = frames.shape[1:3]
  with av.open(path, mode="w") as container:
    stream = container.add_stream(codec, rate=fps)
    stream.width, stream.height, stream.pix_fmt = width, height, "yuv420p"
    for frame in frames:
      for packet in stream.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")):
        container.mux(packet)
    for packet in stream.encode():
      container.mux(packet)


def video_info(path: str) -> dict[str, Any]:
  """The `info` of a video feature, read back from the written file as LeRobot records it.

  `video.codec` is the stream's codec ("h264", "av1"), not the encoder that wrote it
  ("libx264", "libsvtav1").

  Args:
    path: an .mp4 file.
  Returns:
    {"video.height", "video.width", "video.codec", "video.pix_fmt", "video.is_depth_map",
     "video.fps", "video.channels", "has_audio"}.
  """
  with av.open(path) as container:
    stream = container.streams.video[0]
    return {"video.height": stream.height, "video.width": stream.width,
            "video.codec": stream.codec_context.codec.canonical_name,
            "video.pix_fmt": stream.pix_fmt, "video.is_depth_map": False,
            "video.fps": int(stream.base_rate), "video.channels": 3,
            "has_audio": bool(container.streams.audio)}


def feature_stats(values: np.ndarray) -> dict[str, np.ndarray]:
  """One episode's stats of a vector feature: per entry, over the frames.

  Args:
    values: (frames,) or (frames, dim) numbers or bools.
  Returns:
    {"min", "max", "mean", "std", q01..q99: (dim,) (a scalar feature: (1,)), "count": (1,)}.
  """
  values = values.reshape(len(values), -1).astype(np.float64)
  stats = {"min": values.min(0), "max": values.max(0), "mean": values.mean(0),
           "std": values.std(0), "count": np.array([len(values)])}
  for name, q in zip(QUANTILE_NAMES, np.quantile(values, QUANTILES, axis=0), strict=True):
    stats[name] = q
  return stats


def image_stats(frames: np.ndarray) -> dict[str, np.ndarray]:
  """One episode's stats of a camera: per channel over all pixels of all frames, in [0, 1].

  Args:
    frames: (frames, height, width, 3) uint8.
  Returns:
    {"min", "max", "mean", "std", q01..q99: (3, 1, 1), "count": (1,) frames}.
  """
  channels = frames.shape[-1]
  # 256 bins per channel hold every uint8 pixel exactly, without a float copy of the video.
  counts = np.stack([np.bincount(frames[..., c].ravel(), minlength=256)
                     for c in range(channels)]).astype(np.float64)
  levels = np.arange(256) / 255.0
  total = counts.sum(1)
  mean = counts @ levels / total
  std = np.sqrt(np.maximum(counts @ levels ** 2 / total - mean ** 2, 0.0))
  seen = counts > 0
  cumulative = np.cumsum(counts, axis=1)
  stats = {"min": np.array([levels[s][0] for s in seen]),
           "max": np.array([levels[s][-1] for s in seen]), "mean": mean, "std": std}
  for name, q in zip(QUANTILE_NAMES, QUANTILES, strict=True):
    stats[name] = np.array([levels[np.searchsorted(cumulative[c], q * total[c])]
                            for c in range(channels)])
  stats = {k: v.reshape(channels, 1, 1) for k, v in stats.items()}
  stats["count"] = np.array([len(frames)])
  return stats


def aggregate_stats(episodes: list[dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
  """The dataset stats of one feature from its episodes' stats.

  Args:
    episodes: per-episode stats of the feature (feature_stats or image_stats).
  Returns:
    The same keys: min of mins, max of maxes, the exact mean and std of all frames,
    count-weighted quantiles.
  """
  counts = np.array([s["count"][0] for s in episodes], dtype=np.float64)
  weights = (counts / counts.sum()).reshape((-1,) + (1,) * episodes[0]["mean"].ndim)
  means = np.stack([s["mean"] for s in episodes])
  mean = (weights * means).sum(0)
  variance = (weights * (np.stack([s["std"] for s in episodes]) ** 2
                         + (means - mean) ** 2)).sum(0)
  out = {"min": np.min([s["min"] for s in episodes], axis=0),
         "max": np.max([s["max"] for s in episodes], axis=0),
         "mean": mean, "std": np.sqrt(variance),
         "count": np.array([int(counts.sum())])}
  for name in QUANTILE_NAMES:
    out[name] = (weights * np.stack([s[name] for s in episodes])).sum(0)
  return out


def _jsonable(stats: dict[str, dict[str, np.ndarray]]) -> dict[str, dict[str, list]]:
  return {feature: {k: v.tolist() for k, v in s.items()} for feature, s in stats.items()}


def write_tasks(path: str, tasks: list[str]) -> None:
  """Writes meta/tasks.parquet as LeRobot's writer does: a pandas frame indexed by task.

  LeRobot builds `pd.DataFrame({"task_index": ...}, index=tasks)` and reads a
  frame's task string as the index label, so the index must round-trip through
  pandas. pyarrow stores a pandas index as the `__index_level_0__` column plus
  the `pandas` schema metadata that tells pandas to make it the index again;
  this writes both without needing pandas.

  Args:
    path: the tasks.parquet path.
    tasks: task strings; task i gets task_index i.
  """
  index = "__index_level_0__"
  pandas_meta = {
      "index_columns": [index],
      "column_indexes": [{"name": None, "field_name": None, "pandas_type": "unicode",
                          "numpy_type": "object", "metadata": {"encoding": "UTF-8"}}],
      "columns": [
          {"name": "task_index", "field_name": "task_index", "pandas_type": "int64",
           "numpy_type": "int64", "metadata": None},
          {"name": None, "field_name": index, "pandas_type": "unicode",
           "numpy_type": "object", "metadata": None}],
      "creator": {"library": "pyarrow", "version": pa.__version__},
      "pandas_version": "2.0.0",
  }
  table = pa.table({"task_index": pa.array(range(len(tasks)), type=pa.int64()),
                    index: pa.array(tasks, type=pa.string())})
  pq.write_table(table.replace_schema_metadata({"pandas": json.dumps(pandas_meta)}), path)


def export(path: str, out_dir: str, codec: str = DEFAULT_CODEC, task: str | None = None,
           state_keys: Sequence[str] = DEFAULT_STATE,
           environment_state_keys: Sequence[str] = DEFAULT_ENVIRONMENT_STATE
           ) -> dict[str, Any]:
  """Writes the LeRobot v3.0 layout of demonstration file `path` into `out_dir`.

  Args:
    path: an ikea_suite demonstration HDF5 file.
    out_dir: output directory (created; existing files of the layout are overwritten).
    codec: video encoder for av ("libx264", "libsvtav1", ...).
    task: the episodes' task string; default "assemble <furniture>".
    state_keys: what goes into observation.state (see select_keys); default the
      robot's own sensors.
    environment_state_keys: what goes into observation.environment_state; default
      nothing (no such feature).

  Returns:
    The info.json contents.

  Raises:
    IkeaSuiteError: a file with no demos, an empty state, an unknown state key.
    OSError: a file that cannot be read or written.
  """
  with h5py.File(path, "r") as f:
    args = hdf5.read_env_args(f)
    names = hdf5.demo_names(f)
    if not names:
      raise errors.IkeaSuiteError(f"{path} has no demos")
    first = f["data"][names[0]]
    kwargs = args["env_kwargs"]
    vectors = {"observation.state": select_keys(first, kwargs["robot"], state_keys)}
    if not vectors["observation.state"]:
      raise errors.IkeaSuiteError(f"--state-keys {' '.join(state_keys)} select no observation")
    if environment_state_keys:
      vectors["observation.environment_state"] = select_keys(first, kwargs["robot"],
                                                             environment_state_keys)
    videos = video_keys(first)
    control_timestep = kwargs.get("control_timestep", 0.05)
    fps = int(round(1.0 / control_timestep))
    task = task or f"assemble {kwargs['furniture']}"
    columns: dict[str, list[np.ndarray]] = {
        k: [] for k in (*vectors, "action", "next.reward", "next.done", "timestamp",
                        "frame_index", "episode_index", "index", "task_index")}
    frames: dict[str, list[np.ndarray]] = {k: [] for k in videos}
    episodes, episode_stats, start = [], [], 0
    for e, name in enumerate(names):
      demo = f["data"][name]
      n = int(demo.attrs["num_samples"])
      episode = {feature: np.concatenate([demo["obs"][k][()].reshape(n, -1) for k in keys],
                                         axis=1).astype(np.float32)
                 for feature, keys in vectors.items()}
      episode.update({
          "action": demo["actions"][()].astype(np.float32),
          "next.reward": demo["rewards"][()].astype(np.float32),
          "next.done": demo["dones"][()].astype(bool),
          "timestamp": (np.arange(n) / fps).astype(np.float32),
          "frame_index": np.arange(n), "episode_index": np.full(n, e),
          "index": start + np.arange(n), "task_index": np.zeros(n, dtype=np.int64)})
      stats = {k: feature_stats(v) for k, v in episode.items()}
      for k, v in episode.items():
        columns[k].append(v)
      row = {"episode_index": e, "tasks": [task], "length": n, "data/chunk_index": 0,
             "data/file_index": 0, "dataset_from_index": start, "dataset_to_index": start + n}
      for feature, key in videos.items():
        images = demo["obs"][key][()]
        before = sum(len(v) for v in frames[feature])
        frames[feature].append(images)
        stats[feature] = image_stats(images)
        row.update({f"videos/{feature}/chunk_index": 0, f"videos/{feature}/file_index": 0,
                    f"videos/{feature}/from_timestamp": before / fps,
                    f"videos/{feature}/to_timestamp": (before + n) / fps})
      row.update({"meta/episodes/chunk_index": 0, "meta/episodes/file_index": 0})
      row.update({f"stats/{feature}/{k}": v.tolist() for feature, s in stats.items()
                  for k, v in s.items()})
      episodes.append(row)
      episode_stats.append(stats)
      start += n
    vector_names = {feature: _names(first, keys) for feature, keys in vectors.items()}
    action_names = [n.decode() for n in first["actions"].attrs.get("names", [])]
  joined = {k: np.concatenate(v) for k, v in columns.items()}
  total = start
  scalars = {"next.reward": pa.float32(), "next.done": pa.bool_(), "timestamp": pa.float32(),
             "frame_index": pa.int64(), "episode_index": pa.int64(), "index": pa.int64(),
             "task_index": pa.int64()}
  table = {k: pa.array(list(joined[k]), type=pa.list_(pa.float32()))
           for k in (*vectors, "action")}
  table.update({k: pa.array(joined[k], type=t) for k, t in scalars.items()})
  data_path = os.path.join(out_dir, DATA_PATH.format(chunk_index=0, file_index=0))
  os.makedirs(os.path.dirname(data_path), exist_ok=True)
  pq.write_table(pa.table(table), data_path)
  features = {feature: {"dtype": "float32", "shape": [len(names_)], "names": names_}
              for feature, names_ in vector_names.items()}
  features["action"] = {"dtype": "float32", "shape": [joined["action"].shape[1]],
                        "names": action_names or None}
  features["next.reward"] = {"dtype": "float32", "shape": [1], "names": None}
  features["next.done"] = {"dtype": "bool", "shape": [1], "names": None}
  for feature, parts in frames.items():
    video_path = os.path.join(out_dir, VIDEO_PATH.format(video_key=feature, chunk_index=0,
                                                         file_index=0))
    write_video(video_path, np.concatenate(parts), fps, codec)
    info = video_info(video_path)
    features[feature] = {
        "dtype": "video", "shape": [info["video.height"], info["video.width"], 3],
        "names": ["height", "width", "channels"], "info": info}
  for name, dtype in (("timestamp", "float32"), ("frame_index", "int64"),
                      ("episode_index", "int64"), ("index", "int64"), ("task_index", "int64")):
    features[name] = {"dtype": dtype, "shape": [1], "names": None}
  info = {
      "codebase_version": CODEBASE_VERSION, "robot_type": kwargs["robot"],
      "total_episodes": len(names), "total_frames": total, "total_tasks": 1,
      "chunks_size": 1000, "data_files_size_in_mb": 100, "video_files_size_in_mb": 500,
      "fps": fps, "splits": {"train": f"0:{len(names)}"},
      "data_path": DATA_PATH, "video_path": VIDEO_PATH if videos else None,
      "features": features,
  }
  meta = os.path.join(out_dir, "meta")
  os.makedirs(os.path.dirname(os.path.join(out_dir, EPISODES_PATH)), exist_ok=True)
  with open(os.path.join(meta, "info.json"), "w") as out:
    json.dump(info, out, indent=2)
  pq.write_table(pa.Table.from_pylist(episodes), os.path.join(out_dir, EPISODES_PATH))
  write_tasks(os.path.join(out_dir, TASKS_PATH), [task])
  stats = {feature: aggregate_stats([s[feature] for s in episode_stats])
           for feature in episode_stats[0]}
  with open(os.path.join(meta, "stats.json"), "w") as out:
    json.dump(_jsonable(stats), out, indent=2)
  return info


def main(argv: list[str] | None = None) -> int:
  """ikea-suite-export-lerobot: exports a file; returns the exit status."""
  parser = argparse.ArgumentParser(description="Export demonstrations as a LeRobot v3.0 dataset.")
  parser.add_argument("file")
  parser.add_argument("out_dir")
  parser.add_argument("--codec", default=DEFAULT_CODEC,
                      help="video encoder (libx264, libsvtav1, ...)")
  parser.add_argument("--task", default=None, help='task string (default "assemble <furniture>")')
  parser.add_argument(
      "--state-keys", nargs="+", default=list(DEFAULT_STATE), metavar="KEY",
      help="observation.state: groups (robot, furniture, task, all) or observation keys "
           "(robot/joint_positions); default robot, what a real robot knows of itself")
  parser.add_argument(
      "--environment-state-keys", nargs="*", default=list(DEFAULT_ENVIRONMENT_STATE),
      metavar="KEY", help="observation.environment_state (privileged scene state), same "
                          "choices; default none")
  a = parser.parse_args(argv)
  try:
    info = export(a.file, a.out_dir, a.codec, a.task, a.state_keys, a.environment_state_keys)
  except (errors.IkeaSuiteError, OSError) as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  cameras = [k for k, v in info["features"].items() if v["dtype"] == "video"]
  state = info["features"]["observation.state"]["shape"][0]
  print(f"wrote {info['total_episodes']} episodes, {info['total_frames']} frames, "
        f"observation.state {state} dims, videos {cameras or 'none'} to {a.out_dir}")
  return 0


if __name__ == "__main__":
  sys.exit(main())
