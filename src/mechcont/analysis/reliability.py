"""Rare-event reliability: FORM and SORM on exact gradients, checked by importance sampling.

A limit state ``g(x)`` of independent random parameters ``x`` (failure where ``g <= 0``; for
the downlock, ``g`` is the downlock force: the gear does not lock unaided where it is not
positive) is mapped to standard normal space by the exact transform of independent variables
``u_i = Phi^-1(F_i(x_i))`` (Rosenblatt's, which is Nataf's without correlation). There:

* **FORM**: the most probable failure point ``u*`` (the point of ``g = 0`` nearest the origin)
  by the improved Hasofer-Lind-Rackwitz-Fiessler iteration (iHL-RF: the HL-RF direction with
  an Armijo step on the merit ``|u|^2/2 + c|g|``), on the exact gradient
  ``dg/du = dg/dx * dx/du`` (``dg/dx`` from :mod:`mechcont.analysis.sensitivity`, one linear
  solve). ``beta = alpha . u*`` (negative when the mean design fails), ``P = Phi(-beta)``,
  the importance of each variable ``alpha_i^2`` (they sum to 1).
* **SORM** (Breitung): ``P = Phi(-beta) prod (1 + beta kappa_i)^-1/2`` with the principal
  curvatures ``kappa_i`` of the limit state at ``u*`` (positive: curving away from the origin,
  a smaller failure domain). The curvatures come from central differences of the *exact*
  gradient in ``u`` (step :data:`CURVATURE_STEP` standard deviations), not from exact second
  derivatives.
* **Importance sampling** around ``u*``: ``u ~ N(u*, I)``, weights ``phi(u)/phi(u - u*)``,
  the probability with its coefficient of variation; the limit state at the samples is the
  batched downlock solve of the studies (:func:`mechcont.analysis.study.run_chunk`), chunk by
  chunk in this process or on Dask.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from .._status import Status
from ..errors import ConvergenceError, InputError
from ._reliability_checks import ImportanceSampling, MonteCarlo, form_findings, importance_sampling, monte_carlo
from .sensitivity import write_json
from .study._spec import Distribution, StudySpec

if TYPE_CHECKING:
    from distributed import Client
    from scipy.stats.distributions import rv_frozen

    from ..equations import Model
    from .study import ModelSource

__all__ = ["Variables", "DesignPoint", "ImportanceSampling", "MonteCarlo", "ReliabilityResult", "form", "sorm_breitung",
           "importance_sampling", "monte_carlo", "reliability", "downlock_limit_state", "downlock_reliability"]

#: Step (standard deviations) of the central differences of the exact gradient that give the curvatures.
CURVATURE_STEP = 1e-3
#: Importance-sampling samples when not given.
DEFAULT_SAMPLES = 2000
#: Distance from the mean (standard deviations in u) beyond which a search that has not seen the limit state
#: change sign stops: Phi(-38.5) is already below the smallest double.
U_LIMIT = 1000.0

#: ``limit(x) -> (g, dg/dx)``: the limit state and its gradient at the variables' values ``x`` (SI).
LimitState = Callable[[np.ndarray], tuple[float, np.ndarray]]


def _frozen(d: Distribution) -> rv_frozen:
    """SciPy's frozen distribution of ``d``."""
    from scipy import stats

    p = d.fields
    if d.kind == "uniform":
        return stats.uniform(loc=p["low"], scale=p["high"] - p["low"])
    if d.kind == "normal":
        return stats.norm(loc=p["mean"], scale=p["sd"])
    return stats.truncnorm((p["low"] - p["mean"]) / p["sd"], (p["high"] - p["mean"]) / p["sd"], loc=p["mean"],
                           scale=p["sd"])


