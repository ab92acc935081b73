"""Plain data describing one furniture model, as read from its MJCF file.

Nothing here needs a simulator: the loader fills these from XML, the prop and
the task turn them into entities, welds and numpy arrays. A FurnitureSpec is
read once (props/catalog.spec) and handed down as it is, scaled in memory
(props/scaling.py), to the prop, the task, the sequencer and the experts.
"""

import dataclasses
import xml.etree.ElementTree as ET

import numpy as np

from ikea_suite import geometry
from ikea_suite.assembly import mating


@dataclasses.dataclass(frozen=True)
class ConnectorSpec:
  """A connector: a site on a part, its type and the type it mates with.

  The site frame's z axis is the connector's up vector and its x axis the
  forward vector. `twists` are the allowed rotations (radians) about up between
  mating frames; an empty tuple means any twist is allowed.
  """
  name: str
  part: str
  type: str
  mates: str
  twists: tuple
  pos: np.ndarray   # in the part frame
  rot: np.ndarray   # 3x3 rotation, in the part frame

  @property
  def any_twist(self):
    return not self.twists


@dataclasses.dataclass(frozen=True)
class PartSpec:
  """A rigid part: a top-level body of the file, in its assembled pose."""
  name: str
  pos: np.ndarray            # assembled position in the furniture frame
  rot: np.ndarray            # assembled 3x3 rotation
  element: ET.Element        # the <body> element, children copied into the part entity
  bounds: np.ndarray         # (2, 3) axis-aligned bounds of its collision geoms, part frame
  mass: float = 0.0          # kg, as MuJoCo compiles it (the body's <inertial> when it has one)

  def assembled_corners(self):
    """(8, 3) corners of its collision bounds in the assembled (furniture) frame."""
    return geometry.box_corners(*self.bounds) @ self.rot.T + self.pos

  def collision_geoms(self):
    """Its <geom> elements that collide (collision_geoms)."""
    return collision_geoms(self.element)


def collision_geoms(element):
  """The <geom> elements under `element` that collide: all but the visual ones (contype
  and conaffinity 0)."""
  return [geom for geom in element.iter("geom")
          if not (geom.get("contype") == "0" and geom.get("conaffinity") == "0")]


# Compared and hashed by identity: sequence.plan keeps its results per spec object.
@dataclasses.dataclass(frozen=True, eq=False)
class FurnitureSpec:
  """A furniture model: parts, connectors and the file's metadata."""
  name: str
  path: str                 # the model file it was read from
  parts: tuple
  connectors: tuple
  metadata: dict
  assets: ET.Element        # the file's <asset> element (may be empty)
  compiler: dict            # attributes of <compiler>, e.g. meshdir (folders absolute)
  document: ET.Element      # the whole <mujoco> element the rest was read from, as scaled
  scale: float = 1.0        # size factor of `document` against the file (props/scaling.py)

  @property
  def mass(self):
    """Total mass of the assembled furniture, kg."""
    return sum(p.mass for p in self.parts)

  def extents(self):
    """(3,) size in metres of the assembled furniture's axis-aligned box (collision geoms)."""
    corners = np.concatenate([p.assembled_corners() for p in self.parts])
    return corners.max(0) - corners.min(0)

  def part_index(self, name):
    return [p.name for p in self.parts].index(name)

  def assembled_connector_pairs(self):
    """(a, b) connector index pairs, a < b, that mate and coincide in the assembled pose."""
    pose = {p.name: (p.pos, p.rot) for p in self.parts}
    return mating.coinciding_connector_pairs(self.connectors, pose)

  def mating_part_pairs(self):
    """Sorted pairs (i, j), i < j, of parts with at least one mating connector pair."""
    index = {p.name: i for i, p in enumerate(self.parts)}
    return sorted({tuple(sorted((index[a.part], index[b.part])))
                   for a in self.connectors for b in self.connectors if mating.types_mate(a, b)})
