"""Runs the scripted Cursor oracle on every catalog model and prints a success table.

    python benchmarks/oracle_sweep.py                                  # all models, seeds 0, 1
    python benchmarks/oracle_sweep.py --seeds 3 --seed-start 1000      # fresh seeds
    python benchmarks/oracle_sweep.py --seeds 3 --seed-start 2000 --randomize physics
    python benchmarks/oracle_sweep.py --per-category --workers 2

Success rates mean something only on seeds the oracle was never tuned on: the
tests use seeds below 100, so report sweeps with a `--seed-start` of 1000 or
more. Columns: model, parts, connections made (mean), successes over the
seeds, mean control steps and wall-clock seconds per episode. Failed episodes
are listed at the end with how they ended. Exits 1 when any episode fails.
"""

import argparse
import concurrent.futures
import os
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402

import ikea_suite  # noqa: E402
from ikea_suite import cli  # noqa: E402
from ikea_suite.experts import cursor_oracle  # noqa: E402
from ikea_suite.props import catalog  # noqa: E402


def run(name, seed, randomize=None):
  """One oracle episode's summary (see ikea_suite.cli.run_episode)."""
  env = ikea_suite.load(name, "cursor", seed=seed, randomize=randomize)
  return cli.run_episode(env, cursor_oracle.CursorOracle(env))


def _run_model(args):
  name, seeds, randomize = args
  return name, [(seed, run(name, seed, randomize)) for seed in seeds]


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("names", nargs="*", help="models (default: the catalog, filtered)")
  parser.add_argument("--seeds", type=int, default=2, help="episodes per model")
  parser.add_argument("--seed-start", type=int, default=0, help="first seed (then consecutive)")
  parser.add_argument("--randomize", default=None,
                      help="randomization factors or group for load(randomize=...), e.g. physics")
  parser.add_argument("--tag", default=None, help="only models with this tag (e.g. a category)")
  parser.add_argument("--per-category", action="store_true", help="one model per category")
  parser.add_argument("--workers", type=int, default=1, help="parallel processes")
  args = parser.parse_args(argv)
  names = args.names or (catalog.representatives() if args.per_category
                         else catalog.names(tag=args.tag))
  seeds = list(range(args.seed_start, args.seed_start + args.seeds))
  print(f"seeds {seeds[0]}..{seeds[-1]}, randomize={args.randomize}, {args.workers} workers")
  header = f"{'model':42s} {'parts':>5s} {'conn':>5s} {'success':>8s} {'steps':>6s} {'seconds':>8s}"
  print(header)
  print("-" * len(header))
  failed, total_start = [], time.perf_counter()
  jobs = [(name, seeds, args.randomize) for name in names]
  with concurrent.futures.ProcessPoolExecutor(args.workers) as pool:
    for name, results in pool.map(_run_model, jobs):
      summaries = [s for _, s in results]
      ok = sum(s["success"] for s in summaries)
      failed += [(name, seed, s) for seed, s in results if not s["success"]]
      print(f"{name:42s} {catalog.entries()[name].num_parts:5d} "
            f"{np.mean([s['connections'] for s in summaries]):5.1f} {ok:>4d}/{len(seeds):<3d} "
            f"{np.mean([s['steps'] for s in summaries]):6.0f} "
            f"{np.mean([s['seconds'] for s in summaries]):8.2f}", flush=True)
  episodes = len(names) * len(seeds)
  print(f"\n{episodes - len(failed)}/{episodes} episodes assembled "
        f"({100 * (episodes - len(failed)) / episodes:.1f}%), {len(names)} models, "
        f"{time.perf_counter() - total_start:.0f} s")
  for name, seed, s in failed:
    print(f"FAILED {name} seed {seed}: {s['connections']}/{s['needed']} connections, ended by "
          f"{s['ended_by']}, {s['blocked_connects']} refused connects")
  return 1 if failed else 0


if __name__ == "__main__":
  sys.exit(main())