class Variables:
    """Independent random variables and the exact transform ``u = Phi^-1(F(x))`` to standard normal space.

    ``shift`` (SI, one per variable) moves a distribution bodily: ``x = shift + F^-1(Phi(u))``
    (a tolerance about a designed nominal value). Arrays of ``u`` or ``x`` have the variables
    along the last axis. Upper tails are computed from the survival functions, so ``u = 6``
    keeps its precision.
    """

    def __init__(self, names: Sequence[str], dists: Sequence[Distribution], shift: Sequence[float] | None = None):
        self.names, self.dists = list(names), list(dists)
        self.frozen = [_frozen(d) for d in self.dists]
        self.shift = np.zeros(len(self.names)) if shift is None else np.asarray(shift, dtype=float)

    def x(self, u: np.ndarray) -> np.ndarray:
        """The variables' values (SI) at standard normal ``u``."""
        from scipy.stats import norm

        u = np.asarray(u, dtype=float)
        out = np.empty_like(u)
        for j, fr in enumerate(self.frozen):
            uj = u[..., j]
            if self.dists[j].kind == "normal":
                out[..., j] = fr.mean() + fr.std() * uj
            else:
                out[..., j] = np.where(uj <= 0, fr.ppf(norm.cdf(uj)), fr.isf(norm.sf(uj)))
        return out + self.shift

    def u(self, x: np.ndarray) -> np.ndarray:
        """Standard normal ``u`` of the variables' values ``x`` (SI)."""
        from scipy.stats import norm

        x = np.asarray(x, dtype=float) - self.shift
        out = np.empty_like(x)
        for j, fr in enumerate(self.frozen):
            F, S = fr.cdf(x[..., j]), fr.sf(x[..., j])
            out[..., j] = np.where(F <= 0.5, norm.ppf(F), norm.isf(S))
        return out

    def dx_du(self, u: np.ndarray) -> np.ndarray:
        """``dx_i/du_i = phi(u_i) / f_i(x_i)`` (the transform is diagonal)."""
        from scipy.stats import norm

        u = np.asarray(u, dtype=float)
        x = self.x(u) - self.shift
        return np.array([norm.pdf(u[..., j]) / fr.pdf(x[..., j]) if self.dists[j].kind != "normal" else
                         np.full(np.shape(u[..., j]), fr.std()) for j, fr in enumerate(self.frozen)]).T


@dataclass(frozen=True)
class DesignPoint:
    """The most probable failure point found by :func:`form`.

    ``u`` (standard normal) and ``x`` (SI) the point, ``beta = alpha . u``, ``alpha`` the unit
    vector ``-grad_u g / |grad_u g|``, ``grad_u`` and ``grad_x`` the limit state's gradients
    there, ``g`` its value (about 0), ``iterations`` of iHL-RF and ``evaluations`` of ``g``;
    ``g_start`` the limit state at the start (the mean by default: failing there when <= 0).
    """

    u: np.ndarray
    x: np.ndarray
    beta: float
    alpha: np.ndarray
    grad_u: np.ndarray
    grad_x: np.ndarray
    g: float
    iterations: int
    evaluations: int
    g_start: float = math.nan


