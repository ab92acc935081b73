"""The LeRobot export read by the lerobot package's own LeRobotDataset (the interop extra).

Skips where lerobot is not installed (`pip install -e ".[interop]"`). Reads
from a local root with the hub offline, so it needs no network.
"""

import gc
import json
import os

import h5py
import numpy as np
import pytest

os.environ.setdefault("HF_HUB_OFFLINE", "1")

lerobot_dataset = pytest.importorskip("lerobot.datasets.lerobot_dataset",
                                      reason="the interop extra (lerobot) is not installed")

from ikea_suite.datasets import collect  # noqa: E402
from ikea_suite.datasets import lerobot  # noqa: E402

FURNITURE = "table_four_leg_lack"
STEPS = 30   # per episode: a 1.5 s time limit at 20 control steps per second


@pytest.fixture(scope="module")
def export(tmp_path_factory, gl):
  """Two short oracle episodes with 32-pixel front images, exported for LeRobot."""
  root = tmp_path_factory.mktemp("interop")
  path = str(root / "demos.hdf5")
  assert collect.main(["--episodes", "2", "--out", path, "--cameras", "front", "--image-size",
                       "32", "--workers", "1", "--time-limit", "1.5", "--seed", "5",
                       "--keep-failures"]) == 0
  # The collect's render contexts are freed here, on this thread, not whenever a
  # collection happens to run on one of the datasets library's threads (EGL refuses that).
  gc.collect()
  out = root / "lerobot"
  assert lerobot.main([path, str(out)]) == 0
  return path, out


def _video_backend():
  # torchcodec needs the system's FFmpeg libraries; PyAV brings its own.
  try:
    import torchcodec.decoders  # noqa: F401  pylint: disable=import-outside-toplevel,unused-import
  except Exception:  # noqa: BLE001 - any failure to load means: decode with PyAV
    return "pyav"
  return "torchcodec"


def test_lerobot_dataset_reads_the_export(export):
  path, out = export
  dataset = lerobot_dataset.LeRobotDataset("ikea_suite/demos", root=out,
                                           video_backend=_video_backend())
  assert len(dataset) == 2 * STEPS and dataset.num_episodes == 2 and dataset.fps == 20
  assert dataset.meta.total_tasks == 1
  assert dataset.meta.get_task_index(f"assemble {FURNITURE}") == 0
  with h5py.File(path, "r") as f:
    demos = [f[f"data/demo_{i}"] for i in range(2)]
    actions = np.concatenate([d["actions"][()] for d in demos]).astype(np.float32)
    rewards = np.concatenate([d["rewards"][()] for d in demos]).astype(np.float32)
    images = np.concatenate([d["obs/cameras.front_rgb"][()] for d in demos])
    robot = [k for k in sorted(demos[0]["obs"]) if lerobot.key_group(k, "cursor") == "robot"]
    state = np.concatenate([np.concatenate([d["obs"][k][()].reshape(STEPS, -1) for k in robot],
                                           axis=1) for d in demos]).astype(np.float32)
  for i in (0, 1, STEPS - 1, STEPS, 2 * STEPS - 1):
    item = dataset[i]
    episode, frame = divmod(i, STEPS)
    assert item["task"] == f"assemble {FURNITURE}"
    assert int(item["episode_index"]) == episode and int(item["frame_index"]) == frame
    assert int(item["index"]) == i
    assert float(item["timestamp"]) == pytest.approx(frame / 20, abs=1e-6)
    np.testing.assert_array_equal(item["action"].numpy(), actions[i])
    np.testing.assert_array_equal(item["observation.state"].numpy(), state[i])
    assert float(item["next.reward"]) == rewards[i]
    assert bool(item["next.done"]) == (frame == STEPS - 1)
    image = item["observation.images.front"]   # channels first, in [0, 1]
    assert tuple(image.shape) == (3, 32, 32)
    decoded = image.permute(1, 2, 0).numpy() * 255.0
    assert np.abs(decoded - images[i]).mean() < 20   # lossy video, the same picture
  # Episode boundaries as LeRobot reads them.
  episodes = dataset.meta.episodes
  assert [(e["dataset_from_index"], e["dataset_to_index"]) for e in episodes] == [
      (0, STEPS), (STEPS, 2 * STEPS)]
  assert [e["tasks"] for e in episodes] == [[f"assemble {FURNITURE}"]] * 2
  # Stats as LeRobot loads them: every non-string feature, images per channel.
  stats = dataset.meta.stats
  assert set(stats) == {k for k, v in dataset.features.items() if v["dtype"] != "string"}
  assert stats["observation.images.front"]["mean"].shape == (3, 1, 1)
  assert stats["action"]["mean"].shape == (actions.shape[1],)


def test_lerobot_delta_timestamps_pad_at_episode_boundaries(export):
  _, out = export
  dataset = lerobot_dataset.LeRobotDataset(
      "ikea_suite/demos", root=out, video_backend=_video_backend(),
      delta_timestamps={"action": [-0.05, 0.0, 0.05]})
  first, last = dataset[STEPS], dataset[STEPS - 1]
  assert first["action_is_pad"].tolist() == [True, False, False]
  assert last["action_is_pad"].tolist() == [False, False, True]


def test_lerobot_reads_the_codec_it_would_record(export):
  _, out = export
  from lerobot.datasets import video_utils  # pylint: disable=import-outside-toplevel
  info = json.loads((out / "meta/info.json").read_text())
  video = out / "videos/observation.images.front/chunk-000/file-000.mp4"
  recorded = video_utils.get_video_info(video)
  ours = info["features"]["observation.images.front"]["info"]
  assert {k: ours[k] for k in recorded} == recorded
