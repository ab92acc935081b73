"""Demonstration datasets: record episodes, write robomimic-style HDF5, replay, export LeRobot v3.

Modules: `mj_state` (the flattened MuJoCo state), `recorder` (one episode as
arrays), `experts` (which scripted policy drives which robot), `hdf5` (the
file layout), `collect` / `replay` / `lerobot` (the console scripts),
`robomimic_env` (robomimic's environment interface, rebuilt from a file's
env_args, for rollouts). Needs the `datasets` extra (h5py; pyarrow and av for
the LeRobot export); the `interop` extra adds lerobot and robomimic, whose own
loaders tests/test_interop_*.py run on these files.
"""
