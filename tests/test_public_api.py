"""The public API offers the analyses and studies, not only the engine: every name in
``mechcont.__all__`` resolves lazily to the documented object of the same name."""

from __future__ import annotations

import inspect
import subprocess
import sys

import mechcont as mc


def test_every_public_name_resolves_to_a_documented_object_of_that_name():
    for name in mc.__all__:
        obj = getattr(mc, name)
        assert inspect.getdoc(obj), f"mechcont.{name} has no docstring"
        if inspect.ismodule(obj):
            assert obj.__name__ == f"mechcont.{name}", name
        else:
            assert obj.__name__ == name, (name, obj)
    for name in ("downlock", "design_region", "run_study", "optimize", "freefall", "downlock_sensitivity",
                 "equilibrium_family", "unlock_folds", "continuation_with_stops", "downlock_reliability"):
        assert callable(getattr(mc, name)) and name in dir(mc), name
    assert mc.units.display(0.0, "N") == (0.0, "N")


def test_the_analyses_cost_nothing_until_used():
    code = ("import sys, mechcont; print(sorted(m for m in sys.modules if m.startswith(('mechcont.analysis', "
            "'mechcont.dynamics', 'numpy'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"
