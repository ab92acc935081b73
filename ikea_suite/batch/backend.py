"""MJX set-up: the Warp implementation on a CUDA GPU, MJX's JAX implementation otherwise."""

import importlib.util

import jax
from mujoco import mjx

from ikea_suite import errors

IMPLS = ("warp", "jax")


def default_impl():
  """"warp" when jax sees a GPU and warp-lang is installed, else "jax"."""
  has_gpu = any(d.platform == "gpu" for d in jax.devices())
  return "warp" if has_gpu and importlib.util.find_spec("warp") is not None else "jax"


def check_impl(impl):
  """The implementation to use: `impl` if given and valid, else default_impl()."""
  if impl is None:
    return default_impl()
  if impl not in IMPLS:
    raise errors.OptionValueError(f"impl must be one of {', '.join(IMPLS)}, got {impl!r}")
  if impl == "warp" and importlib.util.find_spec("warp") is None:
    raise errors.OptionValueError(
        'impl="warp" needs warp-lang: pip install -e ".[gpu]"')
  return impl


def put(model, impl, num_parts, num_welds, contacts_per_world=None, num_worlds=None):
  """(mjx.Model, one world's mjx.Data) on the default device.

  Args:
    model: the compiled mujoco.MjModel.
    impl: "warp" or "jax".
    num_parts: parts of the furniture (sizes the Warp constraint buffers).
    num_welds: part welds declared.
    contacts_per_world: Warp contact capacity per world (default 8 per part geom).
    num_worlds: worlds that will step together (Warp sizes its contact buffer for all).

  Returns:
    The device model and a single world's initial data (vmap or broadcast it to batch).
  """
  mx = mjx.put_model(model, impl=impl)
  if impl == "jax":
    return mx, mjx.make_data(model, impl=impl)
  contacts = contacts_per_world or 8 * model.ngeom
  # Rows: contacts (elliptic cones: up to 6 rows each), both grips and every part weld that
  # can be on at once (at most one per part pair plus loop closures), 6 rows per weld.
  njmax = 6 * contacts + 6 * (2 + min(num_welds, num_parts * (num_parts - 1) // 2))
  data = mjx.make_data(model, impl=impl, naconmax=contacts * (num_worlds or 1), njmax=njmax)
  return mx, data


def substeps(mx, data, count):
  """`count` physics steps of one world (vmap for many)."""
  return jax.lax.fori_loop(0, count, lambda _, d: mjx.step(mx, d), data)
