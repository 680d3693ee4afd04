"""Continuation of periodic orbits in one parameter: pseudo-arclength on the collocation BVP.

:func:`continue_cycles` follows a family from a :class:`~._cycle_start.CycleStart` (a Hopf point,
:func:`cycles_from_hopf`, or a sampled simulation, :func:`cycles_from_samples`). Each step predicts
along the unit tangent, corrects by Newton on the hyperplane orthogonal to it (the phase condition
against the predicted orbit), takes the new tangent from the same factors, and computes the Floquet
multipliers. The step grows after an easy correction and halves after a failed one or a tangent
that turned more than ``max_angle`` (:class:`~._palc.StepSizeController`). Every ``adapt`` steps the
mesh is re-equidistributed and the current orbit corrected on it.

Test functions between consecutive orbits, zeros located inside the step: ``LPC`` the tangent's
parameter component (Brent's method on the step length); ``PD`` the product of ``1 + mu`` over the
real negative multipliers; ``NS`` the product of ``|mu| - 1`` over the complex pairs (each checked
at the located orbit: a multiplier at -1, a pair on the unit circle, and the trivial multiplier at 1, without
which the multipliers are too inaccurate to tell); ``UZ`` and the bounds (``EP``)
the parameter (or period) minus the value, solved exactly with the parameter held.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from .._roots import brentq
from .._status import Status
from ..equations import velocity_coordinate
from ..errors import ConvergenceError, InputError
from ..units import derivative_unit
from ._collocation import NCOL_RANGE, Mesh
from ._cycle_branch import CycleBranch
from ._cycle_start import CycleStart, hopf_point, hopf_start, samples_start
from ._cycle_system import CycleSystem, NewtonFailure, RateFunction, nontrivial_multipliers, phase_reference, split_multipliers
from ._cycle_tests import (
    HOMOCLINIC_STEPS,
    HOPF_AMPLITUDE,
    ON_CIRCLE,
    UNSTABLE,
    VERTICAL_STEPS,
    _amplitude,
    _amplitude_slope,
    _fold_confirmed,
    _ns,
    _pd,
    _period_runs_away,
    _Point,
)
from ._hopf_point import state_scales
from ._options import ContinuationOptions
from ._palc import StepSizeController

if TYPE_CHECKING:
    from ..equations import Dynamics, Model

__all__ = ["continue_cycles", "cycles_from_hopf", "cycles_from_samples"]

def _check_options(ntst: int, ncol: int, adapt: int) -> None:
    if not (isinstance(ntst, int) and ntst >= 2):
        raise InputError("ntst", f"must be an integer >= 2 (mesh intervals), got {ntst!r}")
    if not (isinstance(ncol, int) and NCOL_RANGE[0] <= ncol <= NCOL_RANGE[1]):
        raise InputError("ncol", f"must be an integer in {NCOL_RANGE[0]}..{NCOL_RANGE[1]} (collocation points per "
                                 f"interval), got {ncol!r}")
    if not (isinstance(adapt, int) and adapt >= 0):
        raise InputError("adapt", f"must be an integer >= 0 (steps between mesh adaptations; 0: never), got {adapt!r}")


def _system(model: Model, vary: str, x: np.ndarray, ntst: int, ncol: int, options: ContinuationOptions,
            omega: float = 1.0) -> tuple[Dynamics, CycleSystem]:
    from ..equations import dynamics_of

    dyn = dynamics_of(model)
    if vary not in model.names or vary in dyn.state_names:
        raise InputError("vary", f"'{vary}' is not a parameter of '{model.name}'; the family is continued in a "
                                 f"parameter, not in a state ({', '.join(dyn.state_names)})")
    rates = RateFunction(model, dyn, vary, x)
    p_scale = options.scales.get(vary, model.variable(vary).scale)
    return dyn, CycleSystem(rates, Mesh(ntst, ncol), _weights(model, dyn, options, omega), 1.0 / p_scale ** 2)


def _weights(model: Model, dyn: Dynamics, options: ContinuationOptions, omega: float) -> np.ndarray:
    """The states' weights in the orbit's norm: 1 / scale^2 (:func:`~._hopf_point.state_scales`, options.scales
    over them); without the velocity states' factor omega they would swamp the norm."""
    scale = state_scales(dyn, model, omega)
    return np.array([1.0 / options.scales.get(n, s) ** 2 for n, s in zip(dyn.state_names, scale)])


