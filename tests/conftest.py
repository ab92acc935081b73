"""Shared test set-up: headless rendering before dm_control loads."""

import os

os.environ.setdefault("MUJOCO_GL", "egl")
