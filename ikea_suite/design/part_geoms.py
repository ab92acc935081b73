"""Geoms of one part: a trimesh visual mesh plus collision primitives or coacd pieces.

A board or a round leg looks bevelled or round through a visual-only mesh and
collides through a MuJoCo primitive of the same extents, which is fast and
exact. A concave shape collides through its convex pieces (see decompose).
Meshes are registered on the blueprint under a content-hash name, so
identical parts share one mesh file.

Every helper takes the part's `construction` (construction.py) and puts it on
exactly one geom of the shape, the one whose extents the construction is
measured against: the primitive of a board or leg, the whole visual mesh of a
concave shape (its convex pieces overlap, so they would count some volume twice).
"""

import hashlib

import numpy as np

from ikea_suite.design import blueprint as bp
from ikea_suite.design import decompose
from ikea_suite.design import shapes

_IDENTITY = np.eye(3)


def register_mesh(furniture, mesh, prefix):
  """Adds `mesh` to the blueprint's assets; returns its content-derived asset name."""
  digest = hashlib.sha1(np.round(mesh.vertices, 7).astype("<f8").tobytes()
                        + np.asarray(mesh.faces).astype("<i8").tobytes()).hexdigest()[:12]
  name = f"{prefix}_{digest}"
  furniture.meshes.setdefault(name, mesh)
  return name


def _visual(furniture, mesh, prefix, material, pos, rot, construction=None):
  return bp.Geom("mesh", pos=tuple(pos), rot=rot, material=material,
                 mesh=register_mesh(furniture, mesh, prefix), collide=False,
                 construction=construction)


def board(furniture, size, material, construction, pos=(0, 0, 0), rot=_IDENTITY, bevel=0.003):
  """A flat board of full extents `size`: bevelled mesh to see, a box to collide."""
  half = tuple(s / 2 for s in size)
  return [_visual(furniture, shapes.bevelled_board(size, bevel), "board", material, pos, rot),
          bp.Geom("box", half, pos=tuple(pos), rot=rot, material=material, visible=False,
                  construction=construction)]


def round_leg(furniture, radius, length, material, construction, pos=(0, 0, 0), rot=_IDENTITY):
  """A round leg along the part's z: a 16-sided mesh to see, a cylinder to collide."""
  return [_visual(furniture, shapes.round_leg(radius, length), "leg", material, pos, rot),
          bp.Geom("cylinder", (radius, length / 2), pos=tuple(pos), rot=rot, material=material,
                  visible=False, construction=construction)]


def concave(furniture, mesh, prefix, material, construction, pos=(0, 0, 0), rot=_IDENTITY):
  """A concave shape: its mesh to see (and to weigh), its coacd convex pieces to collide."""
  geoms = [_visual(furniture, mesh, prefix, material, pos, rot, construction)]
  for piece in decompose.convex_pieces(mesh):
    geoms.append(bp.Geom("mesh", pos=tuple(pos), rot=rot, material=material,
                         mesh=register_mesh(furniture, piece, f"{prefix}_hull"), visible=False))
  return geoms


def box(size, material, construction, pos=(0, 0, 0), rot=_IDENTITY):
  """A plain box primitive (seen and collided), for small blocks and slats."""
  return [bp.Geom("box", tuple(s / 2 for s in size), pos=tuple(pos), rot=rot, material=material,
                  construction=construction)]


def cylinder(radius, length, material, construction, pos=(0, 0, 0), rot=_IDENTITY):
  """A plain cylinder primitive along the part's z (seen and collided): discs and round seats."""
  return [bp.Geom("cylinder", (radius, length / 2), pos=tuple(pos), rot=rot, material=material,
                  construction=construction)]
