"""ikea_suite: long-horizon furniture assembly tasks for MuJoCo and dm_control.

    env = ikea_suite.load("table_four_leg_lack", "cursor", seed=0)
"""

from ikea_suite.errors import ActionError
from ikea_suite.errors import IkeaSuiteError
from ikea_suite.errors import ModelFormatError
from ikea_suite.errors import UnknownNameError
from ikea_suite.suite import DEFAULT_FURNITURE
from ikea_suite.suite import DEFAULT_ROBOT
from ikea_suite.suite import all_environments
from ikea_suite.suite import furniture_names
from ikea_suite.suite import load
from ikea_suite.suite import robot_names


def __getattr__(name):
  # ALL reads the model directory, so it is computed on first use, not at import.
  if name == "ALL":
    return tuple(all_environments())
  raise AttributeError(f"module 'ikea_suite' has no attribute {name!r}")
