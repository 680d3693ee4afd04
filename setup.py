"""The optional compiled corrector (``mechcont.continuation._ckernel``); everything else is in pyproject.toml.

Built when Cython and a C compiler are present; without either ``pip install`` still succeeds
(the extension is optional) and mechcont runs its Python corrector, with the same results to
rounding (``tests/test_kernel.py``).
"""

import os
import sys

from setuptools import Extension, setup

PYX = "src/mechcont/continuation/_ckernel.pyx"


def extensions() -> list:
    try:
        from Cython.Build import cythonize

        flags = ["-O2"] if os.name != "nt" else []
        ext = Extension("mechcont.continuation._ckernel", [PYX], extra_compile_args=flags, optional=True)
        return cythonize([ext], quiet=True, language_level=3)
    except Exception as exc:  # noqa: BLE001 - no Cython, or it failed: the Python corrector runs
        print(f"mechcont: the compiled corrector is not built ({exc}); the Python one runs", file=sys.stderr)
        return []


setup(ext_modules=extensions())
