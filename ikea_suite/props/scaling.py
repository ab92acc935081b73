"""Furniture built larger or smaller (the `scale` load option), in memory.

A furniture at scale s is the same design built s times as large from the
same materials: every length (body, geom, site and inertial positions, geom
sizes, mesh vertices through the mesh `scale` attribute) is multiplied by s,
masses by s^3 and inertia tensors by s^5. Connector sites are positions too,
so they scale with the parts. Arms assemble tabletop-sized furniture this way,
as FurnitureBench does with its miniature furniture.

`scaled` scales a copy of the spec's document (each number written back as
repr(float(v) * factor), which reads back as exactly that product) and
validates it into a new FurnitureSpec: everything downstream sees an ordinary
spec, built in memory.
"""

import copy
import xml.etree.ElementTree as ET

from ikea_suite import errors
from ikea_suite.props import furniture_spec
from ikea_suite.props import model_format

MIN_SCALE, MAX_SCALE = 0.2, 2.0


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


def scale_tree(root: ET.Element, scale: float) -> None:
  """Scales a furniture document in place (lengths s, masses s^3, inertias s^5).

  Args:
    root: the <mujoco> element (model_format.read_document's: asset folders absolute).
    scale: size factor.
  """
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


def scaled(spec: furniture_spec.FurnitureSpec, scale: float) -> furniture_spec.FurnitureSpec:
  """The furniture of `spec` built `scale` times as large (`spec` itself at scale 1).

  Args:
    spec: a FurnitureSpec (catalog.spec, model_format.load_spec).
    scale: size factor against `spec`, checked with check_scale.
  Returns:
    A FurnitureSpec whose `scale` is spec.scale * scale, read from a scaled copy of
    spec.document.
  """
  scale = check_scale(scale)
  if scale == 1.0:
    return spec
  document = copy.deepcopy(spec.document)
  scale_tree(document, scale)
  return model_format.spec_from_document(document, spec.path, scale=spec.scale * scale)
