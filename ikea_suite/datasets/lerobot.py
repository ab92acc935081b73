"""`ikea-suite-export-lerobot`: a demonstration file as a LeRobotDataset v3.0 directory.

    ikea-suite-export-lerobot demos.hdf5 out_dir

Written directly with pyarrow and av (no dependency on the lerobot package):

    meta/info.json                        codebase_version v3.0, fps, features, paths, counts
    meta/tasks.parquet                    task_index, task
    meta/episodes/chunk-000/file-000.parquet
                                          per episode: length, data and video locations
    meta/stats.json                       min, max, mean, std of state, action, reward
    data/chunk-000/file-000.parquet       one row per frame: observation.state, action,
                                          next.reward, next.done, timestamp, frame_index,
                                          episode_index, index, task_index
    videos/observation.images.<camera>/chunk-000/file-000.mp4
                                          every episode's frames of that camera, in order

`observation.state` concatenates every non-image observation (sorted by
name, flattened; names in info.json). Each RGB camera observation
(`cameras/<camera>_rgb`) becomes a video; depth and segmentation are not
exported. All episodes go into chunk 0, file 0.
"""

import argparse
import json
import os
import sys
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
DEFAULT_CODEC = "libx264"


def split_obs(demo: h5py.Group) -> tuple[list[str], dict[str, str]]:
  """(state keys, {video feature name: rgb obs key}) of a demo's obs group.

  Args:
    demo: a data/demo_<i> group.
  Returns:
    (sorted non-camera obs keys, {"observation.images.<camera>": rgb obs key}).
  """
  state, videos = [], {}
  for key in sorted(demo["obs"]):
    data = demo["obs"][key]
    if key.startswith("cameras."):
      if data.dtype == np.uint8 and data.ndim == 4:
        camera = key[len("cameras."):].removesuffix("_rgb")
        videos[f"observation.images.{camera}"] = key
      continue
    state.append(key)
  return state, videos


def _state_names(demo: h5py.Group, keys: list[str]) -> list[str]:
  names = []
  for key in keys:
    size = int(np.prod(demo["obs"][key].shape[1:]))
    names += [f"{hdf5.env_name(key)}[{i}]" for i in range(size)]
  return names


def _write_video(path: str, frames: np.ndarray, fps: int, codec: str) -> None:
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


def _stats(values: np.ndarray) -> dict[str, list]:
  values = values.reshape(len(values), -1).astype(np.float64)
  return {"min": values.min(0).tolist(), "max": values.max(0).tolist(),
          "mean": values.mean(0).tolist(), "std": values.std(0).tolist(),
          "count": [len(values)]}


