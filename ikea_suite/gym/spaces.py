"""dm_env specs -> gymnasium spaces, one function per direction of the mapping.

A bounded spec keeps its bounds; an unbounded one spans its dtype's range
(+-inf for floats, the integer limits for ints), so `uint8` images become
`Box(0, 255, uint8)`. Shapes and dtypes are kept exactly: an observation the
dm_env spec accepts is in the gymnasium space.
"""

from collections.abc import Mapping

import numpy as np
from dm_env import specs
from gymnasium import spaces


def _dtype_limits(dtype: np.dtype) -> tuple[float, float]:
  if np.issubdtype(dtype, np.integer):
    info = np.iinfo(dtype)
    return info.min, info.max
  if np.issubdtype(dtype, np.bool_):
    return 0, 1
  return -np.inf, np.inf


def box_from_spec(spec: specs.Array, dtype: np.dtype | None = None) -> spaces.Box:
  """The gymnasium Box with the spec's shape, dtype and (if bounded) bounds.

  Args:
    spec: a dm_env `Array` or `BoundedArray`.
    dtype: the Box's dtype instead of the spec's (float32 actions of a float64 spec).

  Returns:
    A `gymnasium.spaces.Box` that contains every array `spec.validate` accepts.
  """
  dtype = np.dtype(spec.dtype if dtype is None else dtype)
  if isinstance(spec, specs.BoundedArray):
    low = np.broadcast_to(spec.minimum, spec.shape).astype(dtype)
    high = np.broadcast_to(spec.maximum, spec.shape).astype(dtype)
  else:
    lo, hi = _dtype_limits(dtype)
    low, high = np.full(spec.shape, lo, dtype=dtype), np.full(spec.shape, hi, dtype=dtype)
  return spaces.Box(low=low, high=high, shape=spec.shape, dtype=dtype)


def dict_from_specs(observation_spec: Mapping[str, specs.Array]) -> spaces.Dict:
  """A Dict space with one Box per dm_env observation spec, under the same keys.

  Args:
    observation_spec: the environment's `observation_spec()` mapping.

  Returns:
    A `gymnasium.spaces.Dict` mirroring it key for key.
  """
  return spaces.Dict({name: box_from_spec(spec) for name, spec in observation_spec.items()})
