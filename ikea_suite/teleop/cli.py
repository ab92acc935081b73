"""`ikea-suite-teleop`: drive the Cursor or an arm from the keyboard and record demos.

    ikea-suite-teleop --furniture table_four_leg_lack --robot cursor --out teleop.hdf5
    ikea-suite-teleop --robot sawyer --scale 0.5 --control-mode impedance --out sawyer.hdf5

Opens MuJoCo's passive viewer; keys (ikea_suite/teleop/keymap.py) go to the
viewer window through its key callback, no global keyboard hook. Close the
window to stop; kept episodes are written to --out. On macOS the passive
viewer needs the `mjpython` launcher: `mjpython -m ikea_suite.teleop.cli ...`.

Without a display (a headless machine, SSH without X forwarding) the command stops
with an IkeaSuiteError that points to the headless API: a
`ikea_suite.teleop.session.TeleopSession` takes key codes from code (`on_key`),
steps (`step`) and writes the same files (`write`).
"""

import argparse
import os
import sys
import time
import warnings

import ikea_suite
from ikea_suite import errors
from ikea_suite.datasets import hdf5
from ikea_suite.teleop import session as session_lib


# The arm control modes whose action layout the keyboard drives (keymap.check_layout).
KEYBOARD_MODES = ("task_space", "impedance")


def load_options(robot: str, control_mode: str | None = None,
                 scale: float | None = None) -> dict:
  """load() options of a session: an arm in a task-space delta mode (task_space unless
  `control_mode` says impedance), at `scale` if given; the Cursor takes no mode."""
  options = {} if scale is None else {"scale": scale}
  if control_mode is not None or robot != "cursor":
    options["control_mode"] = control_mode or KEYBOARD_MODES[0]
  return options


NO_DISPLAY = (
    "ikea-suite-teleop opens MuJoCo's viewer window, which needs a display{why}. On a "
    "machine without one, drive a session from code instead: "
    "ikea_suite.teleop.session.TeleopSession(env, env_args) takes key codes "
    "(session.on_key(code)), steps (session.step()) and writes the demos "
    "(session.write(path)); or forward X11 (ssh -X) or use a virtual display (xvfb-run).")


def check_display() -> None:
  """Raises where the viewer cannot open a window, before it tries: MuJoCo's viewer
  ends the whole process when GLFW finds no display, past any exception handler.

  On Linux a display is named by DISPLAY or WAYLAND_DISPLAY and must let GLFW start;
  on macOS the viewer runs under mjpython, which starts GLFW itself.

  Raises:
    IkeaSuiteError: no display; the message names the headless TeleopSession API.
  """
  if not sys.platform.startswith("linux"):
    return
  if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    raise errors.IkeaSuiteError(NO_DISPLAY.format(
        why=" (neither DISPLAY nor WAYLAND_DISPLAY is set)"))
  import glfw   # mujoco's viewer's own binding
  with warnings.catch_warnings():
    warnings.simplefilter("ignore", glfw.GLFWError)   # the failure is reported below
    started = glfw.init()
  if not started:
    display = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    raise errors.IkeaSuiteError(NO_DISPLAY.format(
        why=f" (GLFW cannot open the display {display!r})"))


def run_viewer(session: session_lib.TeleopSession, env, realtime: bool = True) -> None:
  """Runs `session` in the passive viewer until the window closes (check_display first)."""
  import mujoco.viewer   # needs a display; imported only here

  physics = env.physics
  # Reset never recompiles (ikea_suite.environment), so one window serves every episode.
  viewer = mujoco.viewer.launch_passive(physics.model.ptr, physics.data.ptr,
                                        key_callback=session.on_key)
  dt = env.control_timestep()
  try:
    while viewer.is_running():
      start = time.perf_counter()
      with viewer.lock():
        if session.step():
          session.next_episode()
      viewer.sync()
      if realtime:
        time.sleep(max(0.0, dt - (time.perf_counter() - start)))
  finally:
    viewer.close()


def main(argv=None) -> int:
  parser = argparse.ArgumentParser(description="Keyboard teleoperation with recording.")
  parser.add_argument("--furniture", default=ikea_suite.DEFAULT_FURNITURE)
  parser.add_argument("--robot", default=ikea_suite.DEFAULT_ROBOT)
  parser.add_argument("--out", required=True, help="the .hdf5 file to write")
  parser.add_argument("--seed", type=int, default=0)
  parser.add_argument("--hold-steps", type=int, default=3)
  parser.add_argument("--control-mode", choices=KEYBOARD_MODES, default=None,
                      help="an arm's control mode (default task_space)")
  parser.add_argument("--scale", type=float, default=None,
                      help="furniture size factor (default: the robot's work scale, 1 for the "
                           "Cursor, 0.5 for the arms)")
  a = parser.parse_args(argv)
  args = hdf5.env_args(a.furniture, a.robot, load_options(a.robot, a.control_mode, a.scale))
  try:
    check_display()
    env = hdf5.load_env(args)
    session = session_lib.TeleopSession(env, args, seed=a.seed, hold_steps=a.hold_steps)
    run_viewer(session, env)
  except errors.IkeaSuiteError as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  count = session.write(a.out)
  print(f"wrote {count} episodes to {a.out}")
  return 0


if __name__ == "__main__":
  sys.exit(main())