def export(path: str, out_dir: str, codec: str = DEFAULT_CODEC, task: str | None = None
           ) -> dict[str, Any]:
  """Writes the LeRobot v3.0 layout of demonstration file `path` into `out_dir`.

  Args:
    path: an ikea_suite demonstration HDF5 file.
    out_dir: output directory (created; existing files of the layout are overwritten).
    codec: video codec for av ("libx264", "libsvtav1", ...).
    task: the episodes' task string; default "assemble <furniture>".

  Returns:
    The info.json contents.

  Raises:
    IkeaSuiteError: a file with no demos.
    OSError: a file that cannot be read or written.
  """
  with h5py.File(path, "r") as f:
    args = hdf5.read_env_args(f)
    names = hdf5.demo_names(f)
    if not names:
      raise errors.IkeaSuiteError(f"{path} has no demos")
    first = f["data"][names[0]]
    state_keys, video_keys = split_obs(first)
    kwargs = args["env_kwargs"]
    control_timestep = kwargs.get("control_timestep", 0.05)
    fps = int(round(1.0 / control_timestep))
    task = task or f"assemble {kwargs['furniture']}"
    columns = {k: [] for k in ("observation.state", "action", "next.reward", "next.done",
                               "timestamp", "frame_index", "episode_index", "index")}
    episodes, videos, start = [], {k: [] for k in video_keys}, 0
    for e, name in enumerate(names):
      demo = f["data"][name]
      n = int(demo.attrs["num_samples"])
      state = np.concatenate([demo["obs"][k][()].reshape(n, -1) for k in state_keys], axis=1)
      columns["observation.state"].append(state.astype(np.float32))
      columns["action"].append(demo["actions"][()].astype(np.float32))
      columns["next.reward"].append(demo["rewards"][()].astype(np.float32))
      columns["next.done"].append(demo["dones"][()].astype(bool))
      columns["timestamp"].append((np.arange(n) / fps).astype(np.float32))
      columns["frame_index"].append(np.arange(n))
      columns["episode_index"].append(np.full(n, e))
      columns["index"].append(start + np.arange(n))
      row = {"episode_index": e, "tasks": [task], "length": n, "data/chunk_index": 0,
             "data/file_index": 0, "dataset_from_index": start, "dataset_to_index": start + n,
             "meta/episodes/chunk_index": 0, "meta/episodes/file_index": 0}
      frames_before = sum(len(v) for v in videos[next(iter(videos))]) if videos else 0
      for feature, key in video_keys.items():
        videos[feature].append(demo["obs"][key][()])
        row.update({f"videos/{feature}/chunk_index": 0, f"videos/{feature}/file_index": 0,
                    f"videos/{feature}/from_timestamp": frames_before / fps,
                    f"videos/{feature}/to_timestamp": (frames_before + n) / fps})
      episodes.append(row)
      start += n
    state_names = _state_names(first, state_keys)
    action_names = [n.decode() for n in first["actions"].attrs.get("names", [])]
  joined = {k: np.concatenate(v) for k, v in columns.items()}
  total = start
  table = pa.table({
      "observation.state": pa.array(list(joined["observation.state"]),
                                    type=pa.list_(pa.float32())),
      "action": pa.array(list(joined["action"]), type=pa.list_(pa.float32())),
      "next.reward": pa.array(joined["next.reward"], type=pa.float32()),
      "next.done": pa.array(joined["next.done"], type=pa.bool_()),
      "timestamp": pa.array(joined["timestamp"], type=pa.float32()),
      "frame_index": pa.array(joined["frame_index"], type=pa.int64()),
      "episode_index": pa.array(joined["episode_index"], type=pa.int64()),
      "index": pa.array(joined["index"], type=pa.int64()),
      "task_index": pa.array(np.zeros(total, dtype=np.int64), type=pa.int64()),
  })
  data_path = os.path.join(out_dir, DATA_PATH.format(chunk_index=0, file_index=0))
  os.makedirs(os.path.dirname(data_path), exist_ok=True)
  pq.write_table(table, data_path)
  features = {
      "observation.state": {"dtype": "float32", "shape": [len(state_names)], "names": state_names},
      "action": {"dtype": "float32", "shape": [joined["action"].shape[1]],
                 "names": action_names or None},
      "next.reward": {"dtype": "float32", "shape": [1], "names": None},
      "next.done": {"dtype": "bool", "shape": [1], "names": None},
  }
  for feature, frames in videos.items():
    frames = np.concatenate(frames)
    height, width = frames.shape[1:3]
    _write_video(os.path.join(out_dir, VIDEO_PATH.format(video_key=feature, chunk_index=0,
                                                         file_index=0)), frames, fps, codec)
    features[feature] = {
        "dtype": "video", "shape": [height, width, 3], "names": ["height", "width", "channels"],
        "info": {"video.height": height, "video.width": width, "video.codec": codec,
                 "video.pix_fmt": "yuv420p", "video.is_depth_map": False, "video.fps": fps,
                 "video.channels": 3, "has_audio": False}}
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
  pq.write_table(pa.table({"task_index": [0], "task": [task]}),
                 os.path.join(meta, "tasks.parquet"))
  stats = {"observation.state": _stats(joined["observation.state"]),
           "action": _stats(joined["action"]), "next.reward": _stats(joined["next.reward"])}
  with open(os.path.join(meta, "stats.json"), "w") as out:
    json.dump(stats, out)
  return info


def main(argv: list[str] | None = None) -> int:
  """ikea-suite-export-lerobot: exports a file; returns the exit status."""
  parser = argparse.ArgumentParser(description="Export demonstrations as a LeRobot v3.0 dataset.")
  parser.add_argument("file")
  parser.add_argument("out_dir")
  parser.add_argument("--codec", default=DEFAULT_CODEC)
  parser.add_argument("--task", default=None, help='task string (default "assemble <furniture>")')
  a = parser.parse_args(argv)
  try:
    info = export(a.file, a.out_dir, a.codec, a.task)
  except (errors.IkeaSuiteError, OSError) as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  cameras = [k for k, v in info["features"].items() if v["dtype"] == "video"]
  print(f"wrote {info['total_episodes']} episodes, {info['total_frames']} frames, "
        f"videos {cameras or 'none'} to {a.out_dir}")
  return 0


if __name__ == "__main__":
  sys.exit(main())
