"""Robot registry: name -> entity factory and tags."""

import dataclasses

from ikea_suite import errors
from ikea_suite.robots import baxter
from ikea_suite.robots import cursor
from ikea_suite.robots import jaco
from ikea_suite.robots import panda
from ikea_suite.robots import sawyer


@dataclasses.dataclass(frozen=True)
class RobotEntry:
  name: str
  factory: type
  tags: frozenset


_ROBOTS = {}


def register(name, factory, tags=()):
  if name in _ROBOTS:
    raise ValueError(f"robot {name!r} is already registered")
  _ROBOTS[name] = RobotEntry(name, factory, frozenset(tags))


def get(name):
  if not isinstance(name, str) or name not in _ROBOTS:   # a list is no name (nor hashable)
    raise errors.UnknownNameError("robot", name, _ROBOTS)
  return _ROBOTS[name]


def names(tag=None):
  return sorted(n for n, e in _ROBOTS.items() if tag is None or tag in e.tags)


register("cursor", cursor.Cursor, tags=("floating", "bimanual"))
register("sawyer", sawyer.Sawyer, tags=("arm", "single_arm", "paper"))
register("baxter", baxter.Baxter, tags=("arm", "bimanual", "paper"))
register("panda", panda.Panda, tags=("arm", "single_arm"))
register("jaco", jaco.Jaco, tags=("arm", "single_arm"))
