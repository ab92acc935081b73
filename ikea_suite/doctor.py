"""`ikea-suite-rollout --doctor`: what this installation runs on, and a hint for each problem.

Prints Python, MuJoCo, dm_control and numpy versions, the rendering backend
(MUJOCO_GL) and whether an offscreen OpenGL context can be made, each with a
hint when something is off. Returns the number of problems found.
"""

import importlib.metadata
import os
import sys

SUPPORTED_PYTHON = ((3, 10), (3, 12))   # labmaze, a dm-control dependency, has wheels up to 3.12
MUJOCO_SERIES = (3, 17)                 # dm-control 1.0.50 needs mujoco 3.17.x
DM_CONTROL = "1.0.50"


def _version(package):
  try:
    return importlib.metadata.version(package)
  except importlib.metadata.PackageNotFoundError:
    return None


def _gl_problem():
  """None when an offscreen GL context renders, else the reason it cannot."""
  try:
    from dm_control import mujoco as dm_mujoco
    physics = dm_mujoco.Physics.from_xml_string("<mujoco><worldbody/></mujoco>")
    physics.render(8, 8)
    physics.free()
    return None
  except Exception as e:   # noqa: BLE001 - any failure to render is the answer
    return f"{type(e).__name__}: {e}"


def checks():
  """(name, value, problem or None, hint) for each check."""
  out = []
  python = sys.version_info[:2]
  low, high = SUPPORTED_PYTHON
  out.append(("python", sys.version.split()[0],
              None if low <= python <= high else f"Python {python[0]}.{python[1]} is not supported",
              "use Python 3.10-3.12: e.g. `uv venv --python 3.12` or python3.12 from your "
              "package manager (labmaze, needed by dm-control, has no wheels for newer Pythons)"))
  mujoco = _version("mujoco")
  series = tuple(int(v) for v in mujoco.split(".")[:2]) if mujoco else None
  out.append(("mujoco", mujoco or "missing",
              None if series == MUJOCO_SERIES else "dm-control 1.0.50 needs mujoco 3.17.x",
              'reinstall: pip install -e ".[test]" (pins mujoco>=3.17,<3.18)'))
  dm_control = _version("dm-control")
  out.append(("dm_control", dm_control or "missing",
              None if dm_control == DM_CONTROL else f"ikea_suite is tested with dm-control {DM_CONTROL}",
              f"pip install dm-control=={DM_CONTROL}"))
  numpy = _version("numpy")
  out.append(("numpy", numpy or "missing", None if numpy else "numpy is missing",
              "pip install numpy"))
  backend = os.environ.get("MUJOCO_GL", "(not set: GLFW, needs a display)")
  out.append(("MUJOCO_GL", backend, None, ""))
  problem = _gl_problem()
  out.append(("offscreen GL", "works" if problem is None else "fails", problem,
              "headless Linux: MUJOCO_GL=egl with libEGL (apt-get install libegl1 libgl1); "
              "or MUJOCO_GL=osmesa with libosmesa6; with a display, unset MUJOCO_GL"))
  return out


def main():
  """Prints the report; returns the number of problems."""
  problems = 0
  for name, value, problem, hint in checks():
    status = "ok" if problem is None else "PROBLEM"
    print(f"{name:14s} {value:40s} {status}")
    if problem is not None:
      problems += 1
      print(f"{'':14s} {problem}\n{'':14s} hint: {hint}")
  print(f"{problems} problem(s) found")
  return problems
