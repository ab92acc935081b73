"""MJX set-up: the Warp implementation on a CUDA GPU, MJX's JAX implementation otherwise."""

import importlib.util

import jax
import jax.numpy as jnp
from mujoco import mjx

from ikea_suite import errors
from ikea_suite.batch import contact_buffers

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


def put(model, impl, sizing, num_worlds=None):
  """(mjx.Model, one world's mjx.Data) on the default device.

  Args:
    model: the compiled mujoco.MjModel.
    impl: "warp" or "jax".
    sizing: contact_buffers.Sizing of the model (Warp's per-world nconmax and njmax; unused,
      may be None, for jax).
    num_worlds: worlds that will step together (Warp's contact buffer holds all of them:
      naconmax = nconmax * num_worlds).

  Returns:
    The device model and a single world's initial data (vmap or broadcast it to batch).
  """
  mx = mjx.put_model(model, impl=impl)
  if impl == "jax":
    return mx, mjx.make_data(model, impl=impl)
  data = mjx.make_data(model, impl=impl, naconmax=sizing.naconmax(num_worlds),
                       njmax=sizing.njmax)
  return mx, data


def substeps(mx, data, count):
  """`count` physics steps of one world (vmap for many)."""
  return jax.lax.fori_loop(0, count, lambda _, d: mjx.step(mx, d), data)


def substeps_watched(mx, data, count):
  """`count` physics steps of one world (vmap for many), with the Warp buffers' demand.

  Returns:
    (data, overflow, peak): overflow the int32 word of the buffers that overflowed in any of
    the substeps (contact_buffers.OVERFLOW_BUFFERS bits; 0 on MJX's JAX implementation), peak
    (2,) int32 the most contacts or broadphase candidates of all worlds and constraint rows of
    this world that a substep needed.
  """
  def body(_, carry):
    d, seen = carry
    d = mjx.step(mx, d)
    return d, contact_buffers.worse(seen, contact_buffers.demand(d))
  data = contact_buffers.cleared(data)
  nothing = (jnp.int32(0), jnp.zeros(2, dtype=jnp.int32))
  data, (overflow, peak) = jax.lax.fori_loop(0, count, body, (data, nothing))
  return data, overflow, peak