def cycles_from_hopf(model: Model, x: np.ndarray, vary: str, *, options: ContinuationOptions | None = None, ntst: int = 20,
                     ncol: int = 4, at: Sequence[float] = (), adapt: int = 3,
                     progress: Callable[[int], object] | None = None) -> CycleBranch:
    """The family of periodic orbits born at the Hopf point near the full vector ``x``, continued in ``vary``.

    ``x``: a model vector on (or near) an equilibrium branch at a Hopf point (an ``HB`` row); it is
    refined to the Hopf point (:func:`~._cycle_start.hopf_point`). ``ntst`` mesh intervals, ``ncol``
    collocation points each; ``at``: values of ``vary`` where rows are located exactly (``UZ``);
    ``adapt``: steps between mesh adaptations. ``options``: step control (``ds``, ``dsmin``, ``dsmax``, in
    the orbit's L2 norm and the parameter's scale), ``max_steps``, ``bounds`` (on ``vary`` and/or ``period``),
    and its ``engine`` settings (``newton_tol``, ``max_newton``, ``max_angle``). Returns a :class:`CycleBranch`
    (first row ``HB``).
    Raises :class:`InputError` when ``x`` is not near a Hopf point, :class:`ConvergenceError` (with the
    start in ``partial``) when the family cannot start.
    """
    options = options or ContinuationOptions()
    _check_options(ntst, ncol, adapt)
    dyn, system = _system(model, vary, x, ntst, ncol, options)
    hopf = hopf_point(model, dyn, x, vary)
    system = CycleSystem(system.rates, system.mesh, _weights(model, dyn, options, hopf.omega), system.p_weight)
    system.rates.x_base = hopf.x.copy()
    start = hopf_start(system, hopf)
    return continue_cycles(model, system, start, vary, options, at=at, adapt=adapt, progress=progress,
                           hopf_eigenvalues=np.linalg.eigvals(dyn.rates_jacobian(hopf.z, hopf.x)))


def cycles_from_samples(model: Model, x: np.ndarray, t: np.ndarray, Z: np.ndarray, vary: str, *,
                        options: ContinuationOptions | None = None, ntst: int = 20, ncol: int = 4, direction: int = 1,
                        at: Sequence[float] = (), adapt: int = 3, progress: Callable[[int], object] | None = None) -> CycleBranch:
    """The family through a periodic solution of a time simulation, continued in ``vary``.

    ``x``: the model's full vector of the simulation (its parameters); ``t`` (s) and ``Z`` (states,
    ``dynamics_of(model).state_names`` order) sample the converged motion over at least two periods.
    The period is read from the returns to a Poincaré section and the orbit corrected at ``x``'s
    parameters (:func:`~._cycle_start.samples_start`); ``direction`` +1 continues towards larger
    ``vary``, -1 smaller. Other arguments as :func:`cycles_from_hopf`.
    """
    options = options or ContinuationOptions()
    _check_options(ntst, ncol, adapt)
    if direction not in (1, -1):
        raise InputError("direction", f"must be +1 or -1, got {direction!r}")
    _, system = _system(model, vary, x, ntst, ncol, options)
    start = samples_start(system, t, Z, x, tol=options.engine.newton_tol, max_iter=max(options.engine.max_newton, 20))
    return continue_cycles(model, system, start, vary, options, at=at, adapt=adapt, progress=progress,
                           direction=direction)


