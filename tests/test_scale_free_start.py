"""A continuation's start is judged relative to the sizes of its rows' terms, not against an absolute
residual: the same mechanism written in millimetres and grams (rows a million times larger) is solved
just as well, gives the same folds in its own units, and a start that is not an equilibrium is still
refused in either."""

from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.errors import InputError
from mechcont.models import load_model

SHIPPED = Path(__file__).parents[1] / "src" / "mechcont" / "data" / "overcentre.toml"
#: SI -> mm, g, s: lengths x1e3, masses x1e3, accelerations x1e3, stiffness (kg/s^2) x1e3, forces x1e6
TO_MM = {'L1 = { value = 1.5, unit = "m"': 'L1 = { value = 1500.0, unit = "mm"',
         'L2 = { value = 1.5, unit = "m"': 'L2 = { value = 1500.0, unit = "mm"',
         'm1 = { value = 1.0, unit = "kg"': 'm1 = { value = 1000.0, unit = "g"',
         'm2 = { value = 1.0, unit = "kg"': 'm2 = { value = 1000.0, unit = "g"',
         'g = { value = 9.81, unit = "m/s^2", scale = 10.0': 'g = { value = 9810.0, unit = "mm/s^2", scale = 10000.0',
         'k = { value = 127.0, unit = "N/m"': 'k = { value = 127000.0, unit = "g/s^2"',
         'LU = { value = 0.4, unit = "m"': 'LU = { value = 400.0, unit = "mm"'}


def _folds(system, force_scale):
    x0 = find_equilibrium(system, hold={"theta1": 0.3}, free=["F"])
    b = continuation(system, x0, "F", options=ContinuationOptions(
        bounds={"F": (-100 * force_scale, 120 * force_scale)}, ds=0.1 * force_scale, dsmax=10 * force_scale))
    return x0, sorted((p.values["F"], p.values["theta1"]) for p in b.special("LP"))


def test_overcentre_in_millimetres_and_grams_has_the_same_folds(tmp_path):
    text = SHIPPED.read_text()
    for a, b in TO_MM.items():
        assert a in text
        text = text.replace(a, b)
    path = tmp_path / "overcentre_mm.toml"
    path.write_text(text)
    x_si, si = _folds(load_model(SHIPPED), 1.0)
    x_mm, mm = _folds(load_model(path), 1e6)
    assert len(si) == len(mm) == 2
    for (f1, t1), (f2, t2) in zip(si, mm):
        assert f2 == pytest.approx(f1 * 1e6, rel=1e-9)
        assert t2 == pytest.approx(t1, abs=1e-9)
    # a start that is no equilibrium is refused in either unit system, naming the start
    for system, x0 in ((load_model(SHIPPED), x_si), (load_model(path), x_mm)):
        bad = np.array(x0)
        bad[system.index("theta2")] += 1e-3
        with pytest.raises(InputError, match="start: is not an equilibrium"):
            continuation(system, bad, "F")
