"""Env step throughput next to raw MuJoCo stepping of the same compiled model.

For each (furniture, robot): steps/s of env.step with state observations and
random actions; the same number of physics substeps stepped by mujoco.mj_step
on a copy of the env's compiled model; their ratio; reset time; and the cost of
one alignment check over all connector pairs. Usage:

    python benchmarks/step_throughput.py [--steps 1000] [--robot cursor] [--furniture NAME ...]
        [--write]

--write also puts the table, headed by the command, date, machine and versions, into
docs/benchmarks.md (scripts/make_docs.py's markers).
"""

import argparse
import pathlib
import sys
import time

import numpy as np
import replay_timing  # benchmarks/replay_timing.py, beside this script

import ikea_suite

ROOT = pathlib.Path(__file__).resolve().parents[1]


def random_actions(env, steps, rng):
  actions = rng.uniform(-1, 1, size=(steps,) + env.action_spec().shape)
  actions[:, -1] = -1.0   # no connect: measure stepping, not snapping
  return actions


def time_reset(env, repeats=20):
  start = time.perf_counter()
  for _ in range(repeats):
    env.reset()
  return (time.perf_counter() - start) / repeats


def time_alignment(env, repeats=2000):
  task, physics = env.task, env.physics
  start = time.perf_counter()
  for _ in range(repeats):
    task.alignment(physics).attachable(task.thresholds)
  return (time.perf_counter() - start) / repeats


def main():
  parser = argparse.ArgumentParser(description=__doc__)
  parser.add_argument("--steps", type=int, default=1000)
  parser.add_argument("--robot", default="cursor")
  parser.add_argument("--furniture", nargs="*", default=None)
  parser.add_argument("--write", action="store_true",
                      help="also write the table into docs/benchmarks.md")
  args = parser.parse_args()
  names = args.furniture or ikea_suite.furniture_names()
  rng = np.random.default_rng(0)
  header = (f"{'furniture':32s} {'robot':8s} {'substeps':>8s} {'env steps/s':>11s} "
            f"{'raw steps/s':>11s} {'env/raw':>7s} {'reset ms':>8s} {'align us':>8s} {'pairs':>5s}")
  lines = [header, "-" * len(header)]
  print("\n".join(lines))
  ratios = []
  for name in names:
    env = ikea_suite.load(name, args.robot, seed=0)
    env_time, raw_time, substeps = replay_timing.time_env_and_raw(
        env, random_actions(env, args.steps, rng))
    ratios.append(env_time / raw_time)
    lines.append(f"{name:32s} {args.robot:8s} {substeps:8d} {1 / env_time:11.0f} "
                 f"{1 / raw_time:11.0f} {env_time / raw_time:7.2f} {1e3 * time_reset(env):8.1f} "
                 f"{1e6 * time_alignment(env):8.1f} {env.task.furniture.connectors.num_pairs:5d}")
    print(lines[-1], flush=True)
    env.close()
  lines += ["", f"median env/raw ratio over {len(ratios)} models: {np.median(ratios):.2f}"]
  print("\n".join(lines[-2:]))
  if args.write:
    sys.path.insert(0, str(ROOT / "scripts"))
    import make_docs  # pylint: disable=g-import-not-at-top
    make_docs.write_block(ROOT / "docs" / "benchmarks.md", "step-throughput",
                          "```text\n" + "\n".join(lines) + "\n```\n", make_docs.invoked_command())


if __name__ == "__main__":
  main()
