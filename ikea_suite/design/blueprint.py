"""Blueprints: furniture described in Python before it is written as MJCF.

A family function builds a Blueprint by placing parts in their assembled pose
and calling `connect`, which puts a connector on each of two parts at one
shared world frame, so mating frames coincide by construction.
"""

import dataclasses
import math

import numpy as np

from ikea_suite import geometry


@dataclasses.dataclass
class Geom:
  type: str                      # box, cylinder, capsule, sphere, ellipsoid or mesh
  size: tuple = ()
  pos: tuple = (0.0, 0.0, 0.0)
  rot: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(3))
  material: str = "wood_light"
  mesh: str = ""                 # asset name when type == "mesh"
  collide: bool = True           # False: a visual-only geom
  visible: bool = True           # False: a collision-only geom, hidden (group 3)
  # What it is made of (construction.Construction); None: it adds no mass, because
  # it only shows or only collides for a shape whose mass another geom carries.
  construction: object = None


@dataclasses.dataclass
class Connector:
  name: str
  pos: np.ndarray                # in the part frame
  rot: np.ndarray
  type: str
  mates: str
  twists_deg: tuple


@dataclasses.dataclass
class Part:
  name: str
  pos: np.ndarray
  rot: np.ndarray = dataclasses.field(default_factory=lambda: np.eye(3))
  geoms: list = dataclasses.field(default_factory=list)
  connectors: list = dataclasses.field(default_factory=list)

  def to_local(self, world_pos, world_rot):
    return self.rot.T @ (np.asarray(world_pos, float) - self.pos), self.rot.T @ world_rot


@dataclasses.dataclass
class Blueprint:
  """A whole furniture model before it is written out."""
  name: str
  category: str
  family: str
  variant: str
  description: str
  parts: list = dataclasses.field(default_factory=list)
  meshes: dict = dataclasses.field(default_factory=dict)   # asset name -> trimesh.Trimesh
  metadata: dict = dataclasses.field(default_factory=dict)  # extra key -> value, file metadata

  def add_part(self, name, pos, rot=None, geoms=()):
    part = Part(name=name, pos=np.asarray(pos, float),
                rot=np.eye(3) if rot is None else np.asarray(rot, float), geoms=list(geoms))
    self.parts.append(part)
    return part

  def part(self, name):
    return next(p for p in self.parts if p.name == name)

  def connect(self, part_a, part_b, world_pos, up, forward, type_a, type_b, twists_deg=(0,)):
    """Adds mating connectors to two parts at one world frame (up = z, forward = x)."""
    up = np.asarray(up, float) / np.linalg.norm(up)
    forward = np.asarray(forward, float)
    forward = forward - up * (forward @ up)
    forward /= np.linalg.norm(forward)
    rot = geometry.frame_from_axes(up, forward)
    for part, own, other in ((part_a, type_a, type_b), (part_b, type_b, type_a)):
      pos, local_rot = part.to_local(world_pos, rot)
      name = f"{part.name}_{own}_{len(part.connectors)}"
      part.connectors.append(Connector(name, pos, local_rot, own, other, tuple(twists_deg)))


def rot_x(angle):
  c, s = math.cos(angle), math.sin(angle)
  return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(angle):
  c, s = math.cos(angle), math.sin(angle)
  return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


rot_z = geometry.rot_z   # one definition, re-exported for the family code