def form(limit: LimitState, variables: Variables, *, u0: np.ndarray | None = None, tol: float = 1e-9,
         max_iter: int = 500) -> DesignPoint:
    """The most probable failure point of ``limit`` (failure where ``g <= 0``) by iHL-RF from ``u0`` (default the mean).

    Converged when ``|g| <= tol`` times ``|g|`` at the start (or its gradient's length) and
    ``u`` is parallel to the gradient to ``1e-6``. Raises
    :class:`~mechcont.errors.ConvergenceError` when the gradient vanishes or the iteration
    does not converge in ``max_iter``, and one that says so when the limit state has no root along the
    search (``g`` keeps the sign it had at the start out to ``|u| =`` :data:`U_LIMIT`, where no probability
    is left in double precision).
    """
    n = len(variables.names)
    u = np.zeros(n) if u0 is None else np.asarray(u0, dtype=float).copy()
    count = [0]

    def at(u: np.ndarray) -> tuple[np.ndarray, float, np.ndarray, np.ndarray]:
        count[0] += 1
        x = variables.x(u)
        g, gx = limit(x)
        return x, float(g), np.asarray(gx, dtype=float), np.asarray(gx, dtype=float) * variables.dx_du(u)

    x, g, gx, gu = at(u)
    g_start, x_start = g, x
    scale = float(max(abs(float(g)), float(np.linalg.norm(gu)), 1e-300))  # g is divided by this: the merit is unit-free
    for it in range(1, max_iter + 1):
        norm = float(np.linalg.norm(gu))
        if not norm > 0:
            raise ConvergenceError(f"FORM: the limit state's gradient in standard normal space vanishes at "
                                   f"{_where(variables, x)} (g = {g:.6g}): no failure point within the distributions' "
                                   "range (the edge of a bounded one?)")
        alpha = -gu / norm
        # a root: g small against its scale, and against its slope (a g that only decays towards 0, as
        # exp(-u) does, is small far from any root)
        if (abs(g) <= tol * scale and abs(g) <= 1e-6 * norm
                and np.linalg.norm(u - (alpha @ u) * alpha) <= 1e-6 * max(1.0, float(np.linalg.norm(u)))):
            return DesignPoint(u, x, float(alpha @ u), alpha, gu, gx, g, it - 1, count[0], g_start)
        if float(np.linalg.norm(u)) > U_LIMIT and g * g_start > 0:
            raise _no_root(variables, g_start, x_start, g, x, u, count[0])
        d = (alpha @ u + g / norm) * alpha - u  # towards the HL-RF point
        c = 2.0 * float(np.linalg.norm(u)) / (norm / scale) + 10.0  # > |u| / |grad|: d descends the merit
        m0, slope = _merit(u, g, c, scale), float((u + c * np.sign(g) * gu / scale) @ d)
        step = 1.0
        while True:
            try:
                trial = at(u + step * d)
            except (ConvergenceError, InputError):
                trial = None
            if trial is not None and _merit(u + step * d, trial[1], c, scale) <= m0 + 1e-4 * step * min(slope, 0.0):
                break
            step *= 0.5
            if step < 1e-6:
                if trial is None:
                    raise ConvergenceError(f"FORM: the limit state cannot be solved near {_where(variables, x)}")
                break
        u = u + step * d
        x, g, gx, gu = trial
    if g * g_start > 0:
        raise _no_root(variables, g_start, x_start, g, x, u, count[0])
    raise ConvergenceError(f"FORM did not converge in {max_iter} iterations (last g = {g:.6g} at {_where(variables, x)})")


def _no_root(variables: Variables, g0: float, x0: np.ndarray, g: float, x: np.ndarray, u: np.ndarray,
             solves: int) -> ConvergenceError:
    """The error of a search that never saw the limit state change sign."""
    side = "positive (safe)" if g0 > 0 else "not positive (failing)"
    p = "0" if g0 > 0 else "1"
    return ConvergenceError(f"FORM: the limit state has no root along the search: g stays {side} from g = {g0:.6g} at "
                            f"{_where(variables, x0)} to g = {g:.6g} at {_where(variables, x)} ({float(np.linalg.norm(u)):.3g} "
                            f"standard deviations out, {solves} solves): P(g <= 0) is {p} to double precision along this path")


def _merit(u: np.ndarray, g: float, c: float, scale: float) -> float:
    """iHL-RF's merit ``|u|^2/2 + c |g| / scale``."""
    return 0.5 * float(u @ u) + c * abs(g) / scale


def _where(variables: Variables, x: np.ndarray) -> str:
    return ", ".join(f"{n} = {v:.6g}" for n, v in zip(variables.names, x))


def curvatures(limit: LimitState, variables: Variables, point: DesignPoint, h: float = CURVATURE_STEP) -> np.ndarray:
    """Principal curvatures of ``g = 0`` at the design point (positive: curving away from the origin).

    The Hessian in ``u`` from central differences of the exact gradient (step ``h``),
    projected on the tangent plane and divided by ``|grad_u g|``.
    """
    n = len(point.u)
    if n == 1:
        return np.zeros(0)

    def grad_u(u: np.ndarray) -> np.ndarray:
        return np.asarray(limit(variables.x(u))[1], dtype=float) * variables.dx_du(u)

    H = np.column_stack([(grad_u(point.u + h * e) - grad_u(point.u - h * e)) / (2 * h) for e in np.eye(n)])
    H = 0.5 * (H + H.T)
    Q = np.linalg.qr(np.column_stack([point.alpha, np.eye(n)]))[0][:, 1:n]  # the tangent plane's basis
    return np.linalg.eigvalsh(Q.T @ H @ Q / np.linalg.norm(point.grad_u))


