"""Every furniture model the project makes, gathered from the family modules."""

import functools

from ikea_suite.design.families import beds
from ikea_suite.design.families import benches
from ikea_suite.design.families import bookcases
from ikea_suite.design.families import boxes
from ikea_suite.design.families import cabinets
from ikea_suite.design.families import chairs
from ikea_suite.design.families import desks
from ikea_suite.design.families import dressers
from ikea_suite.design.families import shelving
from ikea_suite.design.families import stools
from ikea_suite.design.families import tables
from ikea_suite.design.families import tv_units

FAMILY_MODULES = (tables, chairs, stools, benches, bookcases, shelving, cabinets, dressers,
                  tv_units, desks, beds, boxes)


@functools.lru_cache(maxsize=1)
def _all():
  out = [b for module in FAMILY_MODULES for b in module.variants()]
  names = [b.name for b in out]
  duplicates = sorted({n for n in names if names.count(n) > 1})
  if duplicates:
    raise ValueError(f"duplicate furniture names in the families: {duplicates}")
  for b in out:
    if not b.name.startswith(f"{b.category}_{b.family}_"):
      raise ValueError(f"{b.name!r} does not follow category_family_variant "
                       f"({b.category}_{b.family}_...)")
  return tuple(sorted(out, key=lambda b: b.name))


def blueprints():
  """All blueprints, sorted by name; names are unique and read category_family_variant."""
  return list(_all())


def clear_cache():
  """Forgets the gathered blueprints, so the next blueprints() builds them afresh."""
  _all.cache_clear()
