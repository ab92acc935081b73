"""Whether every part starts at rest: zero actions, motion from the first step to `--seconds` later.

    python benchmarks/rest_sweep.py                              # Cursor (scale 1) and Sawyer (0.5)
    python benchmarks/rest_sweep.py --robots panda baxter --seeds 0 1 2 --seconds 20
    python benchmarks/rest_sweep.py --robots sawyer --arena work_table --models box_open_kuggis
    python benchmarks/rest_sweep.py --robots sawyer panda --arena work_table --seeds 0 2

Prints one line per (robot, model, seed): the largest drift (mm) and turn (degrees) of any
part and the part that moved most ("skip" where the furniture does not fit the arena at
that scale), then the --worst lines (nearest the limits first) and how many exceeded the
limits (2 mm, 1 degree: tests/test_rest.py, which runs a sample of this sweep). Arms run
at their WORK_SCALE unless --scale is given.
"""

import argparse
import sys
import time

import numpy as np
from dm_control import composer

import ikea_suite
from ikea_suite.robots import registry
from ikea_suite.tasks import resting

DRIFT_LIMIT, TURN_LIMIT = 0.002, np.radians(1.0)


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--robots", nargs="+", default=["cursor", "sawyer"])
  parser.add_argument("--models", nargs="+", default=None, help="default: the whole catalog")
  parser.add_argument("--seeds", nargs="+", type=int, default=[0])
  parser.add_argument("--seconds", type=float, default=resting.CHECK_TIME)
  parser.add_argument("--scale", type=float, default=None)
  parser.add_argument("--arena", default=None, choices=["floor", "work_table"],
                      help="floor (default) or work_table (arms)")
  parser.add_argument("--worst", type=int, default=5, help="how many of the worst lines to repeat")
  args = parser.parse_args(argv)
  models = args.models or ikea_suite.furniture_names()
  scored, failed, runs = [], 0, 0
  for robot in args.robots:
    scale = args.scale or registry.get(robot).factory.CONFIG.WORK_SCALE
    options = {"arena": args.arena} if args.arena else {}
    for name in models:
      for seed in args.seeds:
        start = time.perf_counter()
        try:
          env = ikea_suite.load(name, robot, seed=seed, scale=scale, **options)
          motion = resting.start_motion(env, args.seconds)
        except (ikea_suite.IkeaSuiteError, composer.EpisodeInitializationError) as e:
          print(f"skip {robot:7s} {scale:4.2f} {name:42s} seed {seed:3d} {e}", flush=True)
          continue   # does not fit this arena at this scale
        runs += 1
        over = motion.drift > DRIFT_LIMIT or motion.turn > TURN_LIMIT
        failed += over
        score = max(motion.drift / DRIFT_LIMIT, motion.turn / TURN_LIMIT)
        line = (f"{'OVER' if over else 'ok  '} {robot:7s} {scale:4.2f} {name:42s} seed {seed:3d} "
                f"{motion.drift * 1000:7.2f} mm {np.degrees(motion.turn):6.2f} deg "
                f"{motion.worst_part:22s} {time.perf_counter() - start:5.1f} s")
        scored.append((score, line))
        print(line, flush=True)
  for _, line in sorted(scored, key=lambda item: -item[0])[:args.worst]:
    print(f"worst: {line}")
  print(f"{failed} of {runs} runs over {DRIFT_LIMIT * 1000:g} mm or {np.degrees(TURN_LIMIT):g} degree")
  return 1 if failed else 0


if __name__ == "__main__":
  sys.exit(main())
