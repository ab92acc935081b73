"""Env steps/s per robot and control mode next to raw MuJoCo stepping of the same model.

For each (robot, control mode) on one furniture: steps/s of env.step with
smoothly varying random actions (state observations, no rendering); the same
number of physics substeps stepped by mujoco.mj_step on the env's compiled
model from the very states the env stepped from; their ratio; and the Python
control cost per step: the robot's whole apply_action and, within it, the
IK step (DifferentialIK.step).
Usage:

    python benchmarks/robot_throughput.py [--steps 500] [--furniture NAME] [--robots sawyer ...]
        [--clock wall|cpu] [--repeats 1] [--block 25] [--write]

--clock cpu times with this thread's CPU time instead of wall time: on a
machine shared with other jobs, waiting for a core then counts on neither side.
--repeats N runs each row's actions N times from reset: the speeds are the least
over the passes, env/raw the median of the passes' ratios, and control and IK
come from one more pass with timers (time_robot). --block sets how many control steps each side runs before
the other takes its turn (replay_timing); a block as long as --steps times a
whole env pass, then a whole raw pass. --write also puts the table, headed by the command,
date, machine and versions, into docs/benchmarks.md, and each robot's default-mode row into
the README's headline table (scripts/make_docs.py's markers).

References (table_lack; see the README's Robots section): the original IKEA environment
reported Sawyer impedance 225, Sawyer IK 44 and Cursor 491 steps/s; robosuite
1.5.2 Lift with Sawyer runs about 55 steps/s on a machine like ours.
"""

import argparse
import pathlib
import sys
import time

import numpy as np
import replay_timing  # benchmarks/replay_timing.py, beside this script

import ikea_suite
from ikea_suite.robots import control_modes
from ikea_suite.robots import manipulator

ROOT = pathlib.Path(__file__).resolve().parents[1]

CLOCKS = {"wall": time.perf_counter, "cpu": time.thread_time}


class _Timer:
  """Wraps a callable and sums its time on `clock`."""

  def __init__(self, function, clock=time.perf_counter):
    self.function, self.clock, self.seconds, self.calls = function, clock, 0.0, 0

  def __call__(self, *args, **kwargs):
    start = self.clock()
    try:
      return self.function(*args, **kwargs)
    finally:
      self.seconds += self.clock() - start
      self.calls += 1


def smooth_actions(rng, steps, size, keep=0.9):
  """Random actions that wander instead of jumping every step (an AR(1) process in [-1, 1])."""
  actions = np.zeros((steps, size))
  current = np.zeros(size)
  for i in range(steps):
    current = keep * current + (1 - keep) * rng.uniform(-3, 3, size)
    actions[i] = np.clip(current, -1, 1)
  return actions


def time_robot(env, steps, rng, clock=time.perf_counter, repeats=1,
               block=replay_timing.BLOCK):
  """(s per env step, s per raw step, env/raw, substeps, s of apply_action, s of IK) per step.

  Each pass runs the same actions from the same reset. The two speeds are each the least
  over the passes, which filters out passes slowed by other jobs; the ratio is the median of
  the passes' own ratios, each taken on env and raw sides that alternated on the same
  machine. The control and IK figures come from one more pass, with timers wrapped round the
  robot's apply_action and the IK step: kept out of the timed passes, their clock reads
  (system calls under --clock cpu) do not load the env side.
  """
  actions = smooth_actions(rng, steps, env.action_spec().shape[0])
  actions[:, -1] = -1.0   # no connect: measure stepping, not snapping
  seed_state = env.random_state.get_state()
  passes = []
  for _ in range(repeats):
    env.random_state.set_state(seed_state)   # every pass resets to the same episode start
    passes.append(replay_timing.time_env_and_raw(env, actions, clock, block))
  env_seconds, raw_seconds, substeps = np.array(passes).T
  ratio = float(np.median(env_seconds / raw_seconds))
  robot = env.task.robot
  control = robot.apply_action = _Timer(robot.apply_action, clock)   # shadows the method
  ik = robot.ik if isinstance(robot, manipulator.Manipulator) else None   # the Cursor has none
  if ik is not None:
    solve = ik.step = _Timer(ik.step, clock)   # shadows the method
  env.random_state.set_state(seed_state)
  replay_timing.time_env_and_raw(env, actions, clock, block)
  del robot.apply_action
  ik_seconds = 0.0
  if ik is not None:
    del ik.step
    ik_seconds = solve.seconds / steps
  return (env_seconds.min(), raw_seconds.min(), ratio, int(substeps[0]),
          control.seconds / steps, ik_seconds)


def main():
  parser = argparse.ArgumentParser(description=__doc__)
  parser.add_argument("--steps", type=int, default=500)
  parser.add_argument("--furniture", default="table_four_leg_lack")
  parser.add_argument("--robots", nargs="*", default=None)
  parser.add_argument("--modes", nargs="*", default=list(control_modes.MODES))
  parser.add_argument("--clock", choices=sorted(CLOCKS), default="wall")
  parser.add_argument("--repeats", type=int, default=1,
                      help="timed passes per row: least times, median ratio")
  parser.add_argument("--block", type=int, default=replay_timing.BLOCK,
                      help="control steps per turn of the env and raw sides")
  parser.add_argument("--write", action="store_true",
                      help="also write the table into docs/benchmarks.md and README.md")
  args = parser.parse_args()
  robots = args.robots or ikea_suite.robot_names()
  rng = np.random.default_rng(0)
  header = (f"{'robot':8s} {'control mode':16s} {'substeps':>8s} {'env steps/s':>11s} "
            f"{'raw steps/s':>11s} {'env/raw':>7s} {'control ms':>10s} {'IK ms':>6s}")
  lines = [f"furniture: {args.furniture}, clock: {args.clock}, repeats: {args.repeats}, "
           f"block: {args.block}", header, "-" * len(header)]
  print("\n".join(lines))
  headline = []   # each robot's row in its default control mode (the README's table)
  for robot in robots:
    modes = args.modes if robot != "cursor" else [None]
    for mode in modes:
      options = {} if mode is None else {"control_mode": mode}
      env = ikea_suite.load(args.furniture, robot, seed=0, **options)
      env_t, raw_t, ratio, substeps, control_t, ik_t = time_robot(
          env, args.steps, rng, CLOCKS[args.clock], args.repeats, args.block)
      lines.append(f"{robot:8s} {mode or '-':16s} {substeps:8d} {1 / env_t:11.0f} "
                   f"{1 / raw_t:11.0f} {ratio:7.2f} {1e3 * control_t:10.3f} {1e3 * ik_t:6.3f}")
      print(lines[-1], flush=True)
      if mode in (None, control_modes.TASK_SPACE):   # the arms' default mode
        headline.append([f"`{robot}`", mode or "-", f"{1 / env_t:.0f}", f"{1 / raw_t:.0f}",
                         f"{ratio:.2f}"])
      env.close()
  if args.write:
    sys.path.insert(0, str(ROOT / "scripts"))
    import make_docs  # pylint: disable=g-import-not-at-top
    command = make_docs.invoked_command()
    make_docs.write_block(ROOT / "docs" / "benchmarks.md", "robot-throughput",
                          "```text\n" + "\n".join(lines) + "\n```\n", command)
    make_docs.write_block(ROOT / "README.md", "benchmark-headline", make_docs.markdown_table(
        ["robot", "control mode", "env steps/s", "raw MuJoCo steps/s", "env / raw"], headline,
        "llrrr"), command)


if __name__ == "__main__":
  main()
