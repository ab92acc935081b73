"""Env steps/s of the batched (MJX) assembly task next to the CPU environment's single process.

An env step is the CPU environment's step: the robot acts (the cursors, or the
Panda's task-space action through the batched IK), connect is tried (off here:
random actions with connect = -1, measuring stepping), then the same 25 physics
substeps; state observations are computed every step. For each robot and
furniture: the CPU env's steps/s in one process (ikea_suite.load), then the
batched env's steps/s at each world count, after one untimed step that compiles
it, and the world-steps whose Warp contact or constraint buffers
overflowed (contact_buffers; always 0 on MJX's JAX implementation). Prints the
device and MJX implementation.

  python benchmarks/batch_throughput.py [--robot cursor panda] [--worlds 1024 4096 16384]
      [--steps 20] [--furniture table_four_leg_lack chair_back_ivar ...]

--robot panda alone defaults to the four-leg table (the issue's Panda target: 50,000 env
steps/s at 4k worlds or more on one H100). On MJX's JAX implementation (no GPU) the Panda
uses its light collision model (batch/arm_model.py) and is slow: one env step of one world
took about 40 s on the 2-core development machine, so give it --worlds 1 --steps 1 there.

Defaults: 1k, 4k, 16k, 64k worlds on a GPU; 16 and 32 on a CPU (on the 2-core
development machine, 64 worlds of MJX's JAX implementation hung in XLA's CPU
runtime, waiting on a futex with no CPU use, in two runs).
"""

import argparse
import time

import jax
import numpy as np

import ikea_suite
from ikea_suite.batch import backend
from ikea_suite.batch import arm_env
from ikea_suite.batch import env as env_lib

FURNITURE = ("table_four_leg_lack", "chair_back_ivar", "bed_slatted_kids_birch_open")
ARM_FURNITURE = ("table_four_leg_lack",)
ROBOTS = ("cursor",) + arm_env.ROBOTS


def cpu_rate(name, steps, robot="cursor"):
  """Steps/s of ikea_suite.load(name, robot) in this process, random actions, no connect."""
  env = ikea_suite.load(name, robot, seed=0)
  env.reset()
  rng = np.random.default_rng(0)
  actions = rng.uniform(-1, 1, size=(steps,) + env.action_spec().shape)
  actions[:, -1] = -1.0
  start = time.perf_counter()
  for action in actions:
    if env.step(action).last():
      env.reset()
  return steps / (time.perf_counter() - start)


def batch_rate(env, worlds, steps):
  """(steps/s summed over worlds, compile s, overflowed world-steps) of env.step_batch at
  `worlds` worlds."""
  state = env.reset_batch(jax.random.PRNGKey(0), worlds)
  env.overflow_watch.flush()
  before = env.overflow_watch.total
  with env.precision():
    actions = jax.random.uniform(jax.random.PRNGKey(1), (worlds, env.action_size),
                                 minval=-1.0, maxval=1.0).at[:, -1].set(-1.0)
  start = time.perf_counter()
  state = env.step_batch(state, actions)
  jax.block_until_ready(state)
  compile_s = time.perf_counter() - start
  start = time.perf_counter()
  for _ in range(steps):
    state = env.step_batch(state, actions)
  jax.block_until_ready(state)
  rate = worlds * steps / (time.perf_counter() - start)
  env.overflow_watch.flush()
  return rate, compile_s, env.overflow_watch.total - before


def main():
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  on_gpu = any(d.platform == "gpu" for d in jax.devices())
  parser.add_argument("--worlds", type=int, nargs="*",
                      default=[1024, 4096, 16384, 65536] if on_gpu else [16, 32])
  parser.add_argument("--steps", type=int, default=20 if on_gpu else 3)
  parser.add_argument("--cpu-steps", type=int, default=300)
  parser.add_argument("--furniture", nargs="*", default=None,
                      help=f"default: {' '.join(FURNITURE)} (cursor), "
                           f"{' '.join(ARM_FURNITURE)} (arms)")
  parser.add_argument("--robot", nargs="*", default=["cursor"], choices=ROBOTS)
  parser.add_argument("--impl", default=None, choices=backend.IMPLS)
  args = parser.parse_args()
  device = jax.devices()[0]
  impl = backend.check_impl(args.impl)
  print(f"device: {device.platform} {getattr(device, 'device_kind', '')}; MJX impl: {impl}; "
        f"physics substeps per env step: 25")
  header = (f"{'robot':7s} {'furniture':28s} {'worlds':>7s} {'env steps/s':>12s} "
            f"{'x CPU env':>9s} {'compile s':>9s} {'overflow':>8s}")
  print(header)
  print("-" * len(header))
  for robot in args.robot:
    names = args.furniture or (FURNITURE if robot == "cursor" else ARM_FURNITURE)
    for name in names:
      single = cpu_rate(name, args.cpu_steps, robot)
      print(f"{robot:7s} {name:28s} {'CPU env':>7s} {single:12.0f} {1.0:9.2f} {'':>9s}",
            flush=True)
      for worlds in args.worlds:
        if robot == "cursor":
          env = env_lib.load(name, impl=impl, num_worlds=worlds)
        else:
          env = arm_env.load(name, robot, impl=impl, num_worlds=worlds)
        rate, compile_s, overflow = batch_rate(env, worlds, args.steps)
        shown = f"{rate:12.0f}" if rate >= 10 else f"{rate:12.3f}"
        print(f"{robot:7s} {name:28s} {worlds:7d} {shown} {rate / single:9.3g} "
              f"{compile_s:9.1f} {overflow:8d}", flush=True)


if __name__ == "__main__":
  main()
