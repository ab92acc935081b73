"""The optional compiled module robots/_ik_kernels.c, or None where the install could not build it.

setup.py builds it where a C compiler and the Python headers are found. Its functions are
twins of Python in ik_qp and control_modes: the same floating-point operations in the same
order, so episodes are the same bit for bit either way (tests/test_ik.py and
tests/test_control_kernels.py compare them); they take a fraction of the Python's time on
each task-space control step. `ikea-suite-rollout --doctor` says whether it was built.

The fused task-space step (`fused`) also calls MuJoCo's kinematics and the BLAS that numpy's
matmul calls, by address: it is on where both libraries are found as numpy and mujoco's
wheels ship them (numpy's bundled ILP64 OpenBLAS), and DirectQP checks it against the Python
to the bit before using it.
"""

import ctypes
import glob
import logging
import os

try:
  from ikea_suite.robots import _ik_kernels as kernels
except ImportError:   # no compiler where it was installed: the Python twins run
  kernels = None

_MUJOCO_FUNCTIONS = ("mj_kinematics", "mj_comPos", "mj_jacSite")
_BLAS_FUNCTIONS = ("cblas_dgemm", "cblas_dsyrk", "cblas_dgemv")


def _library(directory, patterns):
  """The first file in `directory` matching one of `patterns` opened by ctypes, or None.
  Opening a library the process has loaded already returns that very instance."""
  for pattern in patterns:
    for path in sorted(glob.glob(os.path.join(directory, pattern))):
      try:
        return ctypes.CDLL(path)
      except OSError:
        continue
  return None


def _numpy_blas():
  """(library, symbol prefix, suffix) of the BLAS numpy's matmul calls, where numpy is a
  wheel with its bundled ILP64 OpenBLAS (the one kind whose calling convention the kernels
  declare); else None."""
  import numpy as np
  try:
    blas = np.__config__.CONFIG["Build Dependencies"]["blas"]
  except (AttributeError, KeyError, TypeError):
    return None
  if blas.get("name") != "scipy-openblas" or "USE64BITINT" not in str(
      blas.get("openblas configuration", "")):
    return None
  root = os.path.dirname(np.__file__)
  for directory in (os.path.join(root, os.pardir, "numpy.libs"), os.path.join(root, ".dylibs")):
    library = _library(directory, ("libscipy_openblas64_*",))
    if library is not None:
      return library, "scipy_", "64_"
  return None


def _native_addresses():
  """Addresses of mj_kinematics, mj_comPos, mj_jacSite (MuJoCo's) and cblas_dgemm, cblas_dsyrk,
  cblas_dgemv (numpy's), or None where any is not found."""
  import mujoco
  library = _library(os.path.dirname(mujoco.__file__),
                     ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"))
  blas = _numpy_blas()
  if library is None or blas is None:
    return None
  blas_library, prefix, suffix = blas
  try:
    functions = [getattr(library, name) for name in _MUJOCO_FUNCTIONS]
    functions += [getattr(blas_library, prefix + name + suffix) for name in _BLAS_FUNCTIONS]
  except AttributeError:
    return None
  return [ctypes.cast(f, ctypes.c_void_p).value for f in functions]


def _enable_fused():
  if kernels is None:
    return False
  try:
    addresses = _native_addresses()
  except Exception as e:   # a library that will not load leaves the step to numpy
    logging.info("ikea_suite: fused task-space step off: %s", e)
    return False
  if addresses is None:
    return False
  kernels.set_native(*addresses)
  return True


# Whether the fused task-space step (task_space_assemble) can run here.
fused = _enable_fused()
