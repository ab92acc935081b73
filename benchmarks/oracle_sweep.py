"""Runs the scripted Cursor oracle on every catalog model and prints a success table.

    MUJOCO_GL=egl python benchmarks/oracle_sweep.py                 # all models, 2 seeds
    MUJOCO_GL=egl python benchmarks/oracle_sweep.py --seeds 3 --tag bed
    MUJOCO_GL=egl python benchmarks/oracle_sweep.py --per-category  # one model per category

Columns: model, parts, connections made (mean), successes over N seeds, mean
control steps and wall-clock seconds per episode. Exits 1 when any episode fails.
"""

import argparse
import os
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np  # noqa: E402

import ikea_suite  # noqa: E402
from ikea_suite import cli  # noqa: E402
from ikea_suite.oracle import cursor_oracle  # noqa: E402
from ikea_suite.props import catalog  # noqa: E402


def run(name, seed):
  """One oracle episode; returns (success, connections, steps, seconds)."""
  env = ikea_suite.load(name, "cursor", seed=seed)
  summary = cli.run_episode(env, cursor_oracle.CursorOracle(env))
  return summary["success"], summary["connections"], summary["steps"], summary["seconds"]


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("names", nargs="*", help="models (default: the catalog, filtered)")
  parser.add_argument("--seeds", type=int, default=2, help="episodes per model (seeds 0..N-1)")
  parser.add_argument("--tag", default=None, help="only models with this tag (e.g. a category)")
  parser.add_argument("--per-category", action="store_true", help="one model per category")
  args = parser.parse_args(argv)
  names = args.names or (catalog.representatives() if args.per_category
                         else catalog.names(tag=args.tag))
  header = f"{'model':42s} {'parts':>5s} {'conn':>5s} {'success':>8s} {'steps':>6s} {'seconds':>8s}"
  print(header)
  print("-" * len(header))
  failures, total_start = 0, time.perf_counter()
  for name in names:
    results = [run(name, seed) for seed in range(args.seeds)]
    ok = sum(r[0] for r in results)
    failures += args.seeds - ok
    parts = catalog.entries()[name].num_parts
    print(f"{name:42s} {parts:5d} {np.mean([r[1] for r in results]):5.1f} "
          f"{ok:>4d}/{args.seeds:<3d} {np.mean([r[2] for r in results]):6.0f} "
          f"{np.mean([r[3] for r in results]):8.2f}", flush=True)
  episodes = len(names) * args.seeds
  print(f"\n{episodes - failures}/{episodes} episodes assembled, {len(names)} models, "
        f"{time.perf_counter() - total_start:.0f} s")
  return 1 if failures else 0


if __name__ == "__main__":
  sys.exit(main())
