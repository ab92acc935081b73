"""Which parts a robot's gripper can take as they lie, and so which furniture its expert
cannot assemble whatever its luck.

The single-arm expert takes a part from above, fingers closing across the part's long
axis (part_geometry.across_long_axis). That needs the part's width along the closing
direction to be less than the open fingers' gap and more than the closed fingers' gap:
a wider part does not fit between them, and a thinner one is never squeezed (it hangs
between fingers stopped at their closed limit and falls at the first swing). Panels,
seats and discs lying flat fail the first test; thin metal legs at half scale fail the
second in fingers that stop 13 mm apart when closed (the Rethink gripper in its default
slot, grippers.RETHINK). A hollow part (a drawer box) is taken by a wall's top edge, so
its width is that wall's thickness. The root part stays on the floor and is never picked
up.
"""

import dataclasses

import mujoco
import numpy as np

from ikea_suite import geometry
from ikea_suite.experts import arm_motion
from ikea_suite.experts import part_geometry
from ikea_suite.tasks import hollow_parts


@dataclasses.dataclass(frozen=True)
class GraspProblem:
  part: str
  width: float   # m across the fingers, as the part lies
  gap: tuple     # (closed, open) finger gap of the gripper, m
  clearance: float = 0.0   # room the open fingers must leave, m

  def __str__(self):
    closed, opened = self.gap
    side = "narrower than the closed" if self.width <= closed else "wider than the open"
    spare = (f" less {500 * self.clearance:.0f} mm a side"
             if self.width > closed and self.width < opened else "")
    return (f"{self.part}: {1000 * self.width:.0f} mm across the fingers, {side} "
            f"fingers' gap ({1000 * closed:.0f} to {1000 * opened:.0f} mm){spare}")


# Room (m) a part must leave within the open fingers' gap: 5 mm a side, the expert's
# descent tolerance.
CLEARANCE = 0.01


def finger_gap(physics, robot, arm=0, fraction=1.0):
  """Smallest distance (m) between the first finger's tip and the other fingers' tips,
  with the fingers `fraction` of the way from open (0) to closed (1). Read on a scratch
  copy of the state; nothing moves."""
  poser = arm_motion.FingerPoser(robot, physics, arm)
  poser.set(fraction)
  model, data = poser.model, poser.data
  # The fingertips take a part lying on the floor: only geoms within 2 cm of the deepest
  # along the approach axis (the Sawyer's knuckles meet, 13 mm above its open tips).
  tcp_pos, approach = poser.tcp()
  depth = (data.geom_xpos[poser.geoms] - tcp_pos) @ approach
  tips = [g for g, d in zip(poser.geoms, depth) if d > depth.max() - 0.02]
  first = [g for g in tips if poser.finger_of_geom[g] == 0]
  others = [g for g in tips if poser.finger_of_geom[g] > 0]
  return min(mujoco.mj_geomDistance(model.ptr, data, a, b, 1.0, None)
             for a in first for b in others)


def grasp_width(env, part):
  """The part's width (m) along the direction a top-down grasp closes on it, as it lies: a
  hollow part's (tasks/hollow_parts.py) is its highest wall's thickness, which the grasp
  takes by its top edge."""
  furniture = env.task.furniture
  _, rot = part_geometry.part_pose(env.physics, furniture, part)
  spec = furniture.spec.parts[part]
  wall = hollow_parts.top_wall(spec, rot)
  if wall is not None:
    (_, box_rot, size), _ = wall
    up = int(np.argmax(np.abs((rot @ box_rot)[2])))
    return float(2.0 * min(size[k] for k in range(3) if k != up))
  bounds = spec.bounds
  corners = geometry.box_corners(*bounds) @ rot.T
  return float(np.ptp(corners @ part_geometry.across_long_axis(rot, bounds)))


def grasp_problems(env, arm=0, clearance=CLEARANCE):
  """GraspProblems of every part but the root, as `env`'s parts lie now (after reset).

  A part fits when it is wider than the closed fingers' gap and leaves `clearance`
  (CLEARANCE) within the open fingers' gap.
  """
  robot, physics = env.task.robot, env.physics
  gap = (finger_gap(physics, robot, arm, 1.0), finger_gap(physics, robot, arm, 0.0))
  out = []
  for part, spec in enumerate(env.task.furniture.spec.parts):
    if part != env.task.root_part:
      width = grasp_width(env, part)
      if not gap[0] < width < gap[1] - clearance:
        out.append(GraspProblem(spec.name, width, gap, clearance))
  return out


def main(argv=None):
  """Prints, per catalog model, whether `--robot`'s gripper can take every loose part."""
  import argparse
  import ikea_suite
  from ikea_suite.props import catalog
  from ikea_suite.robots import registry
  parser = argparse.ArgumentParser(description=main.__doc__)
  parser.add_argument("--robot", default="sawyer")
  parser.add_argument("--scale", type=float, default=None, help="default: the robot's WORK_SCALE")
  parser.add_argument("--models", nargs="+", default=None)
  args = parser.parse_args(argv)
  scale = args.scale or registry.get(args.robot).factory.CONFIG.WORK_SCALE
  fits = 0
  for name in args.models or catalog.names():
    env = ikea_suite.load(name, args.robot, scale=scale, seed=0)
    env.reset()
    problems = grasp_problems(env)
    fits += not problems
    print(f"{name:40s} " + ("every loose part fits the gripper" if not problems
                            else f"{len(problems)} parts do not fit; {problems[0]}"), flush=True)
  print(f"{fits} models fit the {args.robot}'s gripper at scale {scale:g}")


if __name__ == "__main__":
  main()
