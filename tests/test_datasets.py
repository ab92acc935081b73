"""Demonstrations: collect (robomimic layout), exact replay, LeRobot v3 export read back."""

import json

import av
import h5py
import numpy as np
import pyarrow.parquet as pq
import pytest

import ikea_suite
from ikea_suite.datasets import collect
from ikea_suite.datasets import experts
from ikea_suite.datasets import hdf5
from ikea_suite.datasets import lerobot
from ikea_suite.datasets import mj_state
from ikea_suite.datasets import recorder
from ikea_suite.datasets import replay
from ikea_suite.experts import registry

FURNITURE = "table_four_leg_lack"


@pytest.fixture(scope="module")
def camera_file(tmp_path_factory, gl):
  """Two short oracle episodes with 16-pixel front images, written by the CLI in-process
  (cut at 1.5 s, before the oracle completes the table: kept with --keep-failures)."""
  path = str(tmp_path_factory.mktemp("demos") / "demos.hdf5")
  assert collect.main(["--episodes", "2", "--out", path, "--cameras", "front", "--image-size",
                       "16", "--workers", "1", "--time-limit", "1.5", "--seed", "5",
                       "--keep-failures"]) == 0
  return path


def test_file_has_the_robomimic_layout(camera_file):
  with h5py.File(camera_file, "r") as f:
    args = json.loads(f["data"].attrs["env_args"])
    assert args["env_name"] == "ikea_suite/Assembly-v0"
    assert args["env_kwargs"]["furniture"] == FURNITURE
    assert args["env_kwargs"]["cameras"] == ["front"]
    assert hdf5.demo_names(f) == ["demo_0", "demo_1"]
    assert f["data"].attrs["total"] == 60
    assert sorted(np.concatenate([f["mask/train"][()], f["mask/valid"][()]])) == [b"demo_0",
                                                                                  b"demo_1"]
    assert len(f["mask/valid"]) == 1
    env = hdf5.load_env(args)
    for i, name in enumerate(hdf5.demo_names(f)):
      demo = f["data"][name]
      n = 30
      assert demo.attrs["seed"] == 5 + i
      assert demo.attrs["num_samples"] == n and demo.attrs["model_name"] == FURNITURE
      assert len(demo.attrs["model_version"]) == 12
      assert demo["actions"].shape == (n, 15) and demo["rewards"].shape == (n,)
      assert list(demo["dones"][()]) == [0] * (n - 1) + [1]
      assert demo["states"].shape == (n, mj_state.state_size(env.physics))
      for key, spec in env.observation_spec().items():
        for group in ("obs", "next_obs"):
          assert demo[group][hdf5.obs_key(key)].shape == (n,) + spec.shape
      np.testing.assert_array_equal(demo["obs/cameras.front_rgb"][1:],
                                    demo["next_obs/cameras.front_rgb"][:-1])
      assert demo["obs/cameras.front_rgb"].dtype == np.uint8
      assert set(demo["subtask"]) == {"phase", "part", "next_pair", "connected_pair",
                                      "connections"}
      assert demo["subtask/phase"][0] == b"reach" and demo["subtask/next_pair"].shape == (n, 2)
    env.close()


def test_replay_is_exact(camera_file):
  for report in replay.replay_file(camera_file):
    assert report.steps == 30 and report.reset_divergence == 0.0
    assert report.max_divergence == 0.0 and report.first_divergent_step == -1


def test_replay_detects_a_changed_action_and_rerenders(camera_file, tmp_path):
  changed = str(tmp_path / "changed.hdf5")
  rendered = str(tmp_path / "rendered.hdf5")
  with h5py.File(camera_file, "r") as src, h5py.File(changed, "w") as dst:
    for name in ("data", "mask"):
      src.copy(name, dst)
    row = dst["data/demo_0/actions"][10]
    row[0] = 0.3 if row[0] != 0.3 else -0.3   # cursor 0 moves differently at step 10
    dst["data/demo_0/actions"][10] = row
  reports = replay.replay_file(changed, render_to=rendered, cameras=("front",), image_size=16)
  assert reports[0].first_divergent_step == 10 and reports[1].max_divergence == 0.0
  with h5py.File(camera_file, "r") as original, h5py.File(rendered, "r") as new:
    np.testing.assert_array_equal(new["data/demo_1/obs/cameras.front_rgb"][()],
                                  original["data/demo_1/obs/cameras.front_rgb"][()])


def test_replay_cli_shows_progress_once(camera_file, capsys):
  assert replay.main([camera_file]) == 0
  captured = capsys.readouterr()
  assert captured.err.count("100%") == 1 and "2/2" in captured.err
  assert "2 demos replayed, largest divergence 0" in captured.out


def test_collect_writes_only_complete_episodes_unless_asked(tmp_path, capsys):
  cut = str(tmp_path / "cut.hdf5")
  assert collect.main(["--episodes", "2", "--out", cut, "--workers", "1",
                       "--time-limit", "0.5"]) == 1
  captured = capsys.readouterr()
  assert "0/2 episodes completed the furniture (success rate 0%)" in captured.out
  assert "nothing written" in captured.err and "--keep-failures" in captured.err
  assert captured.err.count("100%") == 1   # the progress bar's last line, once
  assert not (tmp_path / "cut.hdf5").exists()
  full = str(tmp_path / "full.hdf5")
  assert collect.main(["--episodes", "1", "--out", full, "--workers", "1", "--seed", "2"]) == 0
  assert "1/1 episodes completed the furniture (success rate 100%)" in capsys.readouterr().out
  with h5py.File(full, "r") as f:
    assert f["data/demo_0"].attrs["success"]
    # The file names the scale the robot loaded at, whatever the default later becomes.
    assert hdf5.read_env_args(f)["env_kwargs"]["scale"] == 1.0


