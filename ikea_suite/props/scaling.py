"""Physically scaled copies of furniture model files (the `scale` load option).

A furniture at scale s is the same design built s times as large from the
same materials: every length (body, geom, site and inertial positions, geom
sizes, mesh vertices through the mesh `scale` attribute) is multiplied by s,
masses by s^3 and inertia tensors by s^5. Connector sites are positions too,
so they scale with the parts. Arms assemble tabletop-sized furniture this way,
as FurnitureBench does with its miniature furniture.

The scaled file is written once per (file, scale) into a cache folder next to
nothing else, with mesh and texture folders made absolute, and read by the
ordinary loader: everything downstream sees an ordinary model file.
"""

import hashlib
import os
import pathlib
import tempfile
import xml.etree.ElementTree as ET

from ikea_suite import errors

MIN_SCALE, MAX_SCALE = 0.2, 2.0
_CACHE = pathlib.Path(tempfile.gettempdir()) / "ikea_suite_scaled"


def check_scale(scale: float) -> float:
  """The scale as a float; OptionValueError outside [MIN_SCALE, MAX_SCALE].

  Args:
    scale: size factor of the furniture (1 = as designed).
  Returns:
    float(scale).
  """
  try:
    value = float(scale)
  except (TypeError, ValueError):
    value = None
  if value is None or isinstance(scale, bool) or not MIN_SCALE <= value <= MAX_SCALE:
    raise errors.OptionValueError(
        f"scale must be a number from {MIN_SCALE} to {MAX_SCALE} (1 = full size), got {scale!r}")
  return value


def _times(text, factor):
  return " ".join(repr(float(v) * factor) for v in text.split())


def scale_tree(root: ET.Element, scale: float, model_dir: pathlib.Path) -> None:
  """Scales a parsed furniture file in place (lengths s, masses s^3, inertias s^5).

  Args:
    root: the <mujoco> element.
    scale: size factor.
    model_dir: folder of the original file; relative mesh/texture folders become absolute.
  """
  compiler = root.find("compiler")
  if compiler is None:
    compiler = ET.SubElement(root, "compiler")
  for key in ("meshdir", "texturedir", "assetdir"):
    if compiler.get(key) is not None and not os.path.isabs(compiler.get(key)):
      compiler.set(key, str((model_dir / compiler.get(key)).resolve()))
  if compiler.get("meshdir") is None and compiler.get("assetdir") is None:
    compiler.set("meshdir", str(model_dir.resolve()))
  for mesh in root.iter("mesh"):
    mesh.set("scale", _times(mesh.get("scale", "1 1 1"), scale))
  worldbody = root.find("worldbody")
  for element in worldbody.iter():
    if element.tag == "geom" and element.get("type") == "plane":
      continue   # the file's floor stays as it is
    if element.tag in ("body", "geom", "site", "inertial", "camera", "joint") and element.get("pos"):
      element.set("pos", _times(element.get("pos"), scale))
    if element.tag in ("geom", "site"):
      for key in ("size", "fromto"):
        if element.get(key):
          element.set(key, _times(element.get(key), scale))
    if element.tag == "geom" and element.get("mass"):
      element.set("mass", _times(element.get("mass"), scale ** 3))
    if element.tag == "inertial":
      element.set("mass", _times(element.get("mass"), scale ** 3))
      for key in ("fullinertia", "diaginertia"):
        if element.get(key):
          element.set(key, _times(element.get(key), scale ** 5))


def scaled_path(path: str, scale: float) -> str:
  """Path of the model file `path` scaled by `scale` (the file itself at scale 1).

  Args:
    path: a furniture model file.
    scale: size factor, checked with check_scale.
  Returns:
    The path of a model file of the scaled furniture.
  """
  scale = check_scale(scale)
  if scale == 1.0:
    return str(path)
  source = pathlib.Path(path)
  text = source.read_text()
  digest = hashlib.sha1(f"{source.resolve()}|{scale!r}|{text}".encode()).hexdigest()[:12]
  target = _CACHE / f"{source.stem}_x{scale:g}_{digest}.xml"
  if not target.exists():
    root = ET.fromstring(text)
    scale_tree(root, scale, source.parent)
    _CACHE.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=_CACHE, suffix=".tmp", delete=False) as handle:
      handle.write(ET.tostring(root, encoding="unicode"))
    os.replace(handle.name, target)   # atomic: parallel processes may write the same file
  return str(target)
