"""The sampling checks of FORM: importance sampling around the design point and plain Monte Carlo,
and the findings that say when FORM is outside its domain.

FORM answers a rare-event question: the failure domain far from the mean. Outside that domain
its numbers mislead unless told: when the mean design already fails, FORM's point is the nearest
*safe* point, ``beta < 0`` and ``P`` is near 1, so the importance sampling around that point
estimates the safe probability ``1 - P`` (weighting failures there would weigh a near-certain
event by vanishing weights: the nose gear at LU = 1.35 m gave 0.39 for a truth of 0.9995); an
importance sampling that sees no sample of its event checks nothing. Each case is a finding (a
line of :attr:`ReliabilityResult.findings <mechcont.analysis.reliability.ReliabilityResult>`),
with a plain Monte Carlo estimate where ``n`` samples are expected to see at least
:data:`MC_EVENTS` of the rarer outcome.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .reliability import Variables

__all__ = ["ImportanceSampling", "MonteCarlo", "importance_sampling", "monte_carlo", "MC_EVENTS"]

#: Expected count of the rarer outcome that makes a plain Monte Carlo estimate worth its samples.
MC_EVENTS = 10


@dataclass(frozen=True)
class ImportanceSampling:
    """An importance-sampling estimate: ``probability`` of failure, its coefficient of variation ``cov``,
    ``n`` samples (``failed`` of which could not be solved and were left out), ``seconds``; ``event`` the
    outcome whose weights were summed (``"failure"``, or ``"safe"`` when the mean design fails: then
    ``probability`` is one minus the safe estimate) and ``hits`` the samples in it."""

    probability: float
    cov: float
    n: int
    failed: int
    seconds: float
    ran_on: str = "this process"
    event: str = "failure"
    hits: int = -1


@dataclass(frozen=True)
class MonteCarlo:
    """A plain Monte Carlo estimate: ``failures`` of ``n`` solved samples (``failed`` not solved),
    ``probability = failures / n`` and its standard error ``sqrt(p (1 - p) / n)``."""

    probability: float
    standard_error: float
    n: int
    failures: int
    failed: int
    seconds: float


def importance_sampling(evaluate: Callable[[np.ndarray], np.ndarray], variables: Variables, u_star: np.ndarray, n: int,
                        seed: int = 0, *, safe: bool = False) -> ImportanceSampling:
    """``P(g <= 0)`` from ``n`` samples ``u ~ N(u*, I)`` weighted by ``phi(u) / phi(u - u*)``.

    ``evaluate(X)`` gives ``g`` at the rows of ``X`` (SI), ``nan`` where it could not be solved
    (such samples are left out and counted). With ``safe`` (a mean design that fails, ``u*`` the
    nearest safe point) the weights of the safe samples (``g > 0``) estimate ``1 - P``; ``cov`` is
    then that estimate's standard error divided by ``P``.
    """
    t0 = time.perf_counter()
    u_star = np.asarray(u_star, dtype=float)
    U = u_star + np.random.Generator(np.random.PCG64(seed)).standard_normal((n, len(u_star)))
    g = np.asarray(evaluate(variables.x(U)), dtype=float)
    ok = np.isfinite(g)
    w = np.exp(-U[ok] @ u_star + 0.5 * float(u_star @ u_star))
    inside = g[ok] > 0 if safe else g[ok] <= 0
    terms = np.where(inside, w, 0.0)
    m = int(ok.sum())
    q = float(terms.mean()) if m else float("nan")
    se = float(terms.std(ddof=1) / math.sqrt(m)) if m > 1 else float("nan")
    p = 1.0 - q if safe else q
    cov = se / p if p > 0 and math.isfinite(se) and (safe or q > 0) else float("nan")
    return ImportanceSampling(p, cov, n, n - m, time.perf_counter() - t0, event="safe" if safe else "failure",
                              hits=int(inside.sum()))


def monte_carlo(evaluate: Callable[[np.ndarray], np.ndarray], variables: Variables, n: int, seed: int = 0) -> MonteCarlo:
    """``P(g <= 0)`` from ``n`` samples of the distributions themselves (``u ~ N(0, I)``, seeded)."""
    t0 = time.perf_counter()
    U = np.random.Generator(np.random.PCG64(seed)).standard_normal((n, len(variables.names)))
    g = np.asarray(evaluate(variables.x(U)), dtype=float)
    ok = np.isfinite(g)
    m, k = int(ok.sum()), int((g[ok] <= 0).sum())
    p = k / m if m else float("nan")
    return MonteCarlo(p, math.sqrt(p * (1 - p) / m) if m else float("nan"), m, k, n - m, time.perf_counter() - t0)


def form_findings(limit_state: str, g_mean: float, probability: float, sampling: ImportanceSampling | None,
                  n: int) -> tuple[list[str], bool]:
    """The findings about FORM's domain (one line each), and whether a Monte Carlo estimate of ``n``
    samples is cheap enough to add (it would see :data:`MC_EVENTS` of the rarer outcome)."""
    lines: list[str] = []
    cheap = n > 0 and n * min(probability, 1.0 - probability) >= MC_EVENTS
    if g_mean <= 0:
        lines.append(f"the mean design already fails ({limit_state} = {g_mean:.6g} at the mean): FORM's point is the "
                     "nearest safe point, beta < 0 and P = Phi(-beta) > 1/2; the importance sampling estimates the "
                     "safe probability 1 - P")
    if sampling is not None and sampling.hits == 0:
        what = "safe sample" if sampling.event == "safe" else "failure"
        lines.append(f"importance sampling saw no {what} in its {sampling.n} samples around the design point: it "
                     "checks nothing" + ("" if sampling.event == "safe" else
                                         " (a failure domain elsewhere, or a design point that is not one)"))
    if lines and n > 0 and not cheap:
        rare = min(probability, 1.0 - probability)
        lines.append(f"no Monte Carlo check: {n} samples would see fewer than {MC_EVENTS} of the rarer outcome "
                     + (f"(it needs about {MC_EVENTS / rare:.2g})" if rare > 0 else
                        f"(P = {probability:.6g} to double precision)"))
    return lines, bool(lines) and cheap
