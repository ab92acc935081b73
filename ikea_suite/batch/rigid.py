"""Rigid-transform helpers on jax arrays; quaternions are (w, x, y, z) like MuJoCo's.

The jax counterparts of `ikea_suite.geometry`, written to vectorise over any
leading axes so one call serves every part, connector or cursor of a world.
"""

import jax.numpy as jnp


def quat_to_mat(quat):
  """Rotation matrices (..., 3, 3) of unit quaternions (..., 4)."""
  w, x, y, z = jnp.moveaxis(quat, -1, 0)
  return jnp.stack([
      jnp.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
      jnp.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
      jnp.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
  ], -2)


def mat_to_quat(mat):
  """Unit quaternions (..., 4), w >= 0, of rotation matrices (..., 3, 3).

  Shepperd's method without branches: all four candidate formulas are
  computed and the one with the largest pivot is kept, so it is exact and
  stable for every rotation.
  """
  m = mat
  t = jnp.stack([1 + m[..., 0, 0] + m[..., 1, 1] + m[..., 2, 2],
                 1 + m[..., 0, 0] - m[..., 1, 1] - m[..., 2, 2],
                 1 - m[..., 0, 0] + m[..., 1, 1] - m[..., 2, 2],
                 1 - m[..., 0, 0] - m[..., 1, 1] + m[..., 2, 2]], -1)
  d21, d02, d10 = m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]
  s21, s02, s10 = m[..., 2, 1] + m[..., 1, 2], m[..., 0, 2] + m[..., 2, 0], m[..., 1, 0] + m[..., 0, 1]
  candidates = jnp.stack([
      jnp.stack([t[..., 0], d21, d02, d10], -1),
      jnp.stack([d21, t[..., 1], s10, s02], -1),
      jnp.stack([d02, s10, t[..., 2], s21], -1),
      jnp.stack([d10, s02, s21, t[..., 3]], -1)], -2)
  pivot = jnp.argmax(t, axis=-1)
  q = jnp.take_along_axis(candidates, pivot[..., None, None], axis=-2)[..., 0, :]
  q = q / jnp.linalg.norm(q, axis=-1, keepdims=True)
  return jnp.where(q[..., :1] < 0, -q, q)


def quat_mul(a, b):
  """Hamilton products a * b of quaternions (..., 4)."""
  aw, ax, ay, az = jnp.moveaxis(a, -1, 0)
  bw, bx, by, bz = jnp.moveaxis(b, -1, 0)
  return jnp.stack([aw * bw - ax * bx - ay * by - az * bz,
                    aw * bx + ax * bw + ay * bz - az * by,
                    aw * by - ax * bz + ay * bw + az * bx,
                    aw * bz + ax * by - ay * bx + az * bw], -1)


def axis_angle_to_quat(vec):
  """Unit quaternions (..., 4) of rotation vectors (..., 3) (axis times angle, radians)."""
  angle = jnp.linalg.norm(vec, axis=-1, keepdims=True)
  safe = jnp.maximum(angle, 1e-12)
  return jnp.concatenate([jnp.cos(angle / 2), jnp.sin(angle / 2) * vec / safe], -1)


def rot_z(angle):
  """Rotations (..., 3, 3) by `angle` (radians) about z."""
  c, s = jnp.cos(angle), jnp.sin(angle)
  zero, one = jnp.zeros_like(angle), jnp.ones_like(angle)
  return jnp.stack([jnp.stack([c, -s, zero], -1), jnp.stack([s, c, zero], -1),
                    jnp.stack([zero, zero, one], -1)], -2)


def apply(rot, vec):
  """rot @ vec over leading axes: (..., 3, 3) x (..., 3) -> (..., 3)."""
  return jnp.einsum("...ij,...j->...i", rot, vec)


def real(x):
  """`x` as an array of jax's default float type (float64 inside `jax.enable_x64(True)`)."""
  return jnp.asarray(x, dtype=jnp.result_type(float))