class _Run:
    """One continuation of a family (the state of :func:`continue_cycles`)."""

    def __init__(self, system: CycleSystem, options: ContinuationOptions, at: Sequence[float], adapt: int) -> None:
        self.system, self.options, self.adapt = system, options, adapt
        self.control = StepSizeController(options)
        self.points: list[_Point] = []
        self.max_amplitude = 0.0
        self.s: list[float] = []
        bounds: Mapping[str, tuple[float, float]] = options.bounds
        self.values: list[tuple[str, int, float]] = []  # (label, unknown's index from the end, value)
        vary = system.rates.vary
        for name, (lo, hi) in bounds.items():
            if name not in (vary, "period"):
                raise InputError("bounds", f"'{name}' cannot bound a family of cycles; bound {vary} or period")
            idx = -1 if name == vary else -2
            self.values += [("EP", idx, v) for v in (lo, hi) if math.isfinite(v)]
        self.values += [("UZ", -1, float(v)) for v in at]

    # -- one orbit ------------------------------------------------------------------------------
    def solve(self, cur: _Point, X0: np.ndarray, sigma: float, closing: np.ndarray | None = None,
              target: float | None = None) -> _Point:
        """The orbit on ``cur``'s system on the hyperplane ``<cur.t, X - X0> = sigma`` (or ``closing . X = target``),
        its tangent (pointing the way of ``cur.t``) and multipliers.

        From ``cur`` itself (``X0`` its orbit) the corrector starts from the second-order prediction ``X0 + sigma t +
        sigma^2 / 2 dt/ds`` where the last step estimated the tangent's turn (:attr:`_Point.curvature`): from the
        tangent alone the prediction errs by the family's curvature times sigma^2 / 2, which costs the corrector about
        one iteration per orbit at the default tolerance (and keeps the step control from lengthening the steps)."""
        o, system, row0 = self.options, cur.system, cur.row()
        pred = X0 + sigma * cur.t
        if cur.curvature is not None and X0 is cur.X:
            pred += (0.5 * sigma * sigma) * cur.curvature
        if closing is None or target is None:
            closing = row0
            target = float(closing @ pred)
        X, lu, iters = system.newton(pred, phase_reference(system, pred), closing, target, o.engine.newton_tol,
                                     o.engine.max_newton)
        t, r = system.tangent_and_row(lu, row0)
        # the multipliers from the last factors: their Jacobian is that of the converged orbit to within the tolerance
        mu = lu.multipliers()
        trivial, others = split_multipliers(mu)
        pt = _Point(system, X, t, others, trivial=trivial, r=r)
        pt.iterations = iters  # type: ignore[attr-defined]
        return pt

    def step(self, cur: _Point) -> _Point:
        """One accepted step from ``cur`` (the step size adapted); raises :class:`NewtonFailure` below ``dsmin``."""
        o = self.options
        while True:
            ds = self.control.ds
            try:
                new = self.solve(cur, cur.X, ds)
                cosang = float(cur.row() @ new.t)
                if cosang >= math.cos(o.engine.max_angle):
                    self.control.accept(new.iterations)  # type: ignore[attr-defined]
                    new.ds = ds  # type: ignore[attr-defined]
                    new.curvature = (new.t - cur.t) / ds  # both unit tangents on new's mesh (cur's)
                    return new
                why = f"tangent turned by {math.degrees(math.acos(max(-1.0, min(1.0, cosang)))):.1f} deg"
            except NewtonFailure as exc:
                why = str(exc)
            if not self.control.reject():
                raise NewtonFailure(f"step size fell below dsmin={o.dsmin:g}: {why}")

    def remesh(self, cur: _Point) -> _Point:
        """``cur`` on an adapted mesh: its orbit, tangent and curvature interpolated there (as AUTO does; the next step's
        corrector solves on the new mesh), its multipliers kept; ``cur`` itself when the mesh degenerates."""
        sys_ = cur.system
        u, T, p = sys_.split(cur.X)
        mesh = sys_.mesh.adapted(u)
        if not np.all(np.isfinite(mesh.h)) or mesh.h.min() <= 0:
            return cur
        new_sys = CycleSystem(sys_.rates, mesh, sys_.weights, sys_.p_weight)
        tu, tT, tp = sys_.split(cur.t)
        n = u.shape[1]
        parts = [u, tu]
        if cur.curvature is not None:
            ku, kT, kp = sys_.split(cur.curvature)
            parts.append(ku)
        both = sys_.mesh.moved(np.hstack(parts), mesh)  # one Lagrange basis for the orbit, its tangent and curvature
        X = new_sys.pack(both[:, :n], T, p)
        t = new_sys.pack(both[:, n:2 * n], tT, tp)
        r = new_sys.row(t)
        scale = 1.0 / math.sqrt(max(float(r @ t), 0.0))
        out = _Point(new_sys, X, t * scale, cur.mu, cur.label, cur.approximate, cur.trivial, r=r * scale)
        if cur.curvature is not None:
            out.curvature = new_sys.pack(both[:, 2 * n:], kT, kp)
        return out

    # -- events ---------------------------------------------------------------------------------
    def events(self, cur: _Point, new: _Point, ds: float) -> list[tuple[float, _Point]]:
        """The special orbits inside the step from ``cur`` to ``new`` (``ds``): located, with their step positions."""
        found: list[tuple[float, _Point]] = []
        for label, idx, v in self.values:
            a, b = cur.X[idx] - v, new.X[idx] - v
            if a == 0 or (a > 0) == (b > 0):
                continue
            closing = np.zeros(cur.system.size)
            closing[idx] = 1.0
            w = a / (a - b)
            try:
                pt = self.solve(cur, (1 - w) * cur.X + w * new.X, 0.0, closing, v)
            except NewtonFailure:
                continue
            pt.label = label
            found.append((w * ds, pt))
        tests: list[tuple[str, Callable[[_Point], float]]] = [("LPC", lambda q: float(q.t[-1])), ("PD", lambda q: _pd(q.mu)),
                                                                ("NS", lambda q: _ns(q.mu))]
        for label, fn in tests:
            a, b = fn(cur), fn(new)
            if a == 0 or (a > 0) == (b > 0):
                continue
            cache: dict[float, _Point] = {}

            def g(sigma: float, fn: Callable[[_Point], float] = fn, cache: dict[float, _Point] = cache) -> float:
                cache[sigma] = self.solve(cur, cur.X, sigma)
                return fn(cache[sigma])

            try:
                sigma = brentq(g, 0.0, ds, xtol=1e-13 * max(ds, 1e-6), fa=a, fb=b)
                pt = cache[sigma] if sigma in cache else self.solve(cur, cur.X, sigma)
            except (NewtonFailure, ValueError, RuntimeError):
                sigma, pt = ds, _Point(new.system, new.X, new.t, new.mu, approximate=True, trivial=new.trivial, r=new.r)
            if label in ("PD", "NS") and not abs(pt.trivial - 1.0) < ON_CIRCLE:
                continue  # the trivial multiplier is not 1: the multipliers are not accurate enough to tell
            if label == "PD" and not np.any((pt.mu.imag == 0) & (np.abs(pt.mu + 1) < ON_CIRCLE)):
                continue  # a pair of real multipliers met on the negative axis: not a crossing of -1
            if label == "NS" and not np.any((pt.mu.imag > 0) & (np.abs(np.abs(pt.mu) - 1) < ON_CIRCLE)):
                continue  # a real pair became complex inside the circle: not a torus bifurcation
            pt.label = label
            if label == "LPC":
                small = _amplitude(pt) < HOPF_AMPLITUDE * self.max_amplitude
                # the orbit shrunk to nearly a point, far smaller than its neighbour: the family passed through a
                # Hopf point (where its amplitude changes sign), whatever the multipliers say (a planar cycle's one
                # non-trivial multiplier also tends to 1 there)
                through = small and _amplitude(pt) < HOPF_AMPLITUDE * max(_amplitude(cur), _amplitude(new))
                # where the fold could not be located on the step (Newton fails on the nearly-point orbits around a
                # Hopf point, and pt is then ``new``), the orbits shrinking into the step and growing out of it say so
                through = through or (_amplitude_slope(cur) < 0.0 < _amplitude_slope(new)
                                      and min(_amplitude(cur), _amplitude(new)) < HOPF_AMPLITUDE * self.max_amplitude)
                if not through and not _fold_confirmed(pt):
                    if not small:
                        continue  # the parameter's tangent changed sign without a fold (noise where D barely moves)
                    through = True  # the family turned without a second multiplier at 1, its orbit nearly a point
                if through:
                    pt.label = "HB"  # the family ends there
            found.append((sigma, pt))
        return sorted(found, key=lambda f: f[0])


