"""Total env steps/s of gymnasium async vector envs, 1, 2, 4, ... processes up to the core count.

Each row steps `gymnasium.make_vec("ikea_suite/Assembly-v0", num_envs=n,
vectorization_mode="async")` with random actions (state observations, no
rendering, episodes long enough that no reset falls in the timed window)
and prints total env steps/s, the speed-up over one plain (unvectorized)
gymnasium env in this process, and the efficiency (speed-up / n). Beside each row,
the same number of independent processes, each stepping its own plain env with no
vector wrapper and no parent in the loop, gives the machine's own ceiling (shared
caches, memory bandwidth, clock speed with every core busy, hyperthreads); the last
column, async / independent, is what gymnasium's async vector env itself keeps of it.
Usage:

    nice python benchmarks/vector_throughput.py [--steps 400] [--furniture NAME] [--robot cursor]
        [--max-envs N] [--write]

--write also puts the table, headed by the command, date, machine and versions, into
docs/benchmarks.md (scripts/make_docs.py's markers).
"""

import argparse
import multiprocessing
import os
import pathlib
import sys
import time

import gymnasium
import numpy as np

import ikea_suite.gym

ROOT = pathlib.Path(__file__).resolve().parents[1]


def single_rate(furniture, robot, steps):
  env = gymnasium.make(ikea_suite.gym.ENV_ID, furniture=furniture, robot=robot, time_limit=1e4)
  env.reset(seed=0)
  rng = np.random.default_rng(0)
  low, high = env.action_space.low, env.action_space.high
  actions = rng.uniform(low, high, (steps + 20,) + env.action_space.shape)
  for a in actions[:20]:
    env.step(a)
  start = time.perf_counter()
  for a in actions[20:]:
    env.step(a)
  seconds = time.perf_counter() - start
  env.close()
  return steps / seconds


def _independent_worker(furniture, robot, steps, seed, barrier, results):
  env = gymnasium.make(ikea_suite.gym.ENV_ID, furniture=furniture, robot=robot, time_limit=1e4)
  env.reset(seed=seed)
  rng = np.random.default_rng(seed)
  low, high = env.action_space.low, env.action_space.high
  actions = rng.uniform(low, high, (steps + 20,) + env.action_space.shape)
  for a in actions[:20]:
    env.step(a)
  barrier.wait()
  start = time.perf_counter()
  for a in actions[20:]:
    env.step(a)
  results.put((start, time.perf_counter()))
  env.close()


def independent_rate(furniture, robot, num_procs, steps):
  """Total env steps/s of `num_procs` processes each stepping its own env, started together."""
  context = multiprocessing.get_context("fork")
  barrier, results = context.Barrier(num_procs), context.Queue()
  procs = [context.Process(target=_independent_worker,
                           args=(furniture, robot, steps, seed, barrier, results))
           for seed in range(num_procs)]
  for proc in procs:
    proc.start()
  spans = [results.get() for _ in procs]
  for proc in procs:
    proc.join()
  seconds = max(end for _, end in spans) - min(start for start, _ in spans)
  return num_procs * steps / seconds


def vector_rate(furniture, robot, num_envs, steps):
  # gymnasium's defaults: the platform's start method (fork on Linux), observations in
  # shared memory.
  envs = gymnasium.make_vec(ikea_suite.gym.ENV_ID, num_envs=num_envs, vectorization_mode="async",
                            furniture=furniture, robot=robot, time_limit=1e4)
  envs.reset(seed=0)
  envs.action_space.seed(0)
  for _ in range(20):
    envs.step(envs.action_space.sample())
  actions = [envs.action_space.sample() for _ in range(steps)]
  start = time.perf_counter()
  for a in actions:
    envs.step(a)
  seconds = time.perf_counter() - start
  envs.close()
  return num_envs * steps / seconds


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--steps", type=int, default=400, help="vector steps per row")
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--robot", default=ikea_suite.DEFAULT_ROBOT)
  parser.add_argument("--max-envs", type=int, default=os.cpu_count() or 1)
  parser.add_argument("--write", action="store_true",
                      help="also write the table into docs/benchmarks.md")
  args = parser.parse_args()
  counts, n = [], 1
  while n <= args.max_envs:
    counts.append(n)
    n *= 2
  if counts[-1] != args.max_envs:
    counts.append(args.max_envs)
  single = single_rate(args.furniture, args.robot, args.steps)
  lines = [f"{args.furniture} with {args.robot}, {os.cpu_count()} cores, random actions, "
           f"no rendering", f"single env (no vector wrapper): {single:.0f} steps/s",
           f"{'processes':>9s} {'independent':>12s} {'async steps/s':>14s} {'speed-up':>9s} "
           f"{'efficiency':>11s} {'async/indep.':>13s}"]
  print("\n".join(lines))
  for n in counts:
    ceiling = independent_rate(args.furniture, args.robot, n, args.steps)
    rate = vector_rate(args.furniture, args.robot, n, args.steps)
    lines.append(f"{n:9d} {ceiling:12.0f} {rate:14.0f} {rate / single:9.2f} "
                 f"{rate / single / n:11.2f} {rate / ceiling:13.2f}")
    print(lines[-1], flush=True)
  if args.write:
    sys.path.insert(0, str(ROOT / "scripts"))
    import make_docs  # pylint: disable=g-import-not-at-top
    body = "```text\n" + "\n".join(lines) + "\n```\n"
    make_docs.write_block(ROOT / "docs" / "benchmarks.md", "vector-throughput", body,
                          make_docs.invoked_command())


if __name__ == "__main__":
  main()
