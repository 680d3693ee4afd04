"""Design answers beyond the paper (issue 24): reliability-based optima of the nose gear and the lock stay.

* The nose gear: the longest nominal lock-spring free length ``LU`` with which the gear still
  locks unaided at ``P(not locking) <= 1e-6`` under the issue's tolerances (``LU`` normal, 10 mm,
  about its nominal value; the attachment ``l_sp1`` truncated normal, 5 mm within +-10 mm).
* The lock stay (``lockstay.toml``): the smallest unlock load its actuator must overcome, over the
  spring's stiffness and free length (both toleranced), with the gear locking unaided at the same
  probability; drawn on its design map with the probability constraint's boundary.
* The dual-sidestay gear (``examples/dual_sidestay.toml``), whose lock-link pairs rest on overcentre
  stops: the smallest unlock load of both pairs together (``F_lock``, the release run from rest to
  its fold) over the lock springs' stiffness and stretch, with each stop's preload at rest (its
  reaction) at least :data:`DS_MARGIN` (deterministic: the FORM constraint holds a downlock force,
  not a stop's reaction).

Both are :func:`~mechcont.analysis.optimize.optimize` (SLSQP on exact gradients, FORM inside for
the probability), a few seconds together (the dual-sidestay optimum about 2 s).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from ._timing import timed

if TYPE_CHECKING:
    from ..analysis.optimize import Constraint, OptimumMap, OptimumResult
    from ..analysis.study import Distribution

__all__ = ["P_MAX", "NOSE_TOLERANCES", "STAY_TOLERANCES", "NOSE_BOUNDS", "STAY_BOUNDS", "DS_BOUNDS", "DS_MARGIN",
           "DS_FORCE", "dual_sidestay_optimum", "compute", "run"]

#: ``{name: (kind, parameters (SI), unit)}``: the tolerances of a design's quantities (see :data:`NOSE_TOLERANCES`).
Tolerances = Mapping[str, tuple[str, tuple[float, ...], str]]
#: The probability of not locking unaided that both designs allow.
P_MAX = 1e-6
#: ``{name: (kind, parameters)}`` (SI): the issue's tolerances of the nose gear; LU's centre moves with the design.
NOSE_TOLERANCES = {"LU": ("normal", (1.3, 0.01), "m"), "l_sp1": ("truncnormal", (0.1, 0.005, 0.09, 0.11), "m")}
NOSE_BOUNDS = {"LU": (1.2, 1.4)}
#: The lock stay's tolerances (spring stiffness and free length; both centres move with the design).
STAY_TOLERANCES = {"LU": ("normal", (0.6, 0.005), "m"), "k": ("normal", (20000.0, 1500.0), "N/m")}
STAY_BOUNDS = {"LU": (0.5, 0.7), "k": (10000.0, 30000.0)}
#: The dual-sidestay gear's lock springs (both pairs alike): stiffness (N/m) and stretch (free length over installed
#: length; 0.5 = stretched to twice the free length, the most allowed).
DS_BOUNDS = {"k_lock": (1000.0, 16000.0), "stretch": (0.5, 0.85)}
#: The least preload (N m) each overcentre stop of the dual-sidestay gear must carry at rest: a third of the
#: forward stop's at the description's springs (61.7 N m).
DS_MARGIN = 20.0
#: The unlock force of both lock-link pairs together.
DS_FORCE = "F_lock"


@dataclass
class DesignOptima:
    """The two optima (:class:`~mechcont.analysis.optimize.OptimumResult`) and the lock stay's map."""

    nose: OptimumResult
    nose_force: float
    stay: OptimumResult
    stay_force: float
    stay_map: OptimumMap
    seconds: dict[str, float]
    sidestay: OptimumResult | None = None
    sidestay_nominal: dict[str, float] | None = None


def _random(tolerances: Tolerances) -> dict[str, Distribution]:
    from ..analysis.study import Distribution

    return {n: Distribution(kind, params) for n, (kind, params, _) in tolerances.items()}


def _constraint() -> list[Constraint]:
    from ..analysis.optimize import Constraint

    return [Constraint.parse(f"P(not locking) <= {P_MAX:g}")]


@lru_cache(maxsize=1)
def compute() -> DesignOptima:
    """Both optima, the downlock force at each, and the lock stay's optimum map (cached: one run per process)."""
    from ..analysis.downlock import downlock_point
    from ..analysis.optimize import optimize, optimum_map
    from ..models import load_model

    seconds: dict[str, float] = {}
    with timed(seconds, "nose gear: longest LU at P <= 1e-6"):
        nose_gear = load_model("nose_gear")
        nose = optimize(nose_gear, "LU", NOSE_BOUNDS, maximize=True, constraints=_constraint(),
                        random=_random(NOSE_TOLERANCES))
        nose_force = float(downlock_point(nose_gear, nose.design)[nose_gear.index("F")])
    with timed(seconds, "lock stay: least unlock load at P <= 1e-6"):
        stay_model = load_model("lockstay")
        stay = optimize(stay_model, "unlock_force", STAY_BOUNDS, constraints=_constraint(),
                        random=_random(STAY_TOLERANCES))
        stay_force = float(downlock_point(stay_model, stay.design)[stay_model.index("F")])
    with timed(seconds, "lock stay: design map with the optimum"):
        stay_map = optimum_map(stay_model, stay, STAY_BOUNDS, constraints=_constraint(),
                               random=_random(STAY_TOLERANCES))
    with timed(seconds, "dual-sidestay gear: least unlock load, stops preloaded"):
        sidestay, nominal = dual_sidestay_optimum()
    return DesignOptima(nose, nose_force, stay, stay_force, stay_map, seconds, sidestay, nominal)


