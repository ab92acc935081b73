"""Every furniture model the project makes, gathered from the family modules."""

from ikea_suite.design.families import boxes
from ikea_suite.design.families import chairs
from ikea_suite.design.families import shelves
from ikea_suite.design.families import stools
from ikea_suite.design.families import tables

FAMILY_MODULES = (tables, stools, chairs, shelves, boxes)


def blueprints():
  """All blueprints, sorted by name; names must be unique."""
  out = [b for module in FAMILY_MODULES for b in module.variants()]
  names = [b.name for b in out]
  duplicates = sorted({n for n in names if names.count(n) > 1})
  if duplicates:
    raise ValueError(f"duplicate furniture names in the families: {duplicates}")
  return sorted(out, key=lambda b: b.name)
