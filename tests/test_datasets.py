"""Demonstrations: collect (robomimic layout), exact replay, LeRobot v3 export read back,
the robomimic environment adapter."""

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
from ikea_suite.datasets import robomimic_env
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
  assert "observation.environment_state" not in table
  episodes = pq.read_table(out / "meta/episodes/chunk-000/file-000.parquet").to_pylist()
  assert [(e["dataset_from_index"], e["dataset_to_index"]) for e in episodes] == [(0, 30),
                                                                                 (30, 60)]
  assert info["features"]["action"]["names"][-1] == "connect"
  with h5py.File(camera_file, "r") as f:
    actions = np.concatenate([f[f"data/demo_{i}/actions"][()] for i in range(2)])
    images = np.concatenate([f[f"data/demo_{i}/obs/cameras.front_rgb"][()] for i in range(2)])
    robot = sorted(k for k in f["data/demo_0/obs"]
                   if lerobot.key_group(k, "cursor") == "robot")
    state = np.concatenate([np.concatenate([f[f"data/demo_{i}/obs/{k}"][()].reshape(30, -1)
                                            for k in robot], axis=1) for i in range(2)])
  np.testing.assert_allclose(np.array(table["action"]), actions.astype(np.float32))
  # The default state is the robot's own sensors only: no part poses, no progress.
  names = info["features"]["observation.state"]["names"]
  assert robot and len(names) == state.shape[1] == len(table["observation.state"][0])
  assert all(lerobot.key_group(n.split("[")[0], "cursor") == "robot" for n in names)
  np.testing.assert_array_equal(np.array(table["observation.state"]), state.astype(np.float32))
  video = out / "videos/observation.images.front/chunk-000/file-000.mp4"
  with av.open(str(video)) as container:
    frames = np.stack([f.to_ndarray(format="rgb24") for f in container.decode(video=0)])
  assert frames.shape == images.shape
  assert np.abs(frames.astype(int) - images).mean() < 20   # lossy video, same pictures
  assert episodes[1]["videos/observation.images.front/from_timestamp"] == 1.5
  # The codec LeRobot records is the stream's, not the encoder's name.
  assert info["features"]["observation.images.front"]["info"]["video.codec"] == "h264"


def test_lerobot_export_keeps_stats_and_tasks_as_lerobot_writes_them(camera_file, tmp_path):
  out = tmp_path / "lerobot"
  lerobot.export(camera_file, str(out))
  info = json.loads((out / "meta/info.json").read_text())
  stats = json.loads((out / "meta/stats.json").read_text())
  numeric = {k for k, v in info["features"].items() if v["dtype"] != "string"}
  assert set(stats) == numeric
  keys = {"min", "max", "mean", "std", "count", "q01", "q10", "q50", "q90", "q99"}
  for feature, s in stats.items():
    assert set(s) == keys, feature
    assert s["count"] == [60]
    if info["features"][feature]["dtype"] == "video":
      for k in keys - {"count"}:
        assert np.array(s[k]).shape == (3, 1, 1)
        assert 0.0 <= np.min(s[k]) and np.max(s[k]) <= 1.0
    else:
      assert np.array(s["mean"]).shape == tuple(info["features"][feature]["shape"])
  assert stats["frame_index"]["min"] == [0] and stats["frame_index"]["max"] == [29]
  assert stats["index"]["mean"] == pytest.approx([29.5])
  with h5py.File(camera_file, "r") as f:
    images = np.concatenate([f[f"data/demo_{i}/obs/cameras.front_rgb"][()] for i in range(2)])
    actions = np.concatenate([f[f"data/demo_{i}/actions"][()] for i in range(2)])
  np.testing.assert_allclose(np.array(stats["observation.images.front"]["mean"]).ravel(),
                             images.reshape(-1, 3).mean(0) / 255.0, atol=1e-9)
  np.testing.assert_allclose(np.array(stats["observation.images.front"]["std"]).ravel(),
                             images.reshape(-1, 3).std(0) / 255.0, atol=1e-9)
  np.testing.assert_allclose(stats["action"]["std"], actions.astype(np.float32).std(0),
                             atol=1e-6)
  np.testing.assert_allclose(stats["action"]["max"], actions.max(0), atol=1e-6)
  # Per-episode stats sit in the episodes table as stats/<feature>/<stat>.
  episodes = pq.read_table(out / "meta/episodes/chunk-000/file-000.parquet").to_pylist()
  for e, row in enumerate(episodes):
    assert row["stats/episode_index/min"] == [e] and row["stats/action/count"] == [30]
    assert np.array(row["stats/observation.images.front/mean"]).shape == (3, 1, 1)
    assert {f"stats/{feature}/{k}" for feature in numeric for k in keys} <= set(row)
  # tasks.parquet: the task string is the (pandas) index, task_index the one column.
  tasks = pq.read_table(out / "meta/tasks.parquet")
  pandas_meta = json.loads(tasks.schema.metadata[b"pandas"])
  index = pandas_meta["index_columns"]
  assert index == ["__index_level_0__"] and tasks.column("task_index").to_pylist() == [0]
  assert tasks.column(index[0]).to_pylist() == [f"assemble {FURNITURE}"]
  pandas = pytest.importorskip("pandas")
  frame = pandas.read_parquet(out / "meta/tasks.parquet")
  assert list(frame.columns) == ["task_index"]
  assert frame.iloc[0].name == f"assemble {FURNITURE}" and frame.loc[f"assemble {FURNITURE}",
                                                                     "task_index"] == 0


