"""Demonstration datasets: record episodes, write robomimic-style HDF5, replay, export LeRobot v3.

Modules: `mj_state` (the flattened MuJoCo state), `recorder` (one episode as
arrays), `experts` (which scripted policy drives which robot), `hdf5` (the
file layout), `collect` / `replay` / `lerobot` (the console scripts). Needs
the `datasets` extra (h5py; pyarrow and av for the LeRobot export).
"""