def sorm_breitung(beta: float, kappa: np.ndarray) -> float:
    """Breitung's ``Phi(-beta) prod (1 + beta kappa_i)^-1/2``; for ``beta < 0`` one minus the safe set's.

    ``nan`` where some ``1 + beta kappa_i <= 0`` (the parabolic approximation has no finite probability).
    """
    from scipy.stats import norm

    f = 1.0 + beta * np.asarray(kappa, dtype=float)
    if np.any(f <= 0):
        return float("nan")
    factor = float(np.prod(f ** -0.5))
    return float(norm.cdf(-beta) * factor) if beta >= 0 else float(1.0 - norm.cdf(beta) * factor)


@dataclass(frozen=True)
class ReliabilityResult:
    """The outcome of :func:`reliability`: FORM, SORM and the importance-sampling check.

    ``design_point`` ``{name: value}`` (SI), ``importance`` ``{name: alpha^2}``, ``curvatures``
    the principal curvatures (1/standard deviation), ``sampling`` the importance-sampling
    check (None when not run), ``units`` ``{name: unit}``; ``findings`` one line each where FORM is
    outside its domain (a mean design that fails, an importance sampling that saw none of its event)
    and ``monte_carlo`` a plain Monte Carlo estimate, made then when it is cheap (see
    :mod:`mechcont.analysis._reliability_checks`).
    """

    beta: float
    probability: float
    probability_sorm: float
    design_point: dict[str, float]
    importance: dict[str, float]
    curvatures: list[float]
    iterations: int
    evaluations: int
    sampling: ImportanceSampling | None = None
    units: dict[str, str] = field(default_factory=dict)
    limit_state: str = "g"
    seconds: float = 0.0
    findings: list[str] = field(default_factory=list)
    monte_carlo: MonteCarlo | None = None

    def to_dict(self) -> dict:
        """JSON-ready: beta, probability (FORM), probability_sorm, design_point, importance and the rest (SI)."""
        doc = {"beta": self.beta, "probability": self.probability, "probability_sorm": self.probability_sorm,
               "sorm": "Breitung, curvatures from central differences of the exact gradient",
               "design_point": self.design_point, "importance": self.importance, "curvatures": self.curvatures,
               "limit_state": self.limit_state, "iterations": self.iterations, "evaluations": self.evaluations,
               "seconds": self.seconds, "units": self.units}
        if self.sampling is not None:
            s = self.sampling
            doc["importance_sampling"] = {"probability": s.probability, "cov": s.cov, "n": s.n, "failed": s.failed,
                                          "seconds": s.seconds, "ran_on": s.ran_on, "event": s.event, "hits": s.hits}
        if self.monte_carlo is not None:
            m = self.monte_carlo
            doc["monte_carlo"] = {"probability": m.probability, "standard_error": m.standard_error, "n": m.n,
                                  "failures": m.failures, "failed": m.failed, "seconds": m.seconds}
        doc["findings"] = list(self.findings)
        return doc

    def to_json(self, path: str | os.PathLike) -> None:
        """Write :meth:`to_dict` as JSON, atomically."""
        write_json(path, self.to_dict())

    def summary(self) -> str:
        """Plain text: beta, the probabilities, the design point and the importances."""
        lines = [f"FORM: beta = {self.beta:.6g}, P({self.limit_state} <= 0) = {self.probability:.6g} "
                 f"({self.iterations} iterations, {self.evaluations} solves)",
                 f"SORM (Breitung): P = {self.probability_sorm:.6g}"]
        if self.sampling is not None:
            s = self.sampling
            of = "" if s.event == "failure" else ", as 1 - P(safe)"
            lines.append(f"importance sampling: P = {s.probability:.6g}, coefficient of variation {s.cov:.3g} "
                         f"({s.n} samples, {s.hits} in the {s.event} domain{of}, {s.failed} failed, {s.ran_on})")
        if self.monte_carlo is not None:
            m = self.monte_carlo
            lines.append(f"Monte Carlo: P = {m.probability:.6g}, standard error {m.standard_error:.2g} ({m.failures} "
                         f"failures in {m.n} samples, {m.failed} failed)")
        lines.append("design point (most probable failure point) and importance alpha^2:")
        w = max(len(n) for n in self.design_point)
        lines += [f"  {n:>{w}} = {v:.10g} {self.units.get(n, '')}  alpha^2 {self.importance[n]:.4f}"
                  for n, v in self.design_point.items()]
        return "\n".join(lines)


