"""The furniture catalog: every model file under models/furniture, with tags from its metadata.

Names read category_family_variant (e.g. table_four_leg_lack). Each entry
carries its category, family and variant, part and connection counts, its
assembled mass in kg (as MuJoCo compiles the file), and tags: the category, the family, `parts_N`, and `concave` when some part
collides through convex pieces of a decomposed mesh.
"""

import dataclasses
import functools
import pathlib

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
  family: str = ""
  variant: str = ""
  description: str = ""
  num_connections: int = 0    # connections an assembly makes: parts - 1
  mass: float = 0.0           # kg, all parts together


def _has_mesh_collision(spec):
  return any(g.get("type") == "mesh" and g.get("contype") != "0"
             for p in spec.parts for g in p.element.iter("geom"))


@functools.lru_cache(maxsize=1)
def entries():
  """name -> Entry for every committed furniture model, sorted by name."""
  out = {}
  for path in sorted(paths.furniture_dir().glob("*.xml")):
    spec = model_format.load_spec(str(path))
    meta = spec.metadata
    category = meta.get("category", "uncategorized")
    tags = {category, meta.get("family", ""), f"parts_{len(spec.parts)}"}
    if _has_mesh_collision(spec):
      tags.add("concave")
    out[path.stem] = Entry(path.stem, str(path), category, len(spec.parts),
                           frozenset(tags - {""}), meta.get("family", ""), meta.get("variant", ""),
                           meta.get("description", ""), len(spec.parts) - 1, spec.mass)
  return out


def names(tag=None, min_parts=None, max_parts=None, category=None):
  """Furniture names, optionally those with `tag`, in `category`, with a part count in range."""
  return [e.name for e in entries().values()
          if (tag is None or tag in e.tags)
          and (category is None or e.category == category)
          and (min_parts is None or e.num_parts >= min_parts)
          and (max_parts is None or e.num_parts <= max_parts)]


def categories():
  return sorted({e.category for e in entries().values()})


def families(category=None):
  """Sorted (category, family) pairs, optionally of one category."""
  return sorted({(e.category, e.family) for e in entries().values()
                 if category is None or e.category == category})


def counts():
  """category -> number of models."""
  out = {}
  for e in entries().values():
    out[e.category] = out.get(e.category, 0) + 1
  return dict(sorted(out.items()))


def representatives(smallest=False):
  """One model per category: the one with the median part count, or with `smallest` the one
  with the fewest parts (ties: first by name).

  A small, stable subset that still covers every category, for tests and CI
  runs that cannot afford the whole catalog.
  """
  out = []
  for category in categories():
    members = sorted((entries()[n] for n in names(category=category)),
                     key=lambda e: (e.num_parts, e.name))
    out.append(members[0 if smallest else (len(members) - 1) // 2].name)
  return out


def path_of(name):
  """The model file of a catalog name; a path to a model file is returned as it is."""
  if str(name).endswith(".xml") and pathlib.Path(name).is_file():
    return str(name)
  if name not in entries():
    raise errors.UnknownNameError("furniture", name, entries())
  return entries()[name].path
