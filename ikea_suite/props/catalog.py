"""The furniture catalog: every model file under models/furniture, with tags from its metadata.

Names read category_family_variant (e.g. table_four_leg_lack). Each entry
carries its category, family and variant, part and connection counts, its
assembled mass in kg (as MuJoCo compiles the file), and tags: the category, the family, `parts_N`, and `concave` when some part
collides through convex pieces of a decomposed mesh.

A user adds a directory of model files with `register_models(directory)`;
its models join the catalog under their file stems. A file that fails the
format loader or dm_control's build of its parts (model_format.check_buildable),
or whose name is already taken, affects only itself: it is left out of the
catalog and listed by `invalid_models()` with the reason. (The bundled models
pass both by construction, pinned by tests, so only their format is read here.)

`spec(name, scale)` hands out the FurnitureSpec the scan read (scaled in
memory where asked): load() builds a furniture from it without reading the
file again.
"""

import dataclasses
import functools
import os
import pathlib

from ikea_suite import errors
from ikea_suite.props import furniture_spec
from ikea_suite.props import model_format
from ikea_suite.props import paths
from ikea_suite.props import scaling


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
  return any(g.get("type") == "mesh" for p in spec.parts for g in p.collision_geoms())


@dataclasses.dataclass(frozen=True)
class InvalidModel:
  """A model file left out of the catalog, and why."""
  name: str
  path: str
  error: errors.ModelFormatError

  @property
  def reason(self):
    return self.error.problem


_registered = []   # user directories, in the order they were registered


def _read_checked(path):
  """The spec of a user's model file, checked as load() will build it."""
  spec = model_format.load_spec(str(path))
  model_format.check_buildable(spec)
  return spec


def _entry(path, spec):
  meta = spec.metadata
  category = meta.get("category", "uncategorized")
  tags = {category, meta.get("family", ""), f"parts_{len(spec.parts)}"}
  if _has_mesh_collision(spec):
    tags.add("concave")
  return Entry(path.stem, str(path), category, len(spec.parts), frozenset(tags - {""}),
               meta.get("family", ""), meta.get("variant", ""), meta.get("description", ""),
               len(spec.parts) - 1, spec.mass)


@functools.lru_cache(maxsize=1)
def _scan():
  """(name -> Entry, [InvalidModel], name -> FurnitureSpec) over the committed models and
  every registered directory."""
  valid, invalid, specs = {}, [], {}
  for directory in [paths.furniture_dir(), *_registered]:
    read = _read_checked if directory != paths.furniture_dir() else model_format.load_spec
    for path in sorted(directory.glob("*.xml")):
      try:
        if path.stem in valid:
          raise errors.ModelFormatError(path, "<file>", f"the name {path.stem!r} is already "
                                        f"taken by {valid[path.stem].path}")
        specs[path.stem] = read(path)
        valid[path.stem] = _entry(path, specs[path.stem])
      except errors.ModelFormatError as e:
        invalid.append(InvalidModel(path.stem, str(path), e))
  return dict(sorted(valid.items())), invalid, specs


def entries():
  """name -> Entry for every valid committed or registered furniture model, sorted by name."""
  return _scan()[0]


def invalid_models() -> list[InvalidModel]:
  """Model files left out of the catalog, each with its ModelFormatError and reason.

  Returns:
    A list of InvalidModel (name, path, error, reason), in directory then file order.
  """
  return list(_scan()[1])


def register_models(directory: str | os.PathLike) -> list[str]:
  """Adds every model file (*.xml) of `directory` to the catalog, for names and load().

  Args:
    directory: a folder of model files in the furniture format (e.g. the output of
      ikea-suite-import-original). Registering it again rescans it (new or changed files).

  Returns:
    The sorted names of the directory's valid models; see invalid_models() for the rest.

  Raises:
    ModelFormatError: `directory` is not a directory.
  """
  directory = pathlib.Path(directory).expanduser().resolve()
  if not directory.is_dir():
    raise errors.ModelFormatError(directory, "<directory>", "no such directory to register")
  added = directory not in _registered
  if added:
    _registered.append(directory)
  _scan.cache_clear()   # files may have changed since they were read
  try:
    entries()
  except Exception:
    # Reading files cannot fail outside ModelFormatError (load_spec); should the directory
    # itself be unreadable, the catalog is left as it was.
    if added:
      _registered.remove(directory)
    _scan.cache_clear()
    raise
  return sorted(name for name, e in entries().items() if pathlib.Path(e.path).parent == directory)


def unregister_models(directory: str | os.PathLike) -> None:
  """Removes a directory added by register_models (no effect if it was never added).

  Args:
    directory: the folder given to register_models.
  """
  directory = pathlib.Path(directory).expanduser().resolve()
  if directory in _registered:
    _registered.remove(directory)
    _scan.cache_clear()


def registered_directories() -> list[pathlib.Path]:
  """The user directories added by register_models, in order."""
  return list(_registered)


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


def _looks_like_path(name):
  return isinstance(name, os.PathLike) or (
      isinstance(name, str) and (name.endswith(".xml") or os.sep in name))


def path_of(name: str | os.PathLike) -> str:
  """The model file of a catalog name, or `name` itself when it is a path to a model file.

  Args:
    name: a catalog name (see names()) or the path (str or PathLike) of a model file.

  Returns:
    The model file's path, as a string.

  Raises:
    ModelFormatError: the path is not a valid model file, or the name is one of
      invalid_models() (the error says why).
    UnknownNameError: anything else that is not a catalog name.
  """
  return spec(name).path if _looks_like_path(name) else _entry_of(name).path


def spec(name: str | os.PathLike, scale: float = 1.0) -> furniture_spec.FurnitureSpec:
  """The furniture of a catalog name or model file, read and validated, at `scale`.

  A catalog name gives the spec the catalog read (one object, shared: nothing changes a
  spec); a path is read now. At a scale other than 1 a scaled spec is built in memory.

  Args:
    name: a catalog name (see names()) or the path (str or PathLike) of a model file.
    scale: size factor (scaling.check_scale): lengths x scale, masses x scale^3.

  Returns:
    The FurnitureSpec.

  Raises:
    ModelFormatError: the path is not a valid model file, or the name is one of
      invalid_models() (the error says why).
    UnknownNameError: anything else that is not a catalog name.
    OptionValueError: a scale out of range.
  """
  if _looks_like_path(name):
    found = _read_checked(pathlib.Path(name).expanduser())
  else:
    found = _scan()[2][_entry_of(name).name]
  return scaling.scaled(found, scale)


def _entry_of(name):
  """The Entry of a catalog name; raises as path_of does for a name that is not one."""
  if isinstance(name, str) and name in entries():   # a list is no name (nor hashable)
    return entries()[name]
  broken = [m for m in _scan()[1] if m.name == name]
  if broken:
    raise broken[0].error
  raise errors.UnknownNameError("furniture", name, entries())