def continue_cycles(model: Model, system: CycleSystem, start: CycleStart, vary: str, options: ContinuationOptions, *,
                    at: Sequence[float] = (), adapt: int = 3, progress: Callable[[int], object] | None = None, direction: int = 1,
                    hopf_eigenvalues: np.ndarray | None = None) -> CycleBranch:
    """Continue the family from ``start`` on ``system`` (see :func:`cycles_from_hopf`); returns the :class:`CycleBranch`.

    The family ends at a bound (``EP`` located on it), after ``max_steps``, or when the step falls
    below ``dsmin`` (status ``step size underflow``, the message saying where and why). Raises
    :class:`ConvergenceError` with the start in ``partial`` when not even the first step succeeds.
    """
    run = _Run(system, options, at, adapt)
    X0 = start.X
    for name, (lo, hi) in options.bounds.items():  # as continuation's start: a family begun outside would never stop
        v = float(X0[-1] if name == vary else X0[-2])
        if not lo <= v <= hi:
            raise InputError(name, f"start value {v:.6g} lies outside its bounds {lo:g}:{hi:g}")
    if start.tangent is None:  # the null vector with the parameter held: its tangent points along the family
        closing = np.zeros(system.size)
        closing[-1] = 1.0
        try:
            X0, lu, _ = system.newton(X0, phase_reference(system, X0), closing, float(X0[-1]), options.engine.newton_tol,
                                      options.engine.max_newton)
        except NewtonFailure as exc:
            raise ConvergenceError(f"the start orbit does not converge: {exc}") from None
        t0 = direction * system.tangent(lu)
    else:
        t0 = direction * start.tangent
    if hopf_eigenvalues is not None:  # the equilibrium's multipliers exp(lambda T), without the critical pair
        lam = np.asarray(hopf_eigenvalues, complex)
        crit = np.argsort(np.abs(lam.real) / np.maximum(np.abs(lam), 1e-300))[:2]
        mu0 = np.exp(np.delete(lam, crit) * X0[-2])
    else:
        mu0 = nontrivial_multipliers(system.multipliers(X0))
    cur = _Point(system, X0, t0, mu0, start.label)
    run.points.append(cur)
    run.s.append(0.0)
    status, message = Status.COMPLETED, ""
    steps, s_cur, homoclinic = 0, 0.0, 0
    while True:
        if steps >= options.max_steps:
            message = f"stopped after max_steps={options.max_steps}"
            break
        if adapt and steps and steps % adapt == 0:
            cur = run.remesh(cur)
        try:
            new = run.step(cur)
        except NewtonFailure as exc:
            _, T, p = cur.system.split(cur.X)
            message = f"collocation failed after {vary} = {p:.6g}, period {T:.6g} s ({steps} steps): {exc}"
            if steps == 0:
                raise ConvergenceError(f"the family cannot start: {message}",
                                       partial=_branch(model, run, Status.STEP_UNDERFLOW, message)) from None
            status = Status.STEP_UNDERFLOW
            break
        # at a Hopf start the critical pair sits on the unit circle: no crossing is counted from there
        ref = _Point(cur.system, cur.X, cur.t, new.mu, r=cur.r) if start.label == "HB" and steps == 0 else cur
        ds = new.ds  # type: ignore[attr-defined]
        ended = False
        for sigma, pt in run.events(ref, new, ds):
            run.points.append(pt)
            run.s.append(s_cur + sigma)
            if pt.label == "EP":
                message = f"reached a bound at {vary} = {pt.X[-1]:.6g}, period {pt.X[-2]:.6g} s"
                ended = True
                break
            if pt.label == "HB":
                run.points[-1], message = _hopf_end(model, pt, vary)
                ended = True
                break
        if ended:
            break
        run.max_amplitude = max(run.max_amplitude, _amplitude(new))
        run.points.append(new)
        s_cur += ds
        run.s.append(s_cur)
        homoclinic = homoclinic + 1 if _period_runs_away(cur, new, system.p_weight) else 0
        cur = new
        steps += 1
        if progress is not None:
            progress(1)
        if start.label == "HB" and steps == VERTICAL_STEPS and _vertical(run, system.p_weight):
            msg = (f"the family cannot start: it does not leave {vary} = {X0[-1]:.8g} in {steps} steps while its "
                   f"orbits grow (a degenerate Hopf point: first Lyapunov coefficient 0, a vertical family)")
            raise ConvergenceError(msg, partial=_branch(model, run, Status.STEP_UNDERFLOW, msg))
        if homoclinic >= HOMOCLINIC_STEPS:
            _, T, p = cur.system.split(cur.X)
            message = (f"period growing without bound: approaching a homoclinic orbit at {vary} = {p:.8g} "
                       f"(period {T:.6g} s)")
            break
    if not run.points[-1].label:
        run.points[-1].label = "EP"
    return _branch(model, run, status, message)


