"""The shimmy gear and what needs no Hopf point: the description, the gear running straight at a speed, its
leading eigenvalue, the onset speed by bisection and the brute-force stability grid (see :mod:`.shimmy`).

Apart from :mod:`.shimmy` (the section, :func:`~.shimmy.run`): the section's computations
(:mod:`._shimmy_analysis`) build on these, and the section calls them, so they sit below both.
"""

from __future__ import annotations

from collections.abc import Iterable
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from ..equations import Model
    from ..mechanism import Mechanism

__all__ = ["EXAMPLE", "SPEEDS", "DAMPER_RATES", "shimmy_mechanism", "gear_at", "leading_eigenvalue", "onset_speed",
           "stability_grid"]

#: The shipped description (in the repository, beside the other examples).
EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "shimmy.toml"
#: The speed range of the study (m/s) and the shimmy damper rates of its chart (N m s/rad).
SPEEDS = (1.0, 100.0)
DAMPER_RATES = (0.0, 100.0)


@cache
def shimmy_mechanism(path: str | None = None) -> Mechanism[Any, Any]:
    """The parsed gear description (``examples/shimmy.toml`` by default; ``path`` another file)."""
    from ..mechanism import parse_description

    file = Path(path) if path is not None else EXAMPLE
    if not file.is_file():
        raise InputError("shimmy", f"the gear description {file} is missing (it ships in the repository's examples/)")
    return parse_description(file.read_text(encoding="utf-8"), str(file))


def gear_at(speed: float, mech: Mechanism[Any, Any] | None = None, **values: float) -> tuple[Model, np.ndarray]:
    """The gear running straight at ``speed`` (m/s), other parameters at ``values`` (SI): ``(model, x)``,
    ``x`` the equilibrium (the full variable vector; the tyre's deflection at its steady state)."""
    from ..continuation import find_equilibrium

    mech = shimmy_mechanism() if mech is None else mech
    model = mech.build(V=speed, **values)
    return model, find_equilibrium(model)


def leading_eigenvalue(speed: float, mech: Mechanism[Any, Any] | None = None, **values: float) -> complex:
    """The eigenvalue (1/s) of the gear's linearised dynamics at straight running at ``speed`` (m/s)
    with the largest real part (of a complex pair, the one with positive imaginary part)."""
    from ..equations import dynamics_of

    model, x = gear_at(speed, mech, **values)
    lam = dynamics_of(model).linearise(x).eigenvalues()
    top = lam[np.isclose(lam.real, lam[0].real, rtol=1e-9, atol=0.0)]
    return complex(top[np.argmax(top.imag)])


def onset_speed(mech: Mechanism[Any, Any] | None = None, speeds: tuple[float, float] = SPEEDS, samples: int = 12,
                tol: float = 1e-6,
                **values: float) -> float | None:
    """The lowest speed (m/s) in ``speeds`` where the leading eigenvalue's real part turns positive: the
    first of ``samples`` equally spaced speeds where it is positive brackets it with the previous one,
    then bisection to ``tol`` relative. None when the gear is stable at every sample; ``speeds[0]`` when
    it is already unstable there (shimmy from the start of the range). A band narrower than the
    samples' spacing can be missed: this is a check of Hopf points, not a way to find them all."""
    grid = np.linspace(speeds[0], speeds[1], samples)
    re = [leading_eigenvalue(float(v), mech, **values).real for v in grid]
    above = [i for i, r in enumerate(re) if r > 0]
    if not above:
        return None
    if above[0] == 0:
        return float(speeds[0])
    lo, hi = float(grid[above[0] - 1]), float(grid[above[0]])
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        if leading_eigenvalue(mid, mech, **values).real > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def stability_grid(speeds: Iterable[float], parameter: str, values: Iterable[float], mech: Mechanism[Any, Any] | None = None,
                   **fixed: float) -> np.ndarray:
    """The leading eigenvalue's real part (1/s) at straight running over ``speeds`` (m/s) x the
    ``values`` of ``parameter`` (SI), other parameters at ``fixed``: array (len(values), len(speeds)),
    positive where the gear shimmies. One linearisation per point (about 10 ms on this gear): the
    brute-force chart a continuation of Hopf points is compared with."""
    return np.array([[leading_eigenvalue(float(v), mech, **{**fixed, parameter: float(p)}).real for v in speeds]
                     for p in values])
