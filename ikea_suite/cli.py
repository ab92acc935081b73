"""`ikea-suite-rollout`: run episodes headless and print a summary of each.

    ikea-suite-rollout                       # the Cursor's expert (oracle) on the default furniture
    ikea-suite-rollout --policy random --furniture chair_back_ivar --episodes 3
    ikea-suite-rollout --robot sawyer --episodes 3   # the Sawyer's expert at its work scale
    ikea-suite-rollout --list                # the furniture catalog with part counts and masses
    ikea-suite-rollout --doctor              # versions, rendering backend, hints for problems
"""

import argparse
import sys
import time

import numpy as np

import ikea_suite  # sets MUJOCO_GL=egl on a display-less Linux machine
from ikea_suite import doctor
from ikea_suite.experts import registry
from ikea_suite.props import catalog

POLICIES = ("expert", "oracle", "random")
# --policy oracle: the expert of the robots whose expert is the Cursor oracle.
ORACLE_KIND = "cursor_oracle"


def make_policy(name, env, seed):
  """The policy `name` (POLICIES) for `env`: the robot's scripted expert (the experts'
  registry; refused, with the furniture it assembles, where it is not measured to
  assemble env's furniture at env's scale), the Cursor oracle, or uniform random actions
  from `seed`."""
  if name == "expert":
    return registry.make_expert(env, require_supported=True)
  if name == "oracle":
    robot = env.task.robot.mjcf_model.model
    if robot not in registry.EXPERTS or registry.EXPERTS[robot].kind != ORACLE_KIND:
      oracles = [r for r, e in registry.EXPERTS.items() if e.kind == ORACLE_KIND]
      instead = "expert" if robot in registry.EXPERTS else "random"
      raise ikea_suite.IkeaSuiteError(
          f"--policy oracle drives the {' or '.join(oracles)} robot, not the {robot}; "
          f"use --policy {instead}")
    return registry.make_expert(env)
  rng = np.random.default_rng(seed)
  spec = env.action_spec()
  return lambda timestep: rng.uniform(spec.minimum, spec.maximum, spec.shape)


def run_episode(env, policy):
  """Runs one episode; returns a dict summary."""
  start = time.perf_counter()
  timestep = env.reset()
  if hasattr(policy, "reset"):
    policy.reset()
  steps, episode_return, blocked = 0, 0.0, 0
  while not timestep.last():
    timestep = env.step(policy(timestep))
    steps += 1
    episode_return += timestep.reward
    blocked += len(env.task.blocked_connections)
  seconds = time.perf_counter() - start
  state = env.task.state
  return {"steps": steps, "connections": len(state.connections),
          "needed": len(env.task.furniture.parts) - 1, "success": state.complete,
          "return": episode_return, "seconds": seconds, "steps_per_second": steps / seconds,
          "ended_by": env.termination_reason or "time limit", "blocked_connects": blocked}


def print_catalog():
  """One line per furniture model: name, category, parts and assembled mass."""
  print(f"{'furniture':44s} {'category':11s} {'parts':>5s} {'mass kg':>8s}")
  for e in catalog.entries().values():
    print(f"{e.name:44s} {e.category:11s} {e.num_parts:5d} {e.mass:8.1f}")


def main(argv=None):
  parser = argparse.ArgumentParser(description="Run ikea_suite episodes headless.")
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--robot", default=ikea_suite.DEFAULT_ROBOT)
  parser.add_argument("--policy", default="expert", choices=POLICIES,
                      help="expert: the robot's scripted expert (the Cursor's is the oracle); "
                           "oracle: the Cursor oracle; random: uniform random actions")
  parser.add_argument("--episodes", type=int, default=1)
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--time-limit", type=float, default=None, help="seconds of simulated time")
  parser.add_argument("--scale", type=float, default=None,
                      help="furniture size factor (default: the robot's work scale, 1 for "
                           "the Cursor, 0.5 for the arms)")
  parser.add_argument("--list", action="store_true",
                      help="print the furniture catalog (parts, mass) and exit")
  parser.add_argument("--doctor", action="store_true",
                      help="print versions and whether rendering works, with hints, and exit")
  args = parser.parse_args(argv)
  if args.doctor:
    return 1 if doctor.main() else 0
  if args.list:
    print_catalog()
    return 0
  options = {} if args.time_limit is None else {"time_limit": args.time_limit}
  if args.scale is not None:
    options["scale"] = args.scale
  try:
    env = ikea_suite.load(args.furniture, args.robot, seed=args.seed, **options)
    policy = make_policy(args.policy, env, args.seed)
  except ikea_suite.IkeaSuiteError as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  print(f"{args.furniture} with {args.robot}, {args.policy} policy, "
        f"{len(env.task.furniture.parts)} parts, seed {args.seed}")
  successes = 0
  for episode in range(args.episodes):
    s = run_episode(env, policy)
    successes += s["success"]
    print(f"episode {episode}: steps {s['steps']}, connections {s['connections']}/{s['needed']}, "
          f"success {s['success']}, return {s['return']:.1f}, wall time {s['seconds']:.2f} s "
          f"({s['steps_per_second']:.0f} steps/s)")
  print(f"success rate {successes}/{args.episodes}")
  return 0


if __name__ == "__main__":
  sys.exit(main())
