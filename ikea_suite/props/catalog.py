"""The furniture catalog: every model file under models/furniture, with tags from its metadata."""

import dataclasses
import functools

from ikea_suite import errors
from ikea_suite.props import model_format
from ikea_suite.props import paths


@dataclasses.dataclass(frozen=True)
class Entry:
  name: str
  path: str
  category: str
  num_parts: int
  tags: frozenset


@functools.lru_cache(maxsize=1)
def entries():
  """name -> Entry for every committed furniture model, sorted by name."""
  out = {}
  for path in sorted(paths.furniture_dir().glob("*.xml")):
    spec = model_format.load_spec(str(path))
    category = spec.metadata.get("category", "uncategorized")
    tags = frozenset({category, spec.metadata.get("family", ""), f"parts_{len(spec.parts)}"} - {""})
    out[path.stem] = Entry(path.stem, str(path), category, len(spec.parts), tags)
  return out


def names(tag=None, min_parts=None, max_parts=None):
  """Furniture names, optionally those with `tag` and a part count in range."""
  return [e.name for e in entries().values()
          if (tag is None or tag in e.tags)
          and (min_parts is None or e.num_parts >= min_parts)
          and (max_parts is None or e.num_parts <= max_parts)]


def categories():
  return sorted({e.category for e in entries().values()})


def path_of(name):
  if name not in entries():
    raise errors.UnknownNameError("furniture", name, entries())
  return entries()[name].path
