"""Hopf points as events of equilibrium branches (``HB``), and Hopf curves in two parameters.

:class:`HopfEvent` watches the bialternate-product test function (:mod:`._hopf_point`) along a branch
of equilibria; at a sign change it polishes the point on the minimally extended system and keeps it
only when the critical pair is complex (a neutral saddle, a real pair ``(kappa, -kappa)``, changes the
same sign and is dropped). :class:`HopfProblem` is the Hopf curve ``G = 0, lambda_1 + lambda_2 = 0`` in
``(states, p1, p2)`` for the same pseudo-arclength engine, with Bogdanov–Takens (``BT``: ``omega^2 =
lambda_1 lambda_2`` passes through 0, the pair becomes real and the curve goes on as neutral saddles)
and generalised-Hopf (``GH``: ``l1`` changes sign) events.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Dynamics, EquationSystem
from ..errors import ConvergenceError
from ._events import Event, Hit, PointState, _secant
from ._folds import curve_states
from ._hopf_plane import CriticalPair
from ._hopf_point import HopfPoint, HopfTest, first_lyapunov, polish_hopf, secant_fraction
from ._problem import ContinuationProblem

if TYPE_CHECKING:
    from ._corrector import PseudoArclength

#: omega / |A| below which the pair is taken as a Bogdanov-Takens point's Jordan block (no l1 there)
_BT_OMEGA = 1e-6

__all__ = ["HopfEvent", "HopfProblem", "BogdanovTakensEvent", "GeneralisedHopfEvent", "hopf_point_of"]


def hopf_point_of(test: HopfTest, x: np.ndarray, pair: CriticalPair, residual: float) -> HopfPoint:
    """The :class:`HopfPoint` payload at the located Hopf point ``x`` with its critical ``pair``."""
    omega = pair.omega
    l1, q, method = first_lyapunov(test.dynamics, x, omega, test.system, pair)
    return HopfPoint(omega, l1, q, tuple(test.dynamics.state_names), residual, method)


class HopfEvent(Event):
    """Hopf point (``HB``) of an equilibrium branch, for a model with dynamics.

    ``dynamics``: the model's :class:`~mechcont.equations.Dynamics`; ``system``: its equation system
    (exact gradients for ODE models). Each accepted point costs one eigenvalue decomposition of the
    linearisation, so the engine asks for it only when told (``continuation(..., hopf=True)``).
    """

    label = "HB"

    def __init__(self, dynamics: Dynamics, system: EquationSystem | None = None) -> None:
        self.test = HopfTest(dynamics, system)

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        return self.test.test_value(state.x)

    def locate(self, stepper: PseudoArclength, problem: ContinuationProblem, cur: PointState, ds: float, v0: float,
               v1: float) -> Hit:
        """The secant guess on the test function's product ``psi`` (:func:`secant_fraction`), polished on the
        extended system; a neutral saddle gives no point (``state`` None). When the polish fails, Brent's method
        on the test function gives the point, marked approximate."""
        frac = secant_fraction(v0, v1, self.test.pairs)
        sigma, st, info = _secant(stepper, cur, ds, frac, frac - 1.0)
        if st is not None:
            try:
                u, pair, res = polish_hopf(self.test, problem, st.u)
                z = u / stepper.D
                sigma = float(cur.tangent @ (z - cur.z))
                if -0.1 * abs(ds) <= sigma * math.copysign(1.0, ds) <= 1.1 * abs(ds):
                    if not pair.complex:
                        return sigma, None, {"status": "neutral saddle"}
                    st = stepper.state(z, stepper.tangent(z, cur.tangent))
                    hopf = hopf_point_of(self.test, problem.full(u), pair, res)  # where the pair is
                    return sigma, st, {"status": "located", "residual": res, "hopf": hopf}
                reason = "the Hopf system converged outside the step"
            except (ConvergenceError, np.linalg.LinAlgError) as exc:
                reason = str(exc)
        else:
            reason = "no point at the secant guess"
        sigma, st, info = Event.locate(self, stepper, problem, cur, ds, v0, v1)
        if st is None:
            return sigma, None, info
        pair = self.test.pair(st.x)
        if not pair.complex:
            return sigma, None, {"status": "neutral saddle"}
        return sigma, st, {"status": "approximate", "reason": f"Hopf system not solved: {reason}",
                           "hopf": hopf_point_of(self.test, st.x, pair, math.nan)}


class BogdanovTakensEvent(Event):
    """Bogdanov–Takens point (``BT``) on a Hopf curve: ``omega^2 = lambda_1 lambda_2`` changes sign."""

    label = "BT"

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        assert isinstance(problem, HopfProblem), "BT is an event of Hopf curves"
        return problem.test.pair(state.x).kappa


class GeneralisedHopfEvent(Event):
    """Generalised Hopf point (``GH``, Bautin) on a Hopf curve: the first Lyapunov coefficient changes
    sign (0 where the pair is real, past a BT point: no event there)."""

    label = "GH"

    def value(self, problem: ContinuationProblem, state: PointState) -> float:
        assert isinstance(problem, HopfProblem), "GH is an event of Hopf curves"
        return problem.lyapunov(state.x)


class HopfProblem(ContinuationProblem):
    """The Hopf curve of ``system`` in parameters ``(p1, p2)`` as a continuation problem.

    Unknowns ``u = (states..., p1, p2)``; equations ``G = 0`` and ``g = lambda_1 + lambda_2 = 0``
    (the critical pair's sum, :class:`~._hopf_point.CriticalPair`): the minimally extended system,
    ``n + 1`` equations in ``n + 2`` unknowns, smooth through a Bogdanov–Takens point (the sum of the
    pair is the trace of ``A`` on its invariant plane), where the curve goes on as a curve of neutral
    saddles. Its Jacobian row is :meth:`HopfTest.gradient`.
    """

    def __init__(self, system: EquationSystem, x_hopf: np.ndarray, p1: str, p2: str, states: Iterable[str],
                 test: HopfTest, scales: Mapping[str, float] | None = None) -> None:
        self.system = system.compile()
        states = curve_states(states, p1, p2, "Hopf-curve parameters", "Hopf point")
        self.states, self.p1, self.p2, self.test = states, p1, p2, test
        self.idx_vars = np.array([system.index(n) for n in [*states, p1, p2]])
        self.idx = self.idx_vars
        self.base = np.array(x_hopf, float)
        self.view = system.columns(self.idx_vars)
        self.u0 = self.base[self.idx_vars].copy()
        self.names = (*states, p1, p2)
        self.param_index = len(states) + 1
        sc = system.scales()
        for name, v in (scales or {}).items():
            sc[system.index(name)] = v
        self.scale = sc[self.idx_vars]

    def full(self, u: np.ndarray) -> np.ndarray:
        """The full variable vector at ``u``."""
        x = self.base.copy()
        x[self.idx_vars] = u
        return x

    def evaluate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual (n + 1) and Jacobian (n + 1, n + 2) at ``u``."""
        x = self.full(u)
        r, J = self.view.residual_and_jacobian(x)
        pair = self.test.pair(x)
        return np.append(r, pair.g), np.vstack([J, self.test.gradient(x, self.idx_vars, pair)])

    def residual(self, u: np.ndarray) -> np.ndarray:
        return self.evaluate(u)[0]

    def jacobian(self, u: np.ndarray) -> np.ndarray:
        return self.evaluate(u)[1]

    def lyapunov(self, x: np.ndarray) -> float:
        """``l1`` at the curve point ``x`` (0 where the critical pair is real or ``l1`` is undefined: the
        generalised-Hopf event skips zeros)."""
        key = np.asarray(x, float).tobytes()
        cache = self.__dict__.setdefault("_l1", {})
        if key not in cache:  # the GH event and the table's column ask at the same points (costly on mechanisms)
            cache[key] = self._lyapunov(x)
        return cache[key]

    def _lyapunov(self, x: np.ndarray) -> float:
        pair = self.test.pair(x)
        # at a Bogdanov-Takens point the pair is a Jordan block, split by rounding into omega ~ sqrt(eps) |A|
        # of either sign of kappa, where l1 (~ 1/omega) is rounding too: not a sign change of GH's
        if not pair.complex or pair.omega <= _BT_OMEGA * max(float(np.linalg.norm(pair.A, 1)), np.finfo(float).tiny):
            return 0.0
        try:
            l1 = first_lyapunov(self.test.dynamics, x, pair.omega, self.test.system, pair)[0]
        except np.linalg.LinAlgError:  # A singular: a Bogdanov-Takens point, where l1 is not defined
            return 0.0
        return l1 if math.isfinite(l1) else 0.0

    def side(self, x: np.ndarray) -> tuple[float, float, int]:
        """``(-dg/dp1, -dg/dp2, n)`` at the curve point ``x``: the direction in the parameter plane into
        which the pair turns stable (``g`` followed along the equilibria, ``dg/dp = g_p - g_s G_s^-1 G_p``)
        and the number of the other eigenvalues with positive real part."""
        r, J = self.view.residual_and_jacobian(x)
        pair = self.test.pair(x)
        grad = self.test.gradient(x, self.idx_vars, pair)
        n = len(self.states)
        try:
            y = np.linalg.solve(J[:, :n].T, grad[:n])
        except np.linalg.LinAlgError:
            return math.nan, math.nan, pair.n_others_unstable
        d = grad[n:] - y @ J[:, n:]
        return -float(d[0]), -float(d[1]), pair.n_others_unstable

    def test_functions(self) -> list[Event]:
        return [BogdanovTakensEvent(), GeneralisedHopfEvent()]
