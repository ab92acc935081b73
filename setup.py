"""The one compiled module, ikea_suite.robots._ik_kernels; everything else is in pyproject.toml.

It is optional: where no C compiler or no Python headers are found the build skips it and
ik_qp runs its Python and numpy twins (the same numbers, slower).
"""

import sys

from setuptools import Extension, setup

# No fused multiply-adds: the compiled twin must round as Python does, operation for operation.
_FLAGS = [] if sys.platform == "win32" else ["-ffp-contract=off", "-fno-fast-math"]

setup(ext_modules=[Extension("ikea_suite.robots._ik_kernels",
                             sources=["ikea_suite/robots/_ik_kernels.c"],
                             extra_compile_args=_FLAGS, optional=True)])
