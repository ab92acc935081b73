"""The batched scripted carry policy on one model of every category (catalog.representatives()).

Each world starts with every part but the last assembled and the last a few
cm and degrees from its place (scripted.last_part_start); cursor 0 carries it
into place and connects (scripted.carry_policy). Prints, per model, the
worlds that completed the assembly, the steps the slowest completed world
took (stopping once all completed), and the wall time (model build and jit
compile included); exits 1 if any model is below --min-success.
tests/test_batch_env.py runs a few categories in CI.

  python scripts/batch_scripted_catalog.py [--worlds 16] [--steps 60] [--seeds 1]
      [--models a b ...]

--seeds N runs N batches (seeds --seed, --seed + 1, ...) of --worlds worlds each: the
batches after the first reuse the compiled functions, so they cost only their steps.
"""

import argparse
import sys
import time

import numpy as np

from ikea_suite.batch import env as env_lib
from ikea_suite.batch import scripted
from ikea_suite.props import catalog


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--worlds", type=int, default=16)
  parser.add_argument("--steps", type=int, default=60)
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--seeds", type=int, default=1, help="batches, one seed each")
  parser.add_argument("--min-success", type=float, default=0.95)
  parser.add_argument("--models", nargs="*", default=None)
  args = parser.parse_args(argv)
  models = args.models or sorted(catalog.representatives(),
                                 key=lambda n: catalog.entries()[n].num_parts)
  print(f"{'model':40s} {'parts':>5s} {'welds':>5s} {'completed':>9s} {'steps':>5s} "
        f"{'wall s':>7s}", flush=True)
  failed = []
  for name in models:
    start = time.time()
    env = env_lib.load(name)
    steps = np.concatenate([scripted.completion_steps(env, args.worlds, args.steps, seed=seed)
                            for seed in range(args.seed, args.seed + args.seeds)])
    done = int((steps > 0).sum())
    rate = done / len(steps)
    print(f"{name:40s} {env.num_parts:5d} {env.batch_model.welds.num_welds:5d} "
          f"{f'{done}/{len(steps)}':>9s} {steps.max():5d} {time.time() - start:7.1f}", flush=True)
    if rate < args.min_success:
      failed.append(name)
  if failed:
    print("below --min-success:", ", ".join(failed))
  return 1 if failed else 0


if __name__ == "__main__":
  sys.exit(main())
