"""Shared test set-up: headless rendering before dm_control loads, the one GL probe, and the
property-based tests' settings profiles.

Hypothesis profiles (tests/test_fuzz.py): "ci", the default, tries a few hundred examples
in all, the same ones on every run (derandomized), so CI stays within its time and never
flakes; `pytest tests/test_fuzz.py --hypothesis-profile=long` tries twenty times as many,
new ones each run, for a long local search.

A test that renders takes the `gl` fixture. It skips only when the probe
cannot make an offscreen OpenGL context, with the probe's reason. The run
ends with a line counting the rendering tests that ran; with CI=true, a run
in which every rendering test skipped on a machine that has libEGL fails,
because the rendering paths then went untested without anyone noticing.
"""

import collections
import ctypes.util
import functools
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import pytest  # noqa: E402
from hypothesis import HealthCheck  # noqa: E402
from hypothesis import settings  # noqa: E402

# Loading an environment takes 0.3-1 s: no per-example deadline, and no complaint that
# generating data is slow next to it.
_SLOW = [HealthCheck.too_slow, HealthCheck.data_too_large]
settings.register_profile("ci", max_examples=100, deadline=None, derandomize=True,
                          suppress_health_check=_SLOW, print_blob=True)
settings.register_profile("long", max_examples=2000, deadline=None,
                          suppress_health_check=_SLOW, print_blob=True)
settings.load_profile("ci")

_RENDERING = collections.Counter()


@functools.lru_cache(maxsize=None)
def gl_problem():
  """None when an offscreen GL context can render, else why it cannot."""
  from dm_control import mujoco as dm_mujoco
  try:
    physics = dm_mujoco.Physics.from_xml_string("<mujoco><worldbody/></mujoco>")
    physics.render(8, 8)
  except Exception as error:  # noqa: BLE001 - the probe's answer is the reason itself
    return (f"no offscreen OpenGL context with MUJOCO_GL={os.environ.get('MUJOCO_GL')} "
            f"({type(error).__name__}: {error})")
  physics.free()
  return None


@pytest.fixture(scope="session")
def gl():
  """Skips the test, with the probe's reason, when no offscreen GL context can be made."""
  problem = gl_problem()
  if problem:
    pytest.skip(problem)


def pytest_collection_modifyitems(items):
  for item in items:
    if "gl" in getattr(item, "fixturenames", ()):
      item.add_marker("rendering")


def pytest_configure(config):
  config.addinivalue_line("markers", "rendering: the test renders images (uses the gl fixture)")


def pytest_runtest_logreport(report):
  if "rendering" not in report.keywords:
    return
  if report.when == "setup" and report.skipped:
    _RENDERING["skipped"] += 1
  elif report.when == "call":
    _RENDERING["ran"] += 1


def pytest_terminal_summary(terminalreporter):
  if _RENDERING:
    line = f"rendering tests: {_RENDERING['ran']} ran, {_RENDERING['skipped']} skipped"
    if _RENDERING["skipped"]:
      line += f" ({gl_problem()})"
    terminalreporter.write_line(line)


def pytest_sessionfinish(session):
  if (os.environ.get("CI") == "true" and _RENDERING["skipped"] and not _RENDERING["ran"]
      and ctypes.util.find_library("EGL")):
    print(f"\nCI: every rendering test skipped although libEGL is installed: {gl_problem()}")
    session.exitstatus = 1
