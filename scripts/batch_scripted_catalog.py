"""The batched scripted carry policy on one model of every category (catalog.representatives()).

Each world starts with every part but the last assembled and the last a few
cm and degrees from its place (scripted.last_part_start); cursor 0 carries it
into place and connects (scripted.carry_policy). Prints, per model, the
worlds that completed the assembly, the steps the slowest completed world
took (stopping once all completed), the wall time (model build and jit
compile included), Warp's buffer sizes per world (nconmax, njmax; "-" on MJX's
JAX implementation, which has none) and the world-steps whose contact or
constraint buffers overflowed. Exits 1 if any model is below --min-success or
any buffer overflowed (naming the buffer): an overflow drops contacts, so the
physics of that run is wrong whatever it completed. tests/test_batch_env.py
runs a few categories in CI.

  python scripts/batch_scripted_catalog.py [--worlds 16] [--steps 60] [--seeds 1]
      [--models a b ...] [--impl warp|jax] [--buffer-sizes NCONMAX NJMAX]

--seeds N runs N batches (seeds --seed, --seed + 1, ...) of --worlds worlds each: the
batches after the first reuse the compiled functions, so they cost only their steps.
"""

import argparse
import sys
import time

import numpy as np

from ikea_suite.batch import backend
from ikea_suite.batch import contact_buffers
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
  parser.add_argument("--impl", default=None, choices=backend.IMPLS)
  parser.add_argument("--buffer-sizes", type=int, nargs=2, default=None,
                      metavar=("NCONMAX", "NJMAX"),
                      help="Warp buffers per world instead of the measured sizing")
  args = parser.parse_args(argv)
  models = args.models or sorted(catalog.representatives(),
                                 key=lambda n: catalog.entries()[n].num_parts)
  impl = backend.check_impl(args.impl)
  print(f"MJX impl: {impl}; {args.worlds} worlds", flush=True)
  print(f"{'model':40s} {'parts':>5s} {'welds':>5s} {'completed':>9s} {'steps':>5s} "
        f"{'wall s':>7s} {'nconmax':>7s} {'njmax':>5s} {'overflow':>8s}", flush=True)
  failed, overflowed = [], {}
  for name in models:
    start = time.time()
    env = env_lib.load(name, impl=impl, num_worlds=args.worlds, buffer_sizes=args.buffer_sizes)
    env.overflow_watch.flush()
    before = dict(env.overflow_watch.world_steps)
    steps = np.concatenate([scripted.completion_steps(env, args.worlds, args.steps, seed=seed)
                            for seed in range(args.seed, args.seed + args.seeds)])
    totals = env.overflow_watch.flush()
    new = {k: v - before.get(k, 0) for k, v in totals.items() if v > before.get(k, 0)}
    done = int((steps > 0).sum())
    rate = done / len(steps)
    sizes = (f"{env.buffer_sizing.nconmax:7d} {env.buffer_sizing.njmax:5d}" if impl == "warp"
             else f"{'-':>7s} {'-':>5s}")
    print(f"{name:40s} {env.num_parts:5d} {env.batch_model.welds.num_welds:5d} "
          f"{f'{done}/{len(steps)}':>9s} {steps.max():5d} {time.time() - start:7.1f} "
          f"{sizes} {sum(new.values()):8d}", flush=True)
    if rate < args.min_success:
      failed.append(name)
    if new:
      overflowed[name] = new
  if failed:
    print("below --min-success:", ", ".join(failed))
  if overflowed:
    print(contact_buffers.overflow_summary(overflowed))
  return 1 if failed or overflowed else 0


if __name__ == "__main__":
  sys.exit(main())