def _vertical(run: _Run, p_weight: float) -> bool:
    """True when no orbit so far has moved the parameter from the start's by more than 1e-9 of its scale."""
    p = np.array([pt.X[-1] for pt in run.points])
    scale = max(abs(p[0]), 1.0 / math.sqrt(p_weight) if p_weight > 0 else 0.0, 1e-300)
    return bool(np.max(np.abs(p - p[0])) <= 1e-9 * scale)


def _hopf_end(model: Model, pt: _Point, vary: str) -> tuple[_Point, str]:
    """The Hopf point a family arrives at (its zero-amplitude orbit), refined from the near-point orbit ``pt``."""
    sys_ = pt.system
    u, T, p = sys_.split(pt.X)
    dyn, rates = sys_.rates.dynamics, sys_.rates
    mean = sys_.mesh.mean(u)
    try:
        hopf = hopf_point(model, dyn, dyn.full_vector(mean, rates.x_at(p)), vary)
    except InputError:
        pt.label, pt.approximate = "LPC", True
        return pt, ""
    X = sys_.pack(np.repeat(hopf.z[None, :], sys_.mesh.n_nodes, axis=0), 2 * np.pi / hopf.omega,
                  float(hopf.x[rates.p_index]))
    lam = np.linalg.eigvals(dyn.rates_jacobian(hopf.z, hopf.x))
    crit = np.argsort(np.abs(lam.real) / np.maximum(np.abs(lam), 1e-300))[:2]
    end = _Point(sys_, X, pt.t, np.exp(np.delete(lam, crit) * X[-2]), "HB")
    return end, f"reached a Hopf point at {vary} = {X[-1]:.6g} (period {X[-2]:.6g} s): the family ends there"