def reliability(limit: LimitState, variables: Variables, *, evaluate: Callable[[np.ndarray], np.ndarray] | None = None,
                n: int = 0, seed: int = 0, sorm: bool = True, u0: np.ndarray | None = None,
                limit_state: str = "g") -> ReliabilityResult:
    """FORM, SORM (Breitung) and, with ``evaluate`` and ``n > 0``, importance sampling, of ``limit``.

    ``limit(x) -> (g, dg/dx)`` (failure ``g <= 0``); ``evaluate(X) -> g`` at many rows (SI)
    for the sampling. When the start (the mean) already fails, the importance sampling estimates
    the safe probability instead; that and a sampling that saw none of its event are findings,
    with a plain Monte Carlo estimate of ``n`` samples (seed ``seed + 1``) where it would see
    :data:`~mechcont.analysis._reliability_checks.MC_EVENTS` of the rarer outcome. Returns a
    :class:`ReliabilityResult`.
    """
    import time

    from scipy.stats import norm

    t0 = time.perf_counter()
    p = form(limit, variables, u0=u0)
    kappa = curvatures(limit, variables, p) if sorm else np.zeros(0)
    fails = u0 is None and p.g_start <= 0  # from another start, g there says nothing about the mean
    sample = evaluate is not None and n > 0
    sampling = importance_sampling(evaluate, variables, p.u, n, seed, safe=fails) if evaluate is not None and n > 0 \
        else None
    probability = float(norm.cdf(-p.beta))
    findings, cheap = form_findings(limit_state, p.g_start if u0 is None else math.inf, probability, sampling,
                                    n if sample else 0)
    mc = monte_carlo(evaluate, variables, n, seed + 1) if cheap and evaluate is not None else None
    names = variables.names
    return ReliabilityResult(p.beta, probability, sorm_breitung(p.beta, kappa) if sorm else float("nan"),
                             {k: float(v) for k, v in zip(names, p.x)},
                             {k: float(a * a) for k, a in zip(names, p.alpha)}, [float(k) for k in kappa],
                             p.iterations, p.evaluations + (2 * len(names) if len(kappa) else 0), sampling,
                             limit_state=limit_state, seconds=time.perf_counter() - t0, findings=findings,
                             monte_carlo=mc)


# -- the downlock force as the limit state ---------------------------------------------------------
def downlock_limit_state(system: Model, names: Sequence[str], values: Mapping[str, float] | None = None, *,
                         hold: Mapping[str, float] | None = None, force: str | None = None,
                         condition: str | None = None, threshold: float = 0.0) -> LimitState:
    """``x -> (F(x) - threshold, dF/dx)``: the downlock force (N) at the values ``x`` of ``names``, exact gradient.

    The other parameters at ``values`` (SI). Failure (``g <= 0``): the gear does not lock unaided.
    """
    from .sensitivity import downlock_sensitivity

    names, fixed = list(names), dict(values or {})

    def limit(x: np.ndarray) -> tuple[float, np.ndarray]:
        s = downlock_sensitivity(system, names, {**fixed, **{n: float(v) for n, v in zip(names, x)}}, hold=hold,
                                 force=force, condition=condition)
        return s.value - threshold, np.array([s[n] for n in names])

    return limit