def test_lerobot_state_keys_choose_the_state(camera_file, tmp_path):
  out = tmp_path / "lerobot"
  with h5py.File(camera_file, "r") as f:
    groups = {k: lerobot.key_group(k, "cursor") for k in f["data/demo_0/obs"]}
  assert set(groups.values()) == {"robot", "furniture", "task", "cameras"}
  info = lerobot.export(camera_file, str(out), state_keys=["robot", "furniture"],
                        environment_state_keys=["task"])
  state = info["features"]["observation.state"]["names"]
  assert {lerobot.key_group(n.split("[")[0], "cursor") for n in state} == {"robot",
                                                                          "furniture"}
  environment_state = info["features"]["observation.environment_state"]["names"]
  assert {lerobot.key_group(n.split("[")[0], "cursor") for n in environment_state} == {"task"}
  table = pq.read_table(out / "data/chunk-000/file-000.parquet").to_pydict()
  assert len(table["observation.environment_state"][0]) == len(environment_state)
  single = sorted(k for k, g in groups.items() if g == "robot")[0]
  info = lerobot.export(camera_file, str(out), state_keys=[hdf5.env_name(single)])
  assert {n.split("[")[0] for n in info["features"]["observation.state"]["names"]} == {
      hdf5.env_name(single)}
  everything = lerobot.export(camera_file, str(out), state_keys=["all"])
  assert len(everything["features"]["observation.state"]["names"]) > len(state)
  with pytest.raises(ikea_suite.IkeaSuiteError, match="robot"):
    lerobot.export(camera_file, str(out), state_keys=["robots"])
  with pytest.raises(ikea_suite.IkeaSuiteError):
    lerobot.export(camera_file, str(out), state_keys=["cameras/front_rgb"])
  assert lerobot.main([camera_file, str(out), "--state-keys", "nothing"]) == 2


@pytest.mark.parametrize("encoder, codec", [("libx264", "h264"), ("libsvtav1", "av1")])
def test_video_codec_is_the_streams_not_the_encoders(encoder, codec, tmp_path):
  if encoder not in av.codecs_available:
    pytest.skip(f"this av build has no {encoder}")
  path = str(tmp_path / "video.mp4")
  frames = np.random.default_rng(0).integers(0, 256, (4, 64, 64, 3), dtype=np.uint8)
  lerobot.write_video(path, frames, 20, encoder)
  info = lerobot.video_info(path)
  assert info["video.codec"] == codec and info["video.fps"] == 20
  assert (info["video.height"], info["video.width"], info["video.pix_fmt"]) == (64, 64,
                                                                               "yuv420p")


def test_key_groups_need_no_furniture_name():
  assert lerobot.key_group("robot/joint_positions", "sawyer") == "robot"
  assert lerobot.key_group("sawyer.joint_positions", "sawyer") == "robot"
  assert lerobot.key_group("furniture/part_positions", "sawyer") == "furniture"
  assert lerobot.key_group("any_model_name.part_positions", "sawyer") == "furniture"
  assert lerobot.key_group("task/connections", "sawyer") == "task"
  assert lerobot.key_group("connections", "sawyer") == "task"
  assert lerobot.key_group("cameras.front_rgb", "sawyer") == "cameras"


def test_env_args_rebuild_the_env_through_the_robomimic_adapter(camera_file):
  with h5py.File(camera_file, "r") as f:
    args = hdf5.read_env_args(f)
    demo = f["data/demo_1"]
    actions, states, rewards = demo["actions"][()], demo["states"][()], demo["rewards"][()]
    seed = int(demo.attrs["seed"])
    first = {k: demo["obs"][k][0] for k in demo["obs"]}
    last_next = {k: demo["next_obs"][k][-1] for k in demo["next_obs"]}
  assert isinstance(args["type"], int) and args["type"] not in (1, 2, 3)
  assert json.loads(json.dumps(args)) == args
  env = robomimic_env.create_env_from_metadata(args, use_image_obs=True)
  assert env.serialize() == args and env.type == args["type"]
  assert env.action_dimension == actions.shape[1]
  obs = env.reset_to({"states": states[0], "seed": seed})
  assert set(obs) == set(first)
  for k, v in first.items():
    np.testing.assert_array_equal(obs[k], v, err_msg=k)
  np.testing.assert_array_equal(env.get_state()["states"], states[0])
  for t, action in enumerate(actions):
    obs, reward, done, info = env.step(action)
    assert reward == rewards[t] and done == (t == len(actions) - 1)
    if t + 1 < len(states):
      np.testing.assert_array_equal(env.get_state()["states"], states[t + 1])
  for k, v in last_next.items():
    np.testing.assert_array_equal(obs[k], v, err_msg=k)
  assert info["is_success"] == env.is_success() == {"task": False}
  assert robomimic_env.env_from_env_args(args).action_spec().shape == actions.shape[1:]
  # Without image observations the cameras are off.
  plain = robomimic_env.create_env_from_metadata(args)
  assert not any(k.startswith("cameras.") for k in plain.reset())
  # robomimic's hook for re-rendering a file's states: the cameras and size it asks for.
  rendering = robomimic_env.EnvIkeaSuite.create_for_data_processing(
      camera_names=["top"], camera_height=24, camera_width=24, reward_shaping=True,
      env_name=args["env_name"], **args["env_kwargs"])
  assert rendering.reset()["cameras.top_rgb"].shape == (24, 24, 3)
  assert rendering.serialize()["env_kwargs"]["reward"] == "dense"
  assert rendering.render(height=20, width=30, camera_name="side").shape == (20, 30, 3)


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
