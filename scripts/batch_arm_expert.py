"""The batched scripted arm expert (batch/arm_scripted.py) on the last-part task, per model.

Each world starts with every part but one joined (load option preassembled = parts - 1,
laid out by the CPU task's placement, a panel standing in the rack; batch/arm_model.py
turns the joined group over when the last part goes in from below), and the expert grasps
the loose part, carries it to its mate and connects. Prints, per model, the worlds that
completed their first episode (and the phase each of up to 16 others stopped in), the
steps the slowest completed world took, the wall time (model build and jit compile
included) and the world-steps in which MJX-Warp's contact or constraint buffers
overflowed (batch/contact_buffers.py; none on JAX or the host); exits 1 if any model is
below --min-success or any buffer overflowed. The MJX implementation is
backend.default_impl() (Warp on a GPU) unless --impl; --host-physics steps the physics
with MuJoCo's C library instead (the CPU tests' path, tests/test_batch_arm.py).

The starts are the CPU task's own, recorded from its environment at --layout-seed
(default: --seed) when the batched model is built (arm_env: `layouts`, `layout_seed`);
--seed also draws which of them each world starts from. A seed the expert was never run
on is therefore a set of starts it never saw.

  python scripts/batch_arm_expert.py [--robot panda] [--worlds 1024] [--steps 600]
      [--seed 0] [--layout-seed SEED]
      [--furniture table_four_leg_lack stool_square_pine bench_plank_pine]
"""

import argparse
import sys
import time

import numpy as np

from ikea_suite.batch import arm_env
from ikea_suite.batch import arm_scripted
from ikea_suite.batch import backend
from ikea_suite.batch import contact_buffers
from ikea_suite.props import catalog

FURNITURE = ("table_four_leg_lack", "stool_square_pine", "bench_plank_pine")


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--robot", default="panda", choices=arm_scripted.ROBOTS)
  parser.add_argument("--worlds", type=int, default=1024)
  parser.add_argument("--steps", type=int, default=600)
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--layout-seed", type=int, default=None,
                      help="the CPU environment's seed the starts are recorded from "
                           "(default: --seed)")
  parser.add_argument("--min-success", type=float, default=0.9)
  parser.add_argument("--furniture", nargs="*", default=list(FURNITURE))
  parser.add_argument("--impl", default=None, choices=backend.IMPLS)
  parser.add_argument("--host-physics", action="store_true")
  args = parser.parse_args(argv)
  impl = backend.check_impl(args.impl)
  layout_seed = args.seed if args.layout_seed is None else args.layout_seed
  print(f"robot {args.robot}, {args.worlds} worlds, seed {args.seed}, starts recorded at "
        f"seed {layout_seed}, MJX impl {impl}"
        f"{' (physics: MuJoCo C on the host)' if args.host_physics else ''}")
  print(f"{'model':32s} {'parts':>5s} {'completed':>11s} {'rate':>6s} {'steps':>5s} "
        f"{'wall s':>7s} {'overflow':>8s}", flush=True)
  failed, overflowed = [], {}
  for name in args.furniture:
    start = time.time()
    parts = len(catalog.spec(name).parts)
    env = arm_env.load(name, args.robot, impl=impl, num_worlds=args.worlds,
                       preassembled=parts - 1, layout_seed=layout_seed)
    success, steps, phase = arm_scripted.rollout(env, args.worlds, args.steps, seed=args.seed,
                                                 host_physics=args.host_physics)
    totals = env.overflow_watch.flush()
    rate = float(np.mean(success))
    print(f"{name:32s} {parts:5d} {f'{int(success.sum())}/{len(success)}':>11s} {rate:6.1%} "
          f"{int(steps.max()):5d} {time.time() - start:7.1f} {sum(totals.values()):8d}",
          flush=True)
    stuck = np.flatnonzero(~success)
    if 0 < len(stuck) <= 16:   # where the worlds that did not complete stopped
      print("  not completed: " + ", ".join(
          f"world {w} in {arm_scripted.PHASES[phase[w]]}" for w in stuck))
    if rate < args.min_success:
      failed.append(name)
    if totals:
      overflowed[name] = totals
  if failed:
    print("below --min-success:", ", ".join(failed))
  if overflowed:
    print(contact_buffers.overflow_summary(overflowed))
  return 1 if failed or overflowed else 0


if __name__ == "__main__":
  sys.exit(main())
