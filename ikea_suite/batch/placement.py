"""Randomized start per world: every part flat on the floor, random yaw, scattered in a ring.

The batched form of `tasks/placement.ScatteredParts` (preassembled = 0): the
same resting poses (tasks/resting.py), ring (inner radius = assembled radius + clearance,
width `spread`), gap and yaw range, parts placed largest first without
overlap. The CPU draws candidates until one fits and widens the ring by a
part width every 100 draws; here each part draws CANDIDATES at once, in
blocks of BLOCK whose ring widens by a part width per block, and takes the
first that fits (the least overlapping if none does, which at the default
spread does not happen).
"""

import typing

import jax
import jax.numpy as jnp
import numpy as np

from ikea_suite import geometry
from ikea_suite.batch import rigid
from ikea_suite.tasks import placement as cpu_placement
from ikea_suite.tasks import resting

BLOCK = 32
CANDIDATES = 4 * BLOCK


class Scatter(typing.NamedTuple):
  """Per-furniture constants of the placement, parts in placement order."""
  order: tuple              # part indices, largest extent first
  rest_rot: np.ndarray      # (p, 3, 3) resting rotation of each part (placement order)
  rest_height: np.ndarray   # (p,) m, height of a part that starts at rest; NaN: it lands
  corners: np.ndarray       # (p, 8, 3) collision-bound corners in each part frame
  inner: float              # m, ring's inner radius
  spread: float
  gap: float
  yaw_range: float


def scatter(spec, spread, yaw_range):
  """Scatter constants for a FurnitureSpec: ring width `spread` (m) and largest |yaw|
  `yaw_range` (rad), the options of a resolved config.TaskConfig; clearance and gap as
  tasks/placement.ScatteredParts has them."""
  rests = cpu_placement.lying_rests(spec)
  rest = [rests[i].rotation for i in range(len(spec.parts))]
  height = [np.nan if rests[i].position is None else rests[i].position[2]
            for i in range(len(spec.parts))]
  corners = [geometry.box_corners(*p.bounds) for p in spec.parts]
  extent = [np.ptp(c @ r.T, axis=0).max() for c, r in zip(corners, rest)]
  order = tuple(int(i) for i in np.argsort(-np.array(extent), kind="stable"))
  return Scatter(order, np.array([rest[i] for i in order]), np.array([height[i] for i in order]),
                 np.array([corners[i] for i in order]),
                 cpu_placement.assembled_radius(spec) + cpu_placement.CLEARANCE, spread,
                 cpu_placement.GAP, yaw_range)


def place(scatter_constants, rng):
  """Part poses for one world.

  Args:
    scatter_constants: a Scatter.
    rng: a jax PRNG key.

  Returns:
    (positions (p, 3), rotations (p, 3, 3)) in part index order.
  """
  sc = scatter_constants
  num = len(sc.order)
  keys = jax.random.split(rng, num)
  centres = jnp.zeros((num, 2))
  radii = jnp.zeros(num)
  positions, rotations = [None] * num, [None] * num
  block = jnp.repeat(jnp.arange(CANDIDATES // BLOCK), BLOCK)
  for n, part in enumerate(sc.order):
    k_yaw, k_r, k_angle = jax.random.split(keys[n], 3)
    yaw = jax.random.uniform(k_yaw, (), minval=-sc.yaw_range, maxval=sc.yaw_range)
    rot = rigid.rot_z(yaw) @ rigid.real(sc.rest_rot[n])
    corners = rigid.real(sc.corners[n]) @ rot.T
    centre = (corners[:, :2].max(0) + corners[:, :2].min(0)) / 2
    radius = jnp.max(jnp.linalg.norm(corners[:, :2] - centre, axis=1))
    width = sc.spread + block * (2 * radius + sc.gap)
    low = sc.inner + radius
    r = low + jax.random.uniform(k_r, (CANDIDATES,)) * width
    angle = jax.random.uniform(k_angle, (CANDIDATES,), minval=-np.pi, maxval=np.pi)
    xy = r[:, None] * jnp.stack([jnp.cos(angle), jnp.sin(angle)], axis=1)
    gaps = (jnp.linalg.norm(xy[:, None] - centres[None], axis=2) - radii[None] - radius - sc.gap)
    gaps = jnp.where(jnp.arange(num)[None] < n, gaps, jnp.inf)
    worst = jnp.min(gaps, axis=1)
    free = worst > 0
    pick = jnp.where(free.any(), jnp.argmax(free), jnp.argmax(worst))
    centres = centres.at[n].set(xy[pick])
    radii = radii.at[n].set(radius)
    if np.isnan(sc.rest_height[n]):   # lands from just above the floor
      lift = -corners[:, 2].min(keepdims=True) + resting.LANDING
    else:
      lift = jnp.full(1, sc.rest_height[n])
    shift = jnp.concatenate([xy[pick] - centre, lift])
    positions[part], rotations[part] = shift, rot
  return jnp.stack(positions), jnp.stack(rotations)
