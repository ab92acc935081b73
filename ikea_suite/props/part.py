"""One rigid furniture part as a composer entity, attached to the arena as a free body.

The part's `<inertial>` (its true mass from its construction, see
ikea_suite.design.construction) cannot sit in an entity's worldbody, so the
entity keeps its attributes and the furniture puts them on the free body it
attaches the part to (`Furniture.attach_to`). Without that the body would get
geom-derived inertia at MuJoCo's default density instead.
"""

import pathlib
import xml.etree.ElementTree as ET

from dm_control import composer
from dm_control import mjcf

from ikea_suite.props import model_format


class Part(composer.Entity):
  """A part's geoms and connector sites in the part frame; the free joint comes from the arena."""

  def _build(self, spec, furniture_spec):
    self._mjcf_root = mjcf.from_xml_string(
        ET.tostring(model_format.part_xml(spec, furniture_spec), encoding="unicode"),
        model_dir=str(pathlib.Path(furniture_spec.path).parent))
    self._spec = spec
    inertial = spec.element.find("inertial")
    self._inertial = dict(inertial.attrib) if inertial is not None else None

  @property
  def mjcf_model(self):
    return self._mjcf_root

  @property
  def spec(self):
    return self._spec

  @property
  def inertial(self):
    """The attributes of the part's <inertial> in its file (mass, pos, fullinertia, ...),
    or None when the file leaves inertia to its geoms."""
    return None if self._inertial is None else dict(self._inertial)

  @property
  def geoms(self):
    return self._mjcf_root.worldbody.find_all("geom")