def _is_chunk(source: ModelSource, spec: StudySpec, S: np.ndarray) -> np.ndarray:
    """The downlock force at the rows ``S`` (a chunk of a study's samples); ``nan`` where a solve failed."""
    from .study import load_study_model, run_chunk

    system = load_study_model(source)
    cols = run_chunk(system, replace(spec, n=len(S), chunk=len(S)), 0, samples=S)
    return np.where(cols["status"] == Status.CONVERGED, cols["downlock_force"], np.nan).astype(float)


def _study_evaluate(spec: StudySpec, source: ModelSource, scheduler: str | None, workers: int | None, ran_on: list[str],
                    threshold: float) -> Callable[[np.ndarray], np.ndarray]:
    """``X -> F(X) - threshold`` by the studies' batched chunks, where ``scheduler`` says
    (:func:`mechcont.analysis.study.run_parts`; ``ran_on[0]`` says where the last call ran)."""
    def evaluate(X: np.ndarray) -> np.ndarray:
        from .study import run_parts

        parts = [X[i:i + spec.chunk] for i in range(0, len(X), spec.chunk)]
        out: dict[int, np.ndarray] = {}

        def here(k: int) -> float:
            t = time.perf_counter()
            out[k] = _is_chunk(source, spec, parts[k])
            return time.perf_counter() - t

        def there(client: Client, ks: Sequence[int]) -> None:
            shipped_source, shipped_spec = client.scatter([source, spec], broadcast=True)
            futures = [client.submit(_is_chunk, shipped_source, shipped_spec, parts[k], pure=False) for k in ks]
            out.update(zip(ks, client.gather(futures)))

        ran_on[0] = run_parts({k: len(S) for k, S in enumerate(parts)}, here, there, scheduler, workers)
        return np.concatenate([out[k] for k in range(len(parts))]) - threshold

    return evaluate


def downlock_reliability(spec: StudySpec, *, n: int | None = None, seed: int | None = None, threshold: float = 0.0,
                         scheduler: str | None = None, workers: int | None = None) -> ReliabilityResult:
    """P(not locking unaided) for the distributions of the study ``spec``: FORM, SORM and importance sampling.

    The limit state is the downlock force minus ``threshold`` (N) at the spec's condition,
    the other parameters at the spec's ``values``; ``n`` importance samples (default the
    spec's ``n``; 0 for none) drawn with ``seed`` (default the spec's), solved in chunks of
    the spec's ``chunk`` as a study solves them: in this process (``scheduler=None``), on a
    local Dask cluster (``"local"``), at a scheduler's address, or ``"auto"`` (a local cluster only when the
    samples' computing, timed on their first chunk, would pay for its start: :func:`mechcont.analysis.study.run_parts`).
    """
    from .study import ModelSource, check_scheduler, check_spec, load_study_model

    check_scheduler(scheduler, workers)

    if spec.sampling == "grid":
        raise InputError("--method", "form needs distributions (--dist), not a grid")
    spec = spec.with_model_hash()
    source = ModelSource.of(spec.model)
    system = load_study_model(source)
    check_spec(system, spec)
    names = list(spec.names)
    variables = Variables(names, [d for _, d in spec.parameters])
    limit = downlock_limit_state(system, names, dict(spec.values), hold=dict(spec.hold) or None, force=spec.force,
                                 condition=spec.condition, threshold=threshold)
    ran_on = ["this process"]
    evaluate = _study_evaluate(spec, source, scheduler, workers, ran_on, threshold)
    result = reliability(limit, variables, evaluate=evaluate, n=spec.n if n is None else n,
                         seed=spec.seed if seed is None else seed, limit_state="downlock_force" +
                         (f" - {threshold:g}" if threshold else ""))
    sampling = None if result.sampling is None else replace(result.sampling, ran_on=ran_on[0])
    return replace(result, sampling=sampling, units={k: system.variable(k).unit for k in names})
