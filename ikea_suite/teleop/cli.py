"""`ikea-suite-teleop`: drive the Cursor or an arm from the keyboard and record demos.

    ikea-suite-teleop --furniture table_four_leg_lack --robot cursor --out teleop.hdf5
    ikea-suite-teleop --robot sawyer --scale 0.5 --control-mode impedance --out sawyer.hdf5

Opens MuJoCo's passive viewer; keys (ikea_suite/teleop/keymap.py) go to the
viewer window through its key callback, no global keyboard hook. Close the
window to stop; kept episodes are written to --out. On macOS the passive
viewer needs the `mjpython` launcher: `mjpython -m ikea_suite.teleop.cli ...`.
"""

import argparse
import sys
import time

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


def run_viewer(session: session_lib.TeleopSession, env, realtime: bool = True) -> None:
  """Runs `session` in the passive viewer until the window closes."""
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
                      help="furniture size factor (arms assemble at their WORK_SCALE, e.g. 0.5)")
  a = parser.parse_args(argv)
  args = hdf5.env_args(a.furniture, a.robot, load_options(a.robot, a.control_mode, a.scale))
  try:
    env = hdf5.load_env(args)
    session = session_lib.TeleopSession(env, args, seed=a.seed, hold_steps=a.hold_steps)
  except errors.IkeaSuiteError as e:
    print(f"error: {e}", file=sys.stderr)
    return 2
  run_viewer(session, env)
  count = session.write(a.out)
  print(f"wrote {count} episodes to {a.out}")
  return 0


if __name__ == "__main__":
  sys.exit(main())
