"""Light paths import nothing heavy they do not use: ``import mechcont`` imports no SymPy,
SciPy or Matplotlib, and a continuation, fold or listing command imports no Matplotlib,
``scipy.integrate``/``scipy.optimize``, Exudyn, pandas, pyarrow or Dask (each costs a CLI
run 0.1-1 s). Checked in a fresh interpreter, the commands run in-process."""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ["matplotlib", "scipy.integrate", "scipy.optimize", "exudyn", "pandas", "pyarrow", "dask"]

SCRIPT = r"""
import contextlib, io, json, sys
heavy = json.loads(sys.argv[1])
found = {}
import mechcont
found["import mechcont"] = [m for m in [*heavy, "scipy", "sympy", "symengine", "numpy"] if m in sys.modules]
from mechcont.cli import main
for args in json.loads(sys.argv[2]):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(args)
        except SystemExit as exc:
            assert not exc.code, (args, exc.code)
    found[" ".join(args)] = [m for m in heavy if m in sys.modules]
print(json.dumps(found))
"""


def test_light_paths_import_nothing_heavy():
    commands = [
        ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
         "--bounds", "theta1=-1.2:1.2", "--quiet"],
        ["folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--free", "LU",
         "--bounds", "LU=0.1:2", "--quiet"],
        ["models", "overcentre", "fourbar"],
    ]
    out = subprocess.run([sys.executable, "-c", SCRIPT, json.dumps(HEAVY), json.dumps(commands)],
                         capture_output=True, text=True, check=True, timeout=300).stdout
    found = json.loads(out)
    assert found == {"import mechcont": [], **{" ".join(c): [] for c in commands}}


def _blas_threads(env_value: str | None) -> str:
    import os

    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if env_value is not None:
        env["OPENBLAS_NUM_THREADS"] = env_value
    code = "import os, mechcont, numpy; print(os.environ.get('OPENBLAS_NUM_THREADS'))"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          check=True).stdout.strip()


def test_one_blas_thread_by_default_and_the_users_choice_kept():
    # small matrices on a shared machine: threads spin (a 63 x 64 SVD 96 ms instead of 0.5 ms)
    assert _blas_threads(None) == "1"
    assert _blas_threads("3") == "3"
