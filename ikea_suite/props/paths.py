"""Where the committed model files live, for source checkouts and installs alike."""

import importlib.resources
import pathlib


def models_dir():
  return pathlib.Path(str(importlib.resources.files("ikea_suite.models")))


def furniture_dir():
  return models_dir() / "furniture"
