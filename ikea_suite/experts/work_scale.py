"""The scale a robot's expert assembles each furniture at: the robot's WORK_SCALE, or, for
furniture whose loose parts are too wide for its gripper there, the largest scale at
which every loose part fits between its closed and open fingertips (SMALL_SCALES), or,
for furniture it does not assemble at WORK_SCALE for its reach or its grip, the largest
scale at which it was measured to (REACH_SCALES).

Grasp widths shrink with the scale and the gripper does not, so a slatted bed's side
rail, 77 mm across at scale 0.5, fits the Panda's 79 mm (less 5 mm a side) at 0.44.
`fit_scale` measures that scale from the compiled models (gripper_fit.grasp_problems'
test, widths as the parts lie on seed 0 at full size); SMALL_SCALES holds its values,
so that loading needs no measurement (`python -m ikea_suite.experts.work_scale
--robot sawyer --models ...` prints them again; tests/test_work_scale.py checks some).
"""

import numpy as np

from ikea_suite.props import scaling

# fit_scale's values for the models whose parts do not fit at the robot's WORK_SCALE;
# every other model is assembled at WORK_SCALE. Measured for each robot with the panel
# rack (tasks/panel_placement.py), which stands box walls, bench ends, bookcase and
# cabinet sides and headboards upright, and stands a wide panel that lies flat in the
# furniture (a carcass's far side, a wide lid or shelf) on its long edge: they are taken
# across their thickness, so the bookcases, cabinets, lidded boxes, slatted benches and
# TV benches fit both grippers at 0.5. The Sawyer's and the Baxter's fingers, one slot in
# (grippers.RETHINK_SLOT_1), meet when closed and open to 60 mm; the slatted beds' side
# rails need a smaller scale.
_SLATTED_BEDS = tuple(f"bed_slatted_{v}" for v in (
    "day_black", "junior_pine", "kids_birch_open", "kids_dark_open", "kids_white",
    "toddler_white"))
SMALL_SCALES = {
    "sawyer": dict.fromkeys(_SLATTED_BEDS, 0.32),
    "baxter": dict.fromkeys(_SLATTED_BEDS, 0.32),
    "panda": dict.fromkeys(_SLATTED_BEDS, 0.44),
}


# A scale below WORK_SCALE at which the expert completed its tuning episodes
# (benchmarks/expert_sweep.py --scale, seeds from 1000) of furniture whose parts fit at
# WORK_SCALE but which it does not assemble there: measured, no formula gives it, and the
# largest that worked of those tried. The taller post shelving at 0.5 lays a root ladder
# 0.75-0.95 m long in front of the Panda, and its shelves, standing in the rack as tall as
# the shelving is wide (0.4 m), go to mates at the ladder's far end beyond its reach for a
# shelf held by its top edge: shelving_posts_steel completed 1 of 2 at 0.5 and both at
# 0.45; shelving_posts_black_six none at 0.5 and both at 0.4; shelving_posts_steel_tall
# none of 4 at 0.45, both at 0.4 but 7 of 10 fresh episodes there (shelves slipping from
# the edge grip), and 4 of 4 at 0.35. The Sawyer's fingers let a 0.3 m shelf held by its
# top edge, or a ladder held by one post, slip out on the carry (shelving_posts_white_low:
# none of 2 at 0.5, seed 1000 failed at 0.4, both at 0.35; birch_shelves and steel 1 of 2
# at 0.35 and 4 of 4 at 0.3, where the parts weigh a fifth of what they weigh at 0.5).
# The Baxter's fingers are the Sawyer's: white_low failed seed 1000 at 0.5 and completed
# both at 0.35; steel failed seed 1000 at 0.5 and completed both at 0.3.
REACH_SCALES = {
    "panda": {"shelving_posts_steel": 0.45, "shelving_posts_steel_tall": 0.35,
              "shelving_posts_black_six": 0.4},
    "sawyer": {"shelving_posts_white_low": 0.35, "shelving_posts_birch_shelves": 0.3,
               "shelving_posts_steel": 0.3},
    "baxter": {"shelving_posts_white_low": 0.35, "shelving_posts_steel": 0.3},
}


def work_scale(robot, furniture):
  """The load(scale=...) at which `robot`'s expert assembles `furniture`."""
  from ikea_suite.robots import registry
  default = registry.get(robot).factory.CONFIG.WORK_SCALE
  return min(SMALL_SCALES.get(robot, {}).get(furniture, default),
             REACH_SCALES.get(robot, {}).get(furniture, default))


def fit_scale(robot, furniture, arm=0, clearance=None):
  """The largest scale, in hundredths, no larger than the robot's WORK_SCALE, at which
  every loose part is wider than the closed fingertips' gap and leaves `clearance`
  (default gripper_fit.CLEARANCE, the test grasp_problems makes) within the open one;
  None when there is none from scaling.MIN_SCALE."""
  import ikea_suite
  from ikea_suite.experts import gripper_fit
  from ikea_suite.robots import registry
  clearance = gripper_fit.CLEARANCE if clearance is None else clearance
  env = ikea_suite.load(furniture, robot, scale=1.0, seed=0)
  env.reset()
  robot_, physics = env.task.robot, env.physics
  closed = gripper_fit.finger_gap(physics, robot_, arm, 1.0)
  opened = gripper_fit.finger_gap(physics, robot_, arm, 0.0)
  widths = np.array([gripper_fit.grasp_width(env, part)
                     for part in range(len(env.task.furniture.parts))
                     if part != env.task.root_part])
  largest = (opened - clearance) / widths.max()   # widths scale with the furniture
  scale = min(registry.get(robot).factory.CONFIG.WORK_SCALE, np.floor(100 * largest - 1e-6) / 100)
  if scale < scaling.MIN_SCALE or scale * widths.min() <= closed:
    return None
  return float(scale)


def main(argv=None):
  """Prints fit_scale for `--robot` and each of `--models` (default: every catalog model)."""
  import argparse
  from ikea_suite.props import catalog
  parser = argparse.ArgumentParser(description=main.__doc__)
  parser.add_argument("--robot", default="sawyer")
  parser.add_argument("--models", nargs="+", default=None)
  args = parser.parse_args(argv)
  for name in args.models or catalog.names():
    print(f"{name:40s} {fit_scale(args.robot, name)}", flush=True)


if __name__ == "__main__":
  main()
