"""`ikea-suite-collect`: record expert demonstrations into a robomimic-style HDF5 file.

    ikea-suite-collect --furniture table_four_leg_lack --robot cursor --episodes 20 \\
        --out demos.hdf5 --cameras front --image-size 84 --workers 2

Episodes run in `--workers` processes on this machine (one environment per
process, built once), or with `--ray ADDRESS` as Ray tasks on a cluster (the
`ray` extra). Episode i uses seed `--seed + i`; the file lists them in seed
order whatever order they finish in. Only episodes that complete the furniture are
written unless `--keep-failures`; the command prints the success rate either way. The
expert must be measured to assemble the furniture at that scale
(ikea_suite.experts.supported); each robot loads at its work scale unless `--scale`.
"""

import argparse
import multiprocessing
import os
import sys
from collections.abc import Iterator
from typing import Any

import ikea_suite
from ikea_suite import config
from ikea_suite import environment
from ikea_suite import errors
from ikea_suite.datasets import experts
from ikea_suite.datasets import hdf5
from ikea_suite.datasets import progress as progress_lib
from ikea_suite.datasets import recorder

_worker_env = None   # per-process environment and expert, built by _init_worker


def _build(args: dict[str, Any]):
  env = hdf5.load_env(args)
  return env, experts.make(env)


def run_episode(env: environment.Environment, expert: experts.Expert,
                seed: int) -> recorder.Episode:
  """One expert episode of `env` from random state `seed`.

  Args:
    env: the environment.
    expert: its robot's expert (experts.make(env)).
    seed: the environment's random state is seeded with it before reset.
  Returns:
    The recorded episode, with the expert's subtask labels.
  """
  return recorder.record_episode(env, expert, seed, subtask=expert.subtask)


def _init_worker(args: dict[str, Any]) -> None:
  global _worker_env
  _worker_env = _build(args)


def _worker_episode(seed: int) -> recorder.Episode:
  return run_episode(*_worker_env, seed)


def episodes_in_processes(args: dict[str, Any], seeds: list[int], workers: int
                          ) -> Iterator[recorder.Episode]:
  """Yields episodes as they finish, from `workers` processes (in this one if workers == 1).

  Args:
    args: `hdf5.env_args(...)` of the environment each process builds once.
    seeds: one episode per seed.
    workers: processes; 1 runs the episodes in this process.
  Yields:
    Episodes in the order they finish.
  """
  if workers == 1:
    env, expert = _build(args)
    for seed in seeds:
      yield run_episode(env, expert, seed)
    return
  context = multiprocessing.get_context("spawn")   # no forked GL or MuJoCo state
  with context.Pool(workers, initializer=_init_worker, initargs=(args,)) as pool:
    yield from pool.imap_unordered(_worker_episode, seeds)


def episodes_on_ray(args: dict[str, Any], seeds: list[int], address: str, workers: int
                    ) -> Iterator[recorder.Episode]:
  """Yields episodes as they finish from `workers` Ray actors on the cluster at `address`.

  Args:
    args: `hdf5.env_args(...)` of the environment each actor builds once.
    seeds: one episode per seed.
    address: the Ray cluster address ("auto", "ray://host:10001", "local").
    workers: actors (at most one per seed).
  Yields:
    Episodes in the order they finish.
  Raises:
    IkeaSuiteError: ray is not installed.
  """
  try:
    import ray
  except ImportError:
    raise errors.IkeaSuiteError(
        '--ray needs the ray extra: pip install "ikea_suite[ray]"') from None
  ray.init(address=address, ignore_reinit_error=True, log_to_driver=False)

  @ray.remote
  class Collector:
    def __init__(self, env_args):
      self._env, self._expert = _build(env_args)

    def episode(self, seed):
      return run_episode(self._env, self._expert, seed)

  actors = [Collector.remote(args) for _ in range(min(workers, len(seeds)))]
  pending, queue = {}, list(seeds)
  for actor in actors:
    if queue:
      pending[actor.episode.remote(queue.pop(0))] = actor
  while pending:
    done, _ = ray.wait(list(pending), num_returns=1)
    actor = pending.pop(done[0])
    if queue:
      pending[actor.episode.remote(queue.pop(0))] = actor
    yield ray.get(done[0])


