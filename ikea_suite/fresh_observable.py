"""An observable whose every read makes a new array, which the environment need not copy again."""

from dm_control.composer.observation import observable


class FreshGeneric(observable.Generic):
  """observable.Generic whose callable returns a newly made array on every call (indexing by
  an id array, np.empty, .copy(), .astype), never a view of the physics or a stored array.

  Environment's direct observation path copies each value, as composer's buffers do, except
  these: nothing else holds them, so a copy would be a second one (a few microseconds of
  each control step). tests/test_environment_internals.py checks every one is fresh.
  """
