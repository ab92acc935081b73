"""Keyboard teleoperation in MuJoCo's passive viewer, recording demonstrations.

`keymap` turns key presses into the task's action vector, `session` steps
the environment and records episodes (both headless and tested), `cli` runs
them in `mujoco.viewer.launch_passive` (`ikea-suite-teleop`).
"""
