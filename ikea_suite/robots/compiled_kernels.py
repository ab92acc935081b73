"""The optional compiled module robots/_ik_kernels.c, or None where the install could not build it.

setup.py builds it where a C compiler and the Python headers are found. Its functions are
twins of Python in ik_qp and control_modes: the same floating-point operations in the same
order, so episodes are the same bit for bit either way (tests/test_ik.py and
tests/test_control_kernels.py compare them); they take a fraction of the Python's time on
each task-space control step. `ikea-suite-rollout --doctor` says whether it was built.
"""

try:
  from ikea_suite.robots import _ik_kernels as kernels
except ImportError:   # no compiler where it was installed: the Python twins run
  kernels = None
