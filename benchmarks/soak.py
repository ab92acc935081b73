"""Random-action soak: every furniture x robot pair, checked for MuJoCo warnings.

    python benchmarks/soak.py --steps 200 --workers 2
    python benchmarks/soak.py table_four_leg_lack --robots cursor sawyer

Each pair runs one episode of uniformly random actions (connect included) and
reports any MuJoCo warning (contact or constraint buffer full, bad
accelerations: each ends the episode), how full MuJoCo's arena got at most,
and the most contacts at once. Exits 1 when any pair raised a warning.
"""

import argparse
import concurrent.futures
import os
import sys
import time

os.environ.setdefault("MUJOCO_GL", "egl")

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

import ikea_suite  # noqa: E402
from ikea_suite.props import catalog  # noqa: E402


def soak(name, robot, steps, seed):
  """(warnings, max arena use fraction, max contacts) of one random-action episode."""
  env = ikea_suite.load(name, robot, seed=seed)
  spec = env.action_spec()
  rng = np.random.default_rng(seed)
  env.reset()
  data = env.physics.data
  arena_use, contacts = 0.0, 0
  for _ in range(steps):
    timestep = env.step(rng.uniform(spec.minimum, spec.maximum, size=spec.shape))
    arena_use = max(arena_use, data.maxuse_arena / env.physics.model.narena)
    contacts = max(contacts, int(data.maxuse_con))
    if timestep.last():
      break
  names = list(mujoco.mjtWarning.__members__)
  warnings = [names[i] for i, w in enumerate(data.warning) if w.number]
  reason = env.termination_reason
  if reason and reason != "complete":
    warnings.append(reason)
  return warnings, arena_use, contacts


def _soak_model(args):
  name, robots, steps, seed = args
  return [(name, robot) + soak(name, robot, steps, seed) for robot in robots]


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("names", nargs="*", help="models (default: the whole catalog)")
  parser.add_argument("--robots", nargs="*", default=None, help="default: every robot")
  parser.add_argument("--steps", type=int, default=200, help="control steps per pair")
  parser.add_argument("--seed", type=int, default=5000)
  parser.add_argument("--workers", type=int, default=1, help="parallel processes")
  args = parser.parse_args(argv)
  names = args.names or catalog.names()
  robots = args.robots or ikea_suite.robot_names()
  start, bad, rows = time.perf_counter(), [], 0
  worst_arena, worst_contacts = 0.0, 0
  jobs = [(name, robots, args.steps, args.seed) for name in names]
  with concurrent.futures.ProcessPoolExecutor(args.workers) as pool:
    for results in pool.map(_soak_model, jobs):
      for name, robot, warnings, arena_use, contacts in results:
        rows += 1
        worst_arena, worst_contacts = max(worst_arena, arena_use), max(worst_contacts, contacts)
        if warnings:
          bad.append((name, robot, warnings))
          print(f"WARNING {name} {robot}: {'; '.join(warnings)}", flush=True)
  print(f"{rows} furniture x robot pairs, {args.steps} random steps each: {len(bad)} with "
        f"MuJoCo warnings; arena at most {100 * worst_arena:.1f}% used, at most "
        f"{worst_contacts} contacts; {time.perf_counter() - start:.0f} s")
  return 1 if bad else 0


if __name__ == "__main__":
  sys.exit(main())
