"""The batched scripted carry policy on one model of every category (catalog.representatives()).

Each world starts with every part but the last assembled and the last a few
cm and degrees from its place (scripted.last_part_start); cursor 0 carries it
into place and connects (scripted.carry_policy). Prints, per model, the
fraction of worlds that completed the assembly and the wall time; exits 1 if
any model is below --min-success. tests/test_batch_env.py runs the table in CI.

  python scripts/batch_scripted_catalog.py [--worlds 16] [--steps 60] [--models a b ...]
"""

import argparse
import sys
import time

from ikea_suite.batch import env as env_lib
from ikea_suite.batch import scripted
from ikea_suite.props import catalog


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--worlds", type=int, default=16)
  parser.add_argument("--steps", type=int, default=60)
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--min-success", type=float, default=0.95)
  parser.add_argument("--models", nargs="*", default=None)
  args = parser.parse_args(argv)
  models = args.models or sorted(catalog.representatives(),
                                 key=lambda n: catalog.entries()[n].num_parts)
  print(f"{'model':40s} {'parts':>5s} {'welds':>5s} {'success':>8s} {'wall s':>7s}", flush=True)
  failed = []
  for name in models:
    start = time.time()
    env = env_lib.load(name)
    rate = scripted.run(env, args.worlds, args.steps, seed=args.seed)
    print(f"{name:40s} {env.num_parts:5d} {env.batch_model.welds.num_welds:5d} {rate:8.2%} "
          f"{time.time() - start:7.1f}", flush=True)
    if rate < args.min_success:
      failed.append(name)
  if failed:
    print("below --min-success:", ", ".join(failed))
  return 1 if failed else 0


if __name__ == "__main__":
  sys.exit(main())
