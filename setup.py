"""The optional compiled kernels (``mechcont.continuation._ckernel``, ``._ccondense``); everything else is in pyproject.toml.

Built when Cython and a C compiler are present; without either ``pip install`` still succeeds
(the extension is optional) and mechcont runs its Python corrector, with the same results to
rounding (``tests/test_kernel.py``).
"""

import os
import sys

from setuptools import Extension, setup

#: the compiled corrector, and the collocation's condensation of parameters (``_condensation``)
PYX = {"_ckernel": "src/mechcont/continuation/_ckernel.pyx", "_ccondense": "src/mechcont/continuation/_ccondense.pyx"}


def extensions() -> list:
    try:
        from Cython.Build import cythonize

        flags = ["-O3"] if os.name != "nt" else []
        exts = [Extension(f"mechcont.continuation.{name}", [pyx], extra_compile_args=flags, optional=True)
                for name, pyx in PYX.items()]
        return cythonize(exts, quiet=True, language_level=3)
    except Exception as exc:  # noqa: BLE001 - no Cython, or it failed: the Python corrector runs
        print(f"mechcont: the compiled corrector is not built ({exc}); the Python one runs", file=sys.stderr)
        return []


setup(ext_modules=extensions())
