"""Success of the scripted experts per furniture model and robot, on fresh seeds.

    python benchmarks/expert_sweep.py --robots sawyer panda --seed-start 1000 --seeds 10
    python benchmarks/expert_sweep.py --robots jaco --models table_four_leg_lack --processes 2
    python benchmarks/expert_sweep.py --robots sawyer --models table_four_leg_lack --arena work_table
    python benchmarks/expert_sweep.py --robots sawyer --graspable --num-models 129
    python benchmarks/expert_sweep.py --join sweep_5000.log sweep_5010.log
    python benchmarks/expert_sweep.py --supported --seed-start 31000 --seeds 10
    python benchmarks/expert_sweep.py --robots panda --models chair_back_ivar --seeds 20 --write

For each robot, one row per model: the scale it runs at (unless --scale, the robot's
WORK_SCALE, or for furniture too wide for its gripper there the smaller scale at which
the parts fit: experts/work_scale.py), parts, complete assemblies / seeds, mean
connections, mean control steps and mean wall-clock seconds per episode.
Episodes run in parallel processes (--processes). Report figures from
seeds >= 1000: the experts were developed on seeds below 100.

--write records each (robot, furniture) pair of the sweep (or of the --join logs) in
the experts' measurements, ikea_suite/experts/supported.json, replacing the pair's
earlier record: the listing rule there (experts/registry.py: at least 80% complete, and
for the Baxter both arms) then decides which pairs experts.supported() lists. Measure
on seeds the experts were never tuned on.
"""

import argparse
import json
import multiprocessing
import os
import sys
import time

import numpy as np


def run_episode(job):
  """(robot, furniture, scale, seed, time limit or None, arena, control mode) -> dict summary
  of one expert episode."""
  robot, furniture, scale, seed, time_limit, arena, control_mode = job
  import ikea_suite
  from ikea_suite.experts import joint_planner
  from ikea_suite.experts import registry
  start = time.perf_counter()
  options = {"arena": arena}
  if robot != "cursor":
    options["control_mode"] = control_mode
  if time_limit is not None:
    options["time_limit"] = time_limit
  env = ikea_suite.load(furniture, robot, seed=seed, scale=scale, **options)
  expert = registry.make_expert(env, require_supported=False)   # it measures any pair
  timestep = env.reset()
  expert.reset()
  steps = 0
  while not timestep.last():
    timestep = env.step(expert(timestep))
    steps += 1
  state = env.task.state
  return {"robot": robot, "control_mode": control_mode, "arena": arena,
          "time_limit": time_limit, "furniture": furniture, "scale": scale, "seed": seed,
          "parts": len(env.task.furniture.parts), "connections": len(state.connections),
          "complete": bool(state.complete), "steps": steps,
          "seconds": time.perf_counter() - start,
          "arms_used": sorted(expert.arms_used if registry.expert(robot).two_arm else {0}),
          "planner": joint_planner.AVAILABLE}


def default_models(count):
  """Small tabletop furniture across categories: the `count` models with fewest parts
  and lowest mass per category, round-robin over categories."""
  from ikea_suite.props import catalog
  by_category = {}
  for e in sorted(catalog.entries().values(), key=lambda e: (e.num_parts, e.mass)):
    if e.num_parts <= 6:
      by_category.setdefault(e.category, []).append(e.name)
  out = []
  while len(out) < count and any(by_category.values()):
    for names in by_category.values():
      if names and len(out) < count:
        out.append(names.pop(0))
  return out


def graspable(robot, furniture, scale, arena):
  """True when every loose part fits `robot`'s gripper as placed on the first seed;
  otherwise prints the first part that does not and returns False."""
  import ikea_suite
  from ikea_suite.experts import gripper_fit
  env = ikea_suite.load(furniture, robot, seed=0, scale=scale, arena=arena)
  env.reset()
  problems = gripper_fit.grasp_problems(env)
  if problems:
    print(f"skipped {robot} {furniture}: {len(problems)} parts do not fit its gripper; {problems[0]}")
  return not problems


def print_table(robot, rows):
  print(f"\n{robot}")
  print(f"{'model':40s} {'scale':>5s} {'parts':>5s} {'complete':>9s} {'mean conn':>9s} "
        f"{'steps':>6s} {'seconds':>7s}")
  for furniture in dict.fromkeys(r["furniture"] for r in rows):
    mine = [r for r in rows if r["furniture"] == furniture]
    print(f"{furniture:40s} {mine[0]['scale']:5.2f} {mine[0]['parts']:5d} "
          f"{sum(r['complete'] for r in mine):4d}/{len(mine):<4d} "
          f"{np.mean([r['connections'] for r in mine]):9.2f} "
          f"{np.mean([r['steps'] for r in mine]):6.0f} {np.mean([r['seconds'] for r in mine]):7.1f}")


