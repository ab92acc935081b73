"""Demonstration files read by robomimic's own SequenceDataset, and a rollout through
robomimic's run_rollout in the environment the file's env_args rebuild (the interop extra).

Skips where robomimic is not installed (`pip install -e ".[interop]"`).
"""

import h5py
import numpy as np
import pytest

pytest.importorskip("robomimic", reason="the interop extra (robomimic) is not installed")
torch = pytest.importorskip("torch")

# pylint: disable=wrong-import-position
from robomimic.algo import algo as robomimic_algo  # noqa: E402
from robomimic.envs import env_base  # noqa: E402
from robomimic.utils import dataset as robomimic_dataset  # noqa: E402
from robomimic.utils import env_utils  # noqa: E402
from robomimic.utils import file_utils  # noqa: E402
from robomimic.utils import obs_utils  # noqa: E402
from robomimic.utils import train_utils  # noqa: E402

from ikea_suite.datasets import collect  # noqa: E402
from ikea_suite.datasets import hdf5  # noqa: E402
from ikea_suite.datasets import robomimic_env  # noqa: E402

STEPS = 30   # per demo: a 1.5 s time limit at 20 control steps per second
RGB = "cameras.front_rgb"


@pytest.fixture(scope="module")
def demo_file(tmp_path_factory, gl):
  """Two short oracle demos with 16-pixel front images."""
  path = str(tmp_path_factory.mktemp("robomimic") / "demos.hdf5")
  assert collect.main(["--episodes", "2", "--out", path, "--cameras", "front", "--image-size",
                       "16", "--workers", "1", "--time-limit", "1.5", "--seed", "5",
                       "--keep-failures"]) == 0
  return path


@pytest.fixture(scope="module")
def low_dim_keys(demo_file):
  with h5py.File(demo_file, "r") as f:
    keys = [k for k in f["data/demo_0/obs"] if not k.startswith("cameras.")]
  obs_utils.initialize_obs_utils_with_obs_specs({"obs": {"low_dim": keys, "rgb": [RGB]}})
  return keys


def same(got, stored):
  """Equal in the dtype robomimic hands out (it casts some arrays to float32)."""
  np.testing.assert_array_equal(got, stored.astype(got.dtype))


def test_sequence_dataset_reads_the_file(demo_file, low_dim_keys):
  dataset = robomimic_dataset.SequenceDataset(
      hdf5_path=demo_file, obs_keys=low_dim_keys + [RGB],
      dataset_keys=("actions", "rewards", "dones"), seq_length=10, hdf5_cache_mode="all")
  assert len(dataset) == 2 * STEPS and dataset.n_demos == 2
  with h5py.File(demo_file, "r") as f:
    demo = f["data/demo_1"]
    actions, dones = demo["actions"][()], demo["dones"][()]
    low_dim = {k: demo["obs"][k][()] for k in low_dim_keys}
    images = demo["obs"][RGB][()]
  item = dataset[STEPS + 25]   # demo_1, frame 25: the last 5 of 10 rows repeat frame 29
  same(item["actions"][:5], actions[25:])
  same(item["actions"][5:], np.repeat(actions[-1:], 5, axis=0))
  same(item["dones"][:5], dones[25:])
  for k in low_dim_keys:
    same(item["obs"][k][:5], low_dim[k][25:])
  same(item["obs"][RGB][:5], images[25:])
  # robomimic's rgb processing for training: channels first, in [0, 1].
  processed = obs_utils.process_obs_dict(item["obs"])
  assert processed[RGB].shape == (10, 3, 16, 16)
  np.testing.assert_allclose(processed[RGB][0], images[25].transpose(2, 0, 1) / 255.0,
                             atol=1e-6)
  valid = robomimic_dataset.SequenceDataset(
      hdf5_path=demo_file, obs_keys=low_dim_keys, dataset_keys=("actions",),
      filter_by_attribute="valid", hdf5_cache_mode="low_dim")
  assert valid.n_demos == 1 and len(valid) == STEPS


def test_env_args_rebuild_the_env_for_a_robomimic_rollout(demo_file, low_dim_keys):
  env_meta = file_utils.get_env_metadata_from_dataset(demo_file)
  assert env_utils.get_env_type(env_meta=env_meta) == hdf5.ENV_TYPE
  assert isinstance(env_meta["type"], int)
  env = robomimic_env.create_env_from_metadata(env_meta, use_image_obs=True)
  assert isinstance(env, env_base.EnvBase)
  with h5py.File(demo_file, "r") as f:
    demo = f["data/demo_0"]
    actions, rewards = demo["actions"][()], demo["rewards"][()]
    seed = int(demo.attrs["seed"])
    first_image = demo["obs"][RGB][0]

  class Replay:
    """The demo's actions as a robomimic policy."""
    device = torch.device("cpu")

    def __init__(self):
      self.t = 0
      self.observations = []

    def set_eval(self):
      pass

    def reset(self):
      self.t = 0

    def get_action(self, obs_dict, goal_dict=None):
      self.observations.append(obs_dict)
      self.t += 1
      return torch.as_tensor(actions[self.t - 1])[None]

  replay = Replay()
  env.base_env.random_state.seed(seed)   # the demo's episode
  results = train_utils.run_rollout(robomimic_algo.RolloutPolicy(replay), env, horizon=100)
  assert results["Horizon"] == STEPS and results["Success_Rate"] == 0.0
  assert results["Return"] == pytest.approx(float(rewards.sum()))
  seen = replay.observations[0]
  assert set(seen) == set(low_dim_keys) | {RGB}
  # The policy saw robomimic's processed image of the demo's first frame.
  np.testing.assert_allclose(seen[RGB][0].numpy(), first_image.transpose(2, 0, 1) / 255.0,
                             atol=1e-6)