def _branch(model: Model, run: _Run, status: Status, message: str) -> CycleBranch:
    """The :class:`CycleBranch` of the points computed so far."""
    rates = run.system.rates
    dyn = rates.dynamics
    names = tuple(dyn.state_names)
    known = set(model.names)
    # a mechanism's velocity state (q_dot, no variable of its own) is in its coordinate's unit per second
    units = tuple(model.variable(n).unit if n in known
                  else derivative_unit(model.variable(c).unit, "s") if (c := velocity_coordinate(n, known))
                  else "" for n in names)
    p, period, lo, hi, orbits = [], [], [], [], []
    # a closed loop's dependent coordinates (not states) get their extremes too: the wheel's steer angle when the
    # partition chose the crank
    mech = model.mechanics
    dep_names = tuple(c for c in mech.coordinates if c not in names) if mech is not None else ()
    deps = [model.index(c) for c in dep_names]
    dlo: list[np.ndarray] = []
    dhi: list[np.ndarray] = []
    for pt in run.points:
        u, T, pv = pt.system.split(pt.X)
        smallest, largest = pt.system.mesh.extremes(u)
        p.append(pv)
        period.append(T)
        lo.append(smallest)
        hi.append(largest)
        orbits.append((pt.system.mesh, u.copy()))
        if deps:
            # the nodes and Gauss points (their order does not matter to an extreme; no derivatives needed)
            every = np.vstack([u, pt.system.mesh.gauss_values(u).reshape(-1, u.shape[1])])
            X = dyn.full_vectors(every, rates.x_at(pv))[:, deps]
            dlo.append(X.min(axis=0))
            dhi.append(X.max(axis=0))
    mus = [pt.mu for pt in run.points]
    return CycleBranch(
        model=getattr(model, "name", ""), vary=rates.vary, vary_unit=model.variable(rates.vary).unit,
        state_names=names, state_units=units, p=np.array(p), period=np.array(period), minimum=np.array(lo),
        maximum=np.array(hi), multipliers=mus, n_unstable=np.array([int(np.sum(np.abs(m) > 1 + UNSTABLE)) for m in mus]),
        labels=[pt.label for pt in run.points], s=np.array(run.s), orbits=orbits, status=status, message=message,
        x_base=rates.x_base.copy(), names=tuple(model.names), coordinate_names=dep_names,
        coordinate_units=tuple(model.variable(c).unit for c in dep_names),
        coordinate_minimum=np.array(dlo).reshape(len(dlo), len(deps)),
        coordinate_maximum=np.array(dhi).reshape(len(dhi), len(deps)),
        approximate=frozenset(i for i, pt in enumerate(run.points) if pt.approximate))
