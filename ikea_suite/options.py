"""Range and type checks for user options: each raises OptionValueError naming the option,
the value and what is valid. config.py applies them where an option is given; a bool is
never a number, a number never a bool, and a string neither."""

import numbers

import numpy as np

from ikea_suite import errors


def is_number(value) -> bool:
  """Whether `value` is a real number: an int or float (numpy's too), never a bool."""
  return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def is_integer(value) -> bool:
  """Whether `value` is an int (numpy's too), never a bool."""
  return isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_))


def number(name, value, low=-np.inf, high=np.inf, low_open=False, high_open=False):
  """`value` as a float within [low, high] (ends open where asked); raises otherwise."""
  if not is_number(value):
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


def integer(name, value, low=0, high=None):
  """`value` as an int in [low, high] (no upper bound when `high` is None); raises otherwise."""
  if not is_integer(value) or value < low or (high is not None and value > high):
    bound = f"from {low} to {high}" if high is not None else f">= {low}"
    raise errors.OptionValueError(f"{name} must be a whole number {bound}, got {value!r}")
  return int(value)


def boolean(name, value):
  """`value` if it is True or False (numpy's bool too); raises for anything else, 0 and 1
  and "yes" included."""
  if not isinstance(value, (bool, np.bool_)):
    raise errors.OptionValueError(f"{name} must be a bool (True, False), got {value!r}")
  return bool(value)


def vector(name, value, shape):
  """A finite float array of `shape`, from numbers only (no bools, no strings)."""
  try:
    entries = np.asarray(value, dtype=object)
    array = (entries.astype(float) if all(is_number(v) for v in entries.flat) else None)
  except (TypeError, ValueError):
    array = None
  if array is None:
    raise errors.OptionValueError(f"{name} must be numbers of shape {tuple(shape)}, "
                                  f"got {value!r}")
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
  """`value` if it equals one of `valid` and is of its type (1 is not True); raises otherwise."""
  if not any(isinstance(value, type(v)) and value == v for v in valid):
    raise errors.OptionValueError(f"{name} must be one of {', '.join(map(repr, valid))}, "
                                  f"got {value!r}")
  return value


def names(name, value):
  """A tuple of names from one name (a str) or a sequence of them; raises otherwise."""
  if isinstance(value, str):
    return (value,)
  if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
    return tuple(value)
  raise errors.OptionValueError(f"{name} must be a name or a sequence of names (str), "
                                f"got {value!r}")
