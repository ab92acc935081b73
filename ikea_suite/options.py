"""Range checks for user options: each raises OptionValueError naming the option, the
value and the valid range, at the boundary where the option is given."""

import numbers

import numpy as np

from ikea_suite import errors


def number(name, value, low=-np.inf, high=np.inf, low_open=False, high_open=False):
  """`value` as a float within [low, high] (ends open where asked); raises otherwise."""
  if not isinstance(value, numbers.Real) or isinstance(value, bool):
    raise errors.OptionValueError(f"{name} must be a number, got {value!r}")
  value = float(value)
  too_low = value <= low if low_open else value < low
  too_high = value >= high if high_open else value > high
  if not np.isfinite(value) or too_low or too_high:
    interval = (f"{'(' if low_open or low == -np.inf else '['}{low:g}, "
                f"{high:g}{')' if high_open or high == np.inf else ']'}")
    raise errors.OptionValueError(f"{name} must be a finite number in {interval}, got {value:g}")
  return value


def positive(name, value, high=np.inf):
  """A finite number > 0 (and <= `high`)."""
  return number(name, value, 0.0, high, low_open=True)


def non_negative(name, value):
  return number(name, value, 0.0)


def vector(name, value, shape):
  """A finite float array of `shape`."""
  try:
    array = np.asarray(value, dtype=float)
  except (TypeError, ValueError):
    raise errors.OptionValueError(f"{name} must be numbers of shape {shape}, got {value!r}") from None
  if array.shape != tuple(shape) or not np.isfinite(array).all():
    raise errors.OptionValueError(
        f"{name} must be finite numbers of shape {tuple(shape)}, got {value!r}")
  return array


def box(name, value):
  """A ((x, y, z) low, (x, y, z) high) box with low < high on every axis."""
  array = vector(name, value, (2, 3))
  if not (array[0] < array[1]).all():
    raise errors.OptionValueError(f"{name} must be (low corner, high corner) with low < high, "
                                  f"got {value!r}")
  return array


def choice(name, value, valid):
  if value not in valid:
    raise errors.OptionValueError(f"{name} must be one of {', '.join(map(repr, valid))}, "
                                  f"got {value!r}")
  return value
