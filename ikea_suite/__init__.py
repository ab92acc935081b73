"""ikea_suite: long-horizon furniture assembly tasks for MuJoCo and dm_control.

    env = ikea_suite.load("table_four_leg_lack", "cursor", seed=0)

On a Linux machine with no display, MUJOCO_GL defaults to "egl" (headless
rendering) unless the user set it; this must happen before dm_control loads.
"""

import os as _os
import sys as _sys

if _sys.platform.startswith("linux") and not _os.environ.get("DISPLAY"):
  _os.environ.setdefault("MUJOCO_GL", "egl")

from ikea_suite.errors import ActionError  # noqa: E402  (after the rendering default)
from ikea_suite.errors import EpisodeStartError  # noqa: E402
from ikea_suite.errors import IkeaSuiteError  # noqa: E402
from ikea_suite.errors import ModelFormatError  # noqa: E402
from ikea_suite.errors import OptionValueError  # noqa: E402
from ikea_suite.errors import UnknownNameError  # noqa: E402
from ikea_suite.errors import UnsupportedPairError  # noqa: E402
from ikea_suite.props.catalog import invalid_models  # noqa: E402
from ikea_suite.props.catalog import register_models  # noqa: E402
from ikea_suite.props.catalog import unregister_models  # noqa: E402
from ikea_suite.suite import DEFAULT_FURNITURE  # noqa: E402
from ikea_suite.suite import DEFAULT_ROBOT  # noqa: E402
from ikea_suite.suite import all_environments  # noqa: E402
from ikea_suite.suite import furniture_names  # noqa: E402
from ikea_suite.suite import load  # noqa: E402
from ikea_suite.suite import robot_names  # noqa: E402

__all__ = [   # the public API; ALL and EXPERT_SUPPORTED are computed on first use (below)
    "ActionError", "EpisodeStartError", "IkeaSuiteError", "ModelFormatError", "OptionValueError", "UnknownNameError",
    "UnsupportedPairError",
    "invalid_models", "register_models", "unregister_models", "DEFAULT_FURNITURE",
    "DEFAULT_ROBOT", "all_environments", "furniture_names", "load", "robot_names"]


def __getattr__(name):
  # ALL reads the model directory, so it is computed on first use, not at import.
  # ALL lists every (furniture, robot) pair that loads; EXPERT_SUPPORTED the subset a
  # scripted expert assembles (the experts' registry, measured in
  # ikea_suite/experts/supported.json).
  if name == "ALL":
    return tuple(all_environments())
  if name == "EXPERT_SUPPORTED":   # (furniture, robot) pairs a scripted expert assembles
    from ikea_suite import experts  # pylint: disable=g-import-not-at-top
    return experts.supported_pairs()
  raise AttributeError(f"module 'ikea_suite' has no attribute {name!r}")