def dual_sidestay_optimum(margin: float = DS_MARGIN) -> tuple[OptimumResult, dict[str, float]]:
    """The dual-sidestay gear's lock springs with the least unlock load (:data:`DS_FORCE`, N) with each stop's
    preload at rest at least ``margin`` (N m), over :data:`DS_BOUNDS`. Returns ``(OptimumResult, nominal)``,
    ``nominal`` the unlock load and preloads at the description's springs (``{name: value}``, SI)."""
    from ..analysis.optimize import Constraint, optimize
    from ..analysis.stop_lock import locked_on_stops, stop_unlock
    from .dual_sidestay import generated_gear

    gear = generated_gear()
    best = optimize(gear, "unlock_force", DS_BOUNDS, constraints=[Constraint("stop_preload", ">=", margin)],
                    force=DS_FORCE)
    x, _ = locked_on_stops(gear)
    nominal = {n: float(x[gear.index(n)]) for n in (*DS_BOUNDS, "R_fwd_stop", "R_aft_stop")}
    nominal["unlock_force"] = float(stop_unlock(gear, x, DS_FORCE, stability=False, both=False).unlock_force)
    return best, nominal


def _tolerances(tolerances: Tolerances) -> str:
    def one(name: str, kind: str, p: tuple[float, ...], unit: str) -> str:
        if kind == "normal":
            return f"{name} normal, standard deviation {p[1]:g} {unit}"
        return (f"{name} truncated normal, standard deviation {p[1]:g} {unit} within {p[2] - p[0]:+g}..{p[3] - p[0]:+g} "
                f"{unit}")

    return "; ".join(one(n, *rest) for n, rest in tolerances.items())


def run(out_dir: Path, quiet: bool = True, timings: dict | None = None) -> list[str]:
    """Write the lock stay's optimum figure into ``out_dir``; return summary Markdown lines."""
    from ..outputs.design_plots import optimum_figure
    from ..outputs.plotting import save_figure

    timings = {} if timings is None else timings
    res = compute()
    timings.update({f"design_optimum: {k}": v for k, v in res.seconds.items()})
    nose, stay = res.nose, res.stay
    fig = optimum_figure(res.stay_map, title="lock stay: least unlock load, locking unaided at P <= 1e-6",
                         value_text=f"unlock load {stay.value:.1f} N")
    save_figure(fig, Path(out_dir) / "design_optimum_lockstay.png")
    active = "; ".join(f"{c} (multiplier {m:.4g})" for c, m in stay.active)
    return [
        "## Reliability-based design (beyond the paper)", "",
        f"SLSQP on exact gradients with FORM inside: P(not locking unaided) <= {P_MAX:g} stands for the reliability "
        "index beta >= 4.7534 of the downlock force, each toleranced design parameter's distribution centred on "
        "its design value.", "",
        f"* Nose gear, tolerances {_tolerances(NOSE_TOLERANCES)}: the longest nominal lock-spring free length "
        f"is LU = {nose.design['LU']:.9f} m (beta = {nose.quantities['beta(not locking)']:.5f}, "
        f"P = {nose.quantities['P(not locking)']:.4g}; {nose.iterations} iterations); its nominal downlock force is "
        f"{res.nose_force:.2f} N.",
        f"* Lock stay, tolerances {_tolerances(STAY_TOLERANCES)}: the least unlock load is "
        f"{stay.value:.3f} N at k = {stay.design['k']:.1f} N/m and LU = {stay.design['LU']:.9f} m (nominal downlock "
        f"force {res.stay_force:.2f} N; {stay.iterations} iterations). Active: {active}; the probability "
        "constraint's multiplier is the unlock load one more unit of beta costs.",
        "", "The lock stay's design map over (LU, k) with the optimum, the boundary P = 1e-6 traced through it and "
        "the stiffness's lower bound (active; the map is hatched beyond the design bounds):", "",
        "![lock stay optimum](design_optimum_lockstay.png)", "", *_sidestay_lines(res)]


def _sidestay_lines(res: DesignOptima) -> list[str]:
    """The dual-sidestay optimum's Markdown lines."""
    ds, nom = res.sidestay, res.sidestay_nominal
    if ds is None or nom is None:
        return []
    active = "; ".join(f"{c} (multiplier {m:.4g})" for c, m in ds.active)
    return [
        f"* Dual-sidestay gear (both lock-link pairs on overcentre stops, one lock-spring design for both): the least "
        f"unlock load of both pairs together is {ds.value:.3f} N at k_lock = {ds.design['k_lock']:.1f} N/m and "
        f"stretch = {ds.design['stretch']:.6f}, with each stop's preload at rest at least {DS_MARGIN:g} N m (fwd "
        f"{ds.quantities['R_fwd_stop']:.4f}, aft {ds.quantities['R_aft_stop']:.4f} N m; {ds.iterations} iterations). "
        f"The description's springs (k_lock = {nom['k_lock']:g} N/m, stretch = {nom['stretch']:g}) need "
        f"{nom['unlock_force']:.1f} N with "
        f"preloads fwd {nom['R_fwd_stop']:.1f}, aft {nom['R_aft_stop']:.1f} N m. Active: {active}: a softer spring "
        "stretched further gives the same preload for less unlock load, down to the stretch allowed. "
        "Deterministic: the probability constraint's FORM holds a downlock force, not a stop's reaction.", ""]