def write_measurements(rows, path=None):
  """Records each (robot, furniture) pair of `rows` (episode summaries) in the experts'
  measurements (registry.write; `path` defaults to the package's supported.json) and
  prints what each pair's record now says."""
  from ikea_suite.experts import registry
  # The supported lists promise what load()'s defaults give at the recorded scale.
  options = {"arena": "floor", "control_mode": "task_space", "time_limit": None}
  for row in rows:
    for key, default in options.items():
      if row.get(key, default) != default:
        sys.exit(f"--write records sweeps with load()'s defaults only ({key} {default}); "
                 f"{row['robot']} {row['furniture']} seed {row['seed']} ran with {key} "
                 f"{row[key]}")
    # Without OMPL a twice-stalled carry puts the part back instead of planning round
    # the assembly, so the same seed may end otherwise: the lists promise the planner.
    if not row.get("planner", False):
      sys.exit(f"--write records sweeps run with the joint planner (pip install "
               f"'ikea_suite[planning]'); {row['robot']} {row['furniture']} seed "
               f"{row['seed']} ran without it")
  pairs = {}
  for row in rows:
    pairs.setdefault((row["robot"], row["furniture"]), []).append(row)
  measured = [registry.summarize(robot, furniture, episodes)
              for (robot, furniture), episodes in pairs.items()
              if not registry.expert(robot).every_model]
  registry.write(measured, *([] if path is None else [path]))
  for m in measured:
    arms = "" if m.both_arms is None else f", both arms in {m.both_arms}"
    print(f"wrote {m.robot} {m.furniture}: {m.completed}/{m.episodes} complete{arms} at "
          f"scale {m.scale:g}, seeds {m.seeds}: {'listed' if m.supported else 'not listed'}")
  skipped = sorted({r for r, _ in pairs if registry.expert(r).every_model})
  if skipped:
    print(f"not written: {', '.join(skipped)} (listed for every catalog model)")


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
  parser.add_argument("--robots", nargs="+", default=["sawyer", "panda", "baxter", "jaco"])
  parser.add_argument("--models", nargs="+", default=None)
  parser.add_argument("--supported", action="store_true",
                      help="each robot's own supported list (experts.supported) instead of --models")
  parser.add_argument("--num-models", type=int, default=24)
  parser.add_argument("--seed-start", type=int, default=1000)
  parser.add_argument("--seeds", type=int, default=10)
  parser.add_argument("--scale", type=float, default=None,
                      help="default: the robot's work scale for each model (experts/work_scale.py: "
                           "its WORK_SCALE, or the smaller scale at which the parts fit its gripper)")
  parser.add_argument("--processes", type=int, default=2)
  parser.add_argument("--time-limit", type=float, default=None,
                      help="simulated seconds per episode (default: the task's, 30 + 25 per part)")
  parser.add_argument("--arena", default="floor", help="load(arena=...): floor or work_table")
  parser.add_argument("--control-mode", default="task_space",
                      help="the arms' control mode: task_space or impedance")
  parser.add_argument("--json", default=None, help="also write every episode's summary here")
  parser.add_argument("--graspable", action="store_true",
                      help="skip, naming the part, models with a loose part the robot's gripper "
                           "cannot take as it lies (experts/gripper_fit.py)")
  parser.add_argument("--join", nargs="+", default=None, metavar="LOG",
                      help="run nothing: print the tables of the episodes these sweeps' "
                           "output logs hold (one JSON line each), e.g. two seed ranges")
  parser.add_argument("--write", nargs="?", const="", default=None, metavar="JSON",
                      help="record each pair's completions in the experts' measurements "
                           "(default file: ikea_suite/experts/supported.json)")
  args = parser.parse_args(argv)
  write_to = None if not args.write else args.write
  if args.join:
    rows = [json.loads(line) for log in args.join for line in open(log) if line.startswith("{")]
    for robot in dict.fromkeys(r["robot"] for r in rows):
      mine = sorted((r for r in rows if r["robot"] == robot), key=lambda r: r["seed"])
      print_table(robot, mine)
      print(f"total {sum(r['complete'] for r in mine)}/{len(mine)}")
    if args.write is not None:
      write_measurements(rows, write_to)
    return 0
  from ikea_suite import experts
  from ikea_suite.experts import work_scale
  jobs = []
  for robot in args.robots:
    models = (experts.supported(robot) if args.supported
              else args.models or default_models(args.num_models))
    scales = {m: args.scale or work_scale.work_scale(robot, m) for m in models}
    mine = [m for m in models
            if not args.graspable or graspable(robot, m, scales[m], args.arena)]
    jobs += [(robot, m, scales[m], s, args.time_limit, args.arena, args.control_mode)
             for m in mine for s in range(args.seed_start, args.seed_start + args.seeds)]
  start = time.perf_counter()
  rows = []
  with multiprocessing.get_context("fork").Pool(args.processes) as pool:
    for row in pool.imap_unordered(run_episode, jobs, chunksize=1):
      rows.append(row)   # one line per finished episode, so a cut-short sweep keeps its results
      print(json.dumps(row), flush=True)
  order = {job[:4]: k for k, job in enumerate(jobs)}
  rows.sort(key=lambda r: order[(r["robot"], r["furniture"], r["scale"], r["seed"])])
  limit = "task default" if args.time_limit is None else f"{args.time_limit:g} s"
  print(f"{len(jobs)} episodes, seeds {args.seed_start}..{args.seed_start + args.seeds - 1}, "
        f"time limit {limit}, arena {args.arena}, {args.processes} processes, {time.perf_counter() - start:.0f} s, "
        f"load {os.getloadavg()[0]:.1f}")
  for robot in args.robots:
    print_table(robot, [r for r in rows if r["robot"] == robot])
  if args.json:
    with open(args.json, "w") as f:
      json.dump(rows, f, indent=1)
  if args.write is not None:
    write_measurements(rows, write_to)
  return 0


if __name__ == "__main__":
  sys.exit(main())
