"""Checks that every furniture model is sound: `python -m ikea_suite.design.validate [NAMES]`.

For each model file:
  format      it loads in plain MuJoCo and passes the furniture-format loader,
              which also requires every connector to have a compatible mate
              that coincides with it in the assembled pose, and dm_control builds
              its parts as load() does (model_format.check_buildable);
  graph       the parts form one connected assembly graph;
  overlap     no two parts interpenetrate in the assembled pose by more than
              `PENETRATION_TOL`;
  stability   the furniture, fully connected through the task's own connect
              (so with exactly the welds an episode makes, loops closed),
              stands on the floor for `SETTLE_TIME` seconds: no part drifts
              more than `DRIFT_TOL` or turns more than `TURN_TOL`.

Plain MuJoCo checks (overlap) use the suite's physics configuration too
(`ikea_suite.physics_settings`).
"""

import argparse
import dataclasses
import sys

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import physics_settings
from ikea_suite.assembly import graph
from ikea_suite.design import rigidity
from ikea_suite.props import catalog
from ikea_suite.props import model_format

PENETRATION_TOL = 0.002   # metres
SETTLE_TIME = 5.0         # seconds
DRIFT_TOL = 0.002         # metres
TURN_TOL = np.radians(0.2)


@dataclasses.dataclass
class Report:
  name: str
  problems: list

  @property
  def ok(self):
    return not self.problems


def penetrations(model, data):
  """(depth, body_a, body_b) of every contact between two different parts, deepest first."""
  mujoco.mj_forward(model, data)
  out = []
  for c in data.contact[:data.ncon]:
    a, b = model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2]
    if a and b and a != b:
      out.append((-c.dist, mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, a),
                  mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b)))
  return sorted(out, reverse=True)


def check(path):
  """Every problem found with one model file (an empty list when it is sound)."""
  name = str(path).rsplit("/", 1)[-1].removesuffix(".xml")
  try:
    spec = model_format.load_spec(str(path))
    model_format.check_buildable(spec)
  except errors.ModelFormatError as e:
    return Report(name, [f"format: {e}"])
  problems = []
  components = graph.components(len(spec.parts), model_format.coinciding_pairs(spec))
  if len(components) > 1:
    names = [[spec.parts[i].name for i in group] for group in components]
    problems.append(f"graph: parts fall into {len(components)} unconnected groups {names}")
  model = mujoco.MjModel.from_xml_path(str(path))
  physics_settings.configure_model(model)
  data = mujoco.MjData(model)
  deep = [p for p in penetrations(model, data) if p[0] > PENETRATION_TOL]
  if deep:
    depth, a, b = deep[0]
    problems.append(f"overlap: {a} and {b} interpenetrate by {depth * 1000:.1f} mm "
                    f"({len(deep)} contacts beyond {PENETRATION_TOL * 1000:.0f} mm)")
  if not problems:   # stability is only meaningful for a sound, connected model
    motion = rigidity.measure(rigidity.assemble(str(path)), SETTLE_TIME)
    if motion.drift > DRIFT_TOL or motion.turn > TURN_TOL:
      problems.append(f"stability: fully connected and standing for {SETTLE_TIME:g} s, a part "
                      f"drifted {motion.drift * 1000:.1f} mm and turned "
                      f"{np.degrees(motion.turn):.2f} deg (limits {DRIFT_TOL * 1000:g} mm, "
                      f"{np.degrees(TURN_TOL):g} deg; worst: {motion.worst_part})")
  return Report(name, problems)


def main(argv=None):
  parser = argparse.ArgumentParser(description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
  parser.add_argument("names", nargs="*", help="furniture names (default: the whole catalog)")
  args = parser.parse_args(argv)
  names = args.names or catalog.names()
  failed = 0
  for name in names:
    report = check(catalog.path_of(name))
    failed += not report.ok
    print(f"{'ok  ' if report.ok else 'FAIL'} {name}" + "".join(f"\n     {p}" for p in report.problems))
  print(f"{len(names) - failed}/{len(names)} models valid")
  return 1 if failed else 0


if __name__ == "__main__":
  sys.exit(main())
