"""Checks that every furniture model is sound: `python -m ikea_suite.design.validate [NAMES]`.

For each model file:
  format      it loads in plain MuJoCo and passes the furniture-format loader,
              which also requires every connector to have a compatible mate
              that coincides with it in the assembled pose;
  graph       the parts form one connected assembly graph;
  overlap     no two parts interpenetrate in the assembled pose by more than
              `PENETRATION_TOL`;
  stability   with every weld of the file active, the assembled furniture
              stands on the floor for `SETTLE_TIME` seconds: no part moves
              more than `DRIFT_TOL` (soft welds settle a little under load) or
              turns more than `TURN_TOL`, and over the last second nothing
              creeps more than `CREEP_TOL` (it has come to rest).
"""

import argparse
import dataclasses
import sys

import mujoco
import numpy as np

from ikea_suite import errors
from ikea_suite import geometry
from ikea_suite.props import catalog
from ikea_suite.props import model_format

PENETRATION_TOL = 0.002   # metres
SETTLE_TIME = 2.0         # seconds
DRIFT_TOL = 0.03          # metres
CREEP_TOL = 0.003         # metres, over the last second
TURN_TOL = np.radians(3)


@dataclasses.dataclass
class Report:
  name: str
  problems: list

  @property
  def ok(self):
    return not self.problems


def graph_components(num_parts, pairs):
  """Connected components (lists of part indices) of the assembly graph."""
  parent = list(range(num_parts))
  def find(i):
    while parent[i] != i:
      parent[i] = parent[parent[i]]
      i = parent[i]
    return i
  for i, j in pairs:
    parent[find(i)] = find(j)
  groups = {}
  for i in range(num_parts):
    groups.setdefault(find(i), []).append(i)
  return sorted(groups.values())


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


def settle(model, data, seconds=SETTLE_TIME):
  """Simulates with the file's welds active; returns per-part drift (m), turn (rad) and the
  creep (m) over the last second."""
  mujoco.mj_forward(model, data)
  pos0, quat0 = data.xpos.copy(), data.xquat.copy()
  steps = int(round(seconds / model.opt.timestep))
  last_second = steps - int(round(1.0 / model.opt.timestep))
  for step in range(steps):
    if step == last_second:
      pos1 = data.xpos.copy()
    mujoco.mj_step(model, data)
  drift = np.linalg.norm(data.xpos - pos0, axis=1)
  creep = np.linalg.norm(data.xpos - pos1, axis=1)
  turn = np.array([np.linalg.norm(geometry.mat_to_axis_angle(
      geometry.quat_to_mat(q1) @ geometry.quat_to_mat(q0).T)) for q0, q1 in zip(quat0, data.xquat)])
  return drift[1:], turn[1:], creep[1:]


def check(path):
  """Every problem found with one model file (an empty list when it is sound)."""
  name = str(path).rsplit("/", 1)[-1].removesuffix(".xml")
  try:
    spec = model_format.load_spec(str(path))
  except errors.ModelFormatError as e:
    return Report(name, [f"format: {e}"])
  problems = []
  components = graph_components(len(spec.parts), model_format.coinciding_pairs(spec))
  if len(components) > 1:
    names = [[spec.parts[i].name for i in group] for group in components]
    problems.append(f"graph: parts fall into {len(components)} unconnected groups {names}")
  model = mujoco.MjModel.from_xml_path(str(path))
  data = mujoco.MjData(model)
  deep = [p for p in penetrations(model, data) if p[0] > PENETRATION_TOL]
  if deep:
    depth, a, b = deep[0]
    problems.append(f"overlap: {a} and {b} interpenetrate by {depth * 1000:.1f} mm "
                    f"({len(deep)} contacts beyond {PENETRATION_TOL * 1000:.0f} mm)")
  if not np.all(model.eq_active0) or model.neq < len(spec.parts) - 1:
    problems.append(f"stability: the file has {model.neq} active welds for {len(spec.parts)} parts")
  drift, turn, creep = settle(model, data)
  if drift.max() > DRIFT_TOL or turn.max() > TURN_TOL or creep.max() > CREEP_TOL:
    worst = int(np.argmax(drift))
    problems.append(f"stability: after {SETTLE_TIME:g} s a part moved {drift.max() * 100:.1f} cm, "
                    f"turned {np.degrees(turn.max()):.1f} deg and still creeps "
                    f"{creep.max() * 1000:.1f} mm/s (worst: {model.body(worst + 1).name})")
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