def test_collect_refuses_a_pair_the_expert_is_not_measured_on(tmp_path, capsys):
  out = str(tmp_path / "jaco.hdf5")
  assert collect.main(["--robot", "jaco", "--episodes", "1", "--out", out]) == 2
  err = capsys.readouterr().err
  assert "the jaco expert is not measured to assemble 'table_four_leg_lack'" in err
  assert "box_open_kuggis" in err


def test_full_oracle_demo_labels_connections_and_replays_them():
  env = ikea_suite.load(FURNITURE, "cursor")
  expert = experts.make(env)
  episode = recorder.record_episode(env, expert, seed=0, subtask=expert.subtask)
  assert episode.success and episode.dones[-1]
  made = episode.subtask["connected_pair"]
  steps = np.flatnonzero(made[:, 0] >= 0)
  assert len(steps) == 4
  # The running count and the per-step pairs are recorded separately; they must agree.
  np.testing.assert_array_equal(episode.subtask["connections"], np.cumsum(made[:, 0] >= 0))
  assert set(episode.subtask["part"][steps]) == {1, 2, 3, 4}
  assert episode.rewards[steps[-1]] == 11.0
  env.close()
  replayed = ikea_suite.load(FURNITURE, "cursor")
  replayed.random_state.seed(0)
  replayed.reset()
  mj_state.set_state(replayed.physics, episode.states[0])
  for action in episode.actions:
    replayed.step(action)
  assert [tuple(map(int, pair)) for pair in made[steps]] == replayed.task.state.connections


def test_lerobot_export_reads_back(camera_file, tmp_path):
  out = tmp_path / "lerobot"
  assert lerobot.main([camera_file, str(out)]) == 0
  info = json.loads((out / "meta/info.json").read_text())
  assert info["codebase_version"] == "v3.0" and info["fps"] == 20
  assert info["total_episodes"] == 2 and info["total_frames"] == 60
  table = pq.read_table(out / "data/chunk-000/file-000.parquet").to_pydict()
  assert table["episode_index"] == [0] * 30 + [1] * 30
  assert table["frame_index"] == list(range(30)) * 2 and table["index"] == list(range(60))
  episodes = pq.read_table(out / "meta/episodes/chunk-000/file-000.parquet").to_pylist()
  assert [(e["dataset_from_index"], e["dataset_to_index"]) for e in episodes] == [(0, 30),
                                                                                 (30, 60)]
  assert info["features"]["action"]["names"][-1] == "connect"
  with h5py.File(camera_file, "r") as f:
    actions = np.concatenate([f[f"data/demo_{i}/actions"][()] for i in range(2)])
    images = np.concatenate([f[f"data/demo_{i}/obs/cameras.front_rgb"][()] for i in range(2)])
  np.testing.assert_allclose(np.array(table["action"]), actions.astype(np.float32))
  assert len(table["observation.state"][0]) == info["features"]["observation.state"]["shape"][0]
  video = out / "videos/observation.images.front/chunk-000/file-000.mp4"
  with av.open(str(video)) as container:
    frames = np.stack([f.to_ndarray(format="rgb24") for f in container.decode(video=0)])
  assert frames.shape == images.shape
  assert np.abs(frames.astype(int) - images).mean() < 20   # lossy video, same pictures
  assert episodes[1]["videos/observation.images.front/from_timestamp"] == 1.5


def test_collect_in_two_processes_matches_in_process(tmp_path):
  args = hdf5.env_args(FURNITURE, "cursor", {"time_limit": 0.5})
  parallel = collect.collect(args, episodes=2, seed=3, workers=2, progress=False)
  serial = collect.collect(args, episodes=2, seed=3, workers=1, progress=False)
  assert [e.seed for e in parallel] == [3, 4]
  for a, b in zip(parallel, serial, strict=True):
    np.testing.assert_array_equal(a.states, b.states)


def test_collect_on_a_local_ray_instance():
  ray = pytest.importorskip("ray", reason="the ray extra is not installed")
  args = hdf5.env_args(FURNITURE, "cursor", {"time_limit": 0.25})
  try:
    episodes = collect.collect(args, episodes=2, seed=0, workers=1, ray_address="local",
                               progress=False)
  finally:
    ray.shutdown()
  assert [e.seed for e in episodes] == [0, 1] and all(e.num_samples == 5 for e in episodes)


def test_every_robot_has_an_expert_and_arms_need_task_space():
  assert set(registry.ROBOTS) == set(ikea_suite.robot_names())
  assert experts.make(ikea_suite.load(FURNITURE, "baxter")).name == "two_arm"
  with pytest.raises(ikea_suite.IkeaSuiteError, match="task_space"):
    experts.make(ikea_suite.load("box_open_kuggis", "jaco", control_mode="joint_position"))
