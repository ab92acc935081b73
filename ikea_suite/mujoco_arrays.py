"""Cheap per-step reads of MuJoCo's arrays: views kept per MjData, id lists as slices, and
observables whose reads the environment hands out without a second copy.

A control step's Python runs with caches the physics has just flushed, and there a read costs
mostly the code it passes through: dm_control's `physics.data.qpos` goes through two Python
properties and builds a new numpy view, and indexing by an id array runs numpy's general
fancy-indexing machinery. With kept views and slices the Panda's observations cost about
30 us less per control step (benchmarks/robot_throughput.py's conditions).
"""

import collections

import numpy as np
from dm_control.composer.observation import observable


class ArrayViews:
  """Named arrays of a physics' MjData as numpy views into MuJoCo's buffers.

  `views(physics)` returns them as a named tuple (`views(physics).qpos`). They are fetched
  again only when `physics.data` is another object than last time (another physics, or a
  recompiled one).
  """

  __slots__ = ("_type", "_data", "_arrays")

  def __init__(self, *names):
    self._type = collections.namedtuple("MjDataViews", names)
    self._data, self._arrays = None, None

  def __call__(self, physics):
    data = physics.data
    if data is not self._data:
      raw = data.ptr
      self._arrays = self._type(*(getattr(raw, name) for name in self._type._fields))
      self._data = data
    return self._arrays


def compact_index(ids):
  """The ids flattened: a slice where they run consecutively upward, else an int array.

  array[compact_index(ids)] holds what array[np.ravel(ids)] holds; by a slice it is a view
  (copy it to keep it) and costs about a third of indexing by an id array.
  """
  flat = np.asarray(ids, dtype=np.intp).ravel()
  if flat.size and np.array_equal(flat, np.arange(flat[0], flat[0] + flat.size)):
    return slice(int(flat[0]), int(flat[0]) + flat.size)
  return flat


class FreshGeneric(observable.Generic):
  """observable.Generic whose callable returns a newly made array on every call (indexing by
  an id array, np.empty, .copy(), .astype), never a view of the physics or a stored array.

  The environment's direct observation path (composer_internals.direct_readers) copies each
  value, as composer's buffers do, except these: nothing else holds them, so a copy would be
  a second one (a few microseconds of each control step). tests/test_environment_internals.py
  checks every one is fresh.
  """