def collect(args: dict[str, Any], episodes: int, seed: int = 0, workers: int = 1,
            ray_address: str | None = None, progress: bool = True) -> list[recorder.Episode]:
  """Records `episodes` expert episodes with seeds seed, seed+1, ...; returns them in seed order.

  Args:
    args: `hdf5.env_args(...)` of the environment.
    episodes: how many.
    seed: the first episode's seed.
    workers: processes (or Ray actors) running episodes at once.
    ray_address: a Ray cluster address ("auto", "ray://host:10001", "local"); None for processes.
    progress: show a progress bar on stderr.
  Returns:
    The episodes, sorted by seed.
  Raises:
    IkeaSuiteError: ray_address given without the ray extra installed.
  """
  seeds = list(range(seed, seed + episodes))
  source = (episodes_on_ray(args, seeds, ray_address, workers) if ray_address
            else episodes_in_processes(args, seeds, workers))
  done = list(progress_lib.progress(source, episodes, "collect", "episode", enabled=progress))
  return sorted(done, key=lambda e: e.seed)


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
  """The command line of ikea-suite-collect (sys.argv[1:] when `argv` is None)."""
  parser = argparse.ArgumentParser(description="Record expert demonstrations to HDF5.")
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--robot", default=ikea_suite.DEFAULT_ROBOT)
  parser.add_argument("--episodes", type=int, default=10)
  parser.add_argument("--out", required=True, help="the .hdf5 file to write")
  parser.add_argument("--cameras", nargs="*", default=[], help="camera names, e.g. front")
  parser.add_argument("--image-size", type=int, default=config.TaskConfig.image_size)
  parser.add_argument("--workers", type=int, default=min(os.cpu_count() or 1, 8))
  parser.add_argument("--seed", type=int, default=0, help="seed of the first episode")
  parser.add_argument("--time-limit", type=float, default=None, help="seconds of simulated time")
  parser.add_argument("--reward", default=config.TaskConfig.reward, choices=config.REWARDS)
  parser.add_argument("--scale", type=float, default=None,
                      help="furniture size factor (default: the robot's work scale, 1 for "
                           "the Cursor, 0.5 for the arms)")
  parser.add_argument("--keep-failures", action="store_true",
                      help="also write episodes that did not complete the furniture")
  parser.add_argument("--valid-fraction", type=float, default=0.1)
  parser.add_argument("--ray", default=None, metavar="ADDRESS",
                      help="run episodes on the Ray cluster at ADDRESS (ray extra)")
  return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
  """ikea-suite-collect: records the episodes and writes the file; returns the exit status."""
  a = parse_args(argv)
  options = {"reward": a.reward}
  if a.cameras:
    options.update(cameras=tuple(a.cameras), image_size=a.image_size)
  if a.time_limit is not None:
    options["time_limit"] = a.time_limit
  if a.scale is not None:
    options["scale"] = a.scale
  try:
    if a.episodes < 1 or a.workers < 1:
      raise errors.OptionValueError("--episodes and --workers must be at least 1")
    # Fails fast on a bad name, a robot without an expert or a pair it is not measured
    # to assemble; the file records the scale the robot loaded at, so that replays
    # rebuild this environment whatever the default.
    probe = hdf5.load_env(hdf5.env_args(a.furniture, a.robot, options))
    experts.make(probe)
    options["scale"] = probe.task.config.scale
    action_names = list(probe.task.action_names)
    probe.close()
    args = hdf5.env_args(a.furniture, a.robot, options)
    episodes = collect(args, a.episodes, a.seed, a.workers, a.ray)
  except errors.IkeaSuiteError as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  successes = sum(e.success for e in episodes)
  print(f"{successes}/{len(episodes)} episodes completed the furniture "
        f"(success rate {successes / len(episodes):.0%})")
  kept = episodes if a.keep_failures else [e for e in episodes if e.success]
  if not kept:
    print(f"error: no episode completed {a.furniture}; nothing written to {a.out} "
          f"(--keep-failures writes failed episodes too)", file=sys.stderr)
    return 1
  count = hdf5.write(a.out, kept, args, a.valid_fraction, action_names)
  steps = sum(e.num_samples for e in kept)
  size = os.path.getsize(a.out)
  dropped = len(episodes) - len(kept)
  print(f"wrote {count} demos ({sum(e.success for e in kept)} successful"
        + (f"; {dropped} failed left out, --keep-failures keeps them" if dropped else "")
        + f"), {steps} steps, to {a.out} ({size / 1e6:.2f} MB)")
  return 0


if __name__ == "__main__":
  sys.exit(main())
