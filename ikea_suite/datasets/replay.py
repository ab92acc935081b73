"""`ikea-suite-replay`: replay every demo of a file and report divergence from its states.

    ikea-suite-replay demos.hdf5
    ikea-suite-replay demos.hdf5 --render out.hdf5 --cameras front --image-size 128

Each demo's environment is rebuilt from the file's env_args, reset from the
demo's seed, set to the stored initial state (`states[0]`), and stepped with
the stored actions; after step t the flattened state is compared with
`states[t + 1]`. Divergence is the largest absolute difference of any state
entry; on the same machine and versions it is 0. With `--render` the replay
also renders the chosen cameras and writes a copy of the file whose obs and
next_obs include those images. A progress bar (demos replayed) shows on stderr.
"""

import argparse
import dataclasses
import shutil
import sys

import h5py
import numpy as np

from ikea_suite import config
from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.datasets import hdf5
from ikea_suite.datasets import mj_state
from ikea_suite.datasets import progress as progress_lib


@dataclasses.dataclass
class Replay:
  """Outcome of replaying one demo."""
  name: str
  steps: int
  reset_divergence: float    # reset from the seed vs the stored initial state
  divergence: np.ndarray     # per step t < N-1: max |state after step t - states[t+1]|
  obs: dict[str, list] = dataclasses.field(default_factory=dict)   # re-rendered, if asked

  @property
  def max_divergence(self) -> float:
    """Largest divergence over all steps (0.0 for a replay that matched exactly)."""
    return float(self.divergence.max()) if len(self.divergence) else 0.0

  @property
  def first_divergent_step(self) -> int:
    """First step whose state differs at all, -1 if none."""
    bad = np.flatnonzero(self.divergence > 0)
    return int(bad[0]) if len(bad) else -1


def replay_demo(env: environment.Environment, demo: h5py.Group, name: str, keep_obs: tuple[str, ...] = ()) -> Replay:
  """Replays one demo group in `env` (built from the file's env_args).

  Args:
    env: the environment.
    demo: the demo's HDF5 group.
    name: its name, for the report.
    keep_obs: observation names (environment spelling) to collect per step.

  Returns:
    A `Replay`; `obs[key]` holds N + 1 frames (initial, then after each step).
  """
  actions, states = demo["actions"][()], demo["states"][()]
  env.random_state.seed(int(demo.attrs["seed"]))
  timestep = env.reset()
  reset_divergence = float(np.abs(mj_state.get_state(env.physics) - states[0]).max())
  mj_state.set_state(env.physics, states[0])
  obs = {k: [np.array(timestep.observation[k])] for k in keep_obs}
  divergence = np.zeros(max(len(actions) - 1, 0))
  for t, action in enumerate(actions):
    timestep = env.step(action)
    for k in keep_obs:
      obs[k].append(np.array(timestep.observation[k]))
    if t + 1 < len(states):
      divergence[t] = np.abs(mj_state.get_state(env.physics) - states[t + 1]).max()
  return Replay(name, len(actions), reset_divergence, divergence, obs)


def replay_file(path: str, render_to: str | None = None, cameras: tuple[str, ...] = (),
                image_size: int = 84, progress: bool = True) -> list[Replay]:
  """Replays every demo of `path`; with `render_to`, writes a copy with re-rendered images.

  Args:
    path: a demonstration HDF5 file.
    render_to: path of the copy with rendered images, or None to only replay.
    cameras: camera names to render (with render_to).
    image_size: rendered image side, pixels.
    progress: show a progress bar (demos replayed) on stderr.
  Returns:
    One Replay per demo, in index order.
  Raises:
    OptionValueError: render_to given with no camera.
    OSError: a file that cannot be read or written.
  """
  with h5py.File(path, "r") as f:
    args = hdf5.read_env_args(f)
    overrides = {"cameras": tuple(cameras), "image_size": image_size} if render_to else {}
    env = hdf5.load_env(args, **overrides)
    keep = tuple(k for k in env.observation_spec() if k.startswith("cameras/")) if render_to else ()
    if render_to and not keep:
      raise errors.OptionValueError("--render needs at least one camera (--cameras front)")
    names = hdf5.demo_names(f)
    reports = [replay_demo(env, f["data"][name], name, keep) for name in
               progress_lib.progress(names, len(names), "replay", "demo", enabled=progress)]
    env.close()
  if render_to:
    shutil.copyfile(path, render_to)
    with h5py.File(render_to, "r+") as f:
      for report in reports:
        demo = f["data"][report.name]
        for key, frames in report.obs.items():
          for group, part in (("obs", frames[:-1]), ("next_obs", frames[1:])):
            if hdf5.obs_key(key) in demo[group]:
              del demo[group][hdf5.obs_key(key)]
            demo[group].create_dataset(hdf5.obs_key(key), data=np.stack(part), compression="gzip")
  return reports


def main(argv: list[str] | None = None) -> int:
  """ikea-suite-replay: replays a file and prints divergences; returns the exit status."""
  parser = argparse.ArgumentParser(description="Replay demonstrations and report divergence.")
  parser.add_argument("file")
  parser.add_argument("--render", default=None, metavar="OUT.hdf5",
                      help="write a copy with images re-rendered during the replay")
  parser.add_argument("--cameras", nargs="*", default=["front"])
  parser.add_argument("--image-size", type=int, default=config.TaskConfig.image_size)
  a = parser.parse_args(argv)
  try:
    reports = replay_file(a.file, a.render, tuple(a.cameras), a.image_size)
  except (errors.IkeaSuiteError, OSError) as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  print(f"{'demo':10s} {'steps':>6s} {'reset div':>10s} {'max div':>10s} {'first div step':>15s}")
  for r in reports:
    print(f"{r.name:10s} {r.steps:6d} {r.reset_divergence:10.3g} {r.max_divergence:10.3g} "
          f"{r.first_divergent_step:15d}")
  worst = max((r.max_divergence for r in reports), default=0.0)
  print(f"{len(reports)} demos replayed, largest divergence {worst:.3g}"
        + (f"; images written to {a.render}" if a.render else ""))
  return 0


if __name__ == "__main__":
  sys.exit(main())
