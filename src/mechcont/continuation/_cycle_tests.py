"""What the continuation of cycles measures between orbits: the test functions of folds, period doublings and
tori, the confirmation of a located fold, the amplitude, and the signs of a family approaching a homoclinic orbit."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._cycle_system import CycleSystem

#: |mu| beyond 1 + this counts as unstable (the collocation's multipliers are accurate to its order)
UNSTABLE = 1e-6
#: a located PD/NS must have its multiplier(s) this close to the unit circle, else it is not labelled
ON_CIRCLE = 1e-4
#: at a fold of cycles a second multiplier is 1; a turn whose nearest is further from 1 than this, at an orbit
#: smaller than HOPF_AMPLITUDE times the family's largest, is the family arriving at a Hopf point
FOLD_MULTIPLIER = 1e-3
HOPF_AMPLITUDE = 0.1
#: the largest tolerance on the second multiplier of a fold, however inaccurate the multipliers
FOLD_MULTIPLIER_MAX = 0.1
#: towards a homoclinic orbit the period grows while the parameter stops: HOMOCLINIC_STEPS consecutive steps with
#: (relative change of the parameter) / (relative growth of the period) below HOMOCLINIC_RATIO end the family
HOMOCLINIC_RATIO = 1e-5
HOMOCLINIC_STEPS = 3
#: ... and the orbit's extent (each state's max - min) changing by less than this times the period's relative growth:
#: towards a homoclinic orbit the orbit converges to the loop while the period diverges; in a canard explosion
#: (FitzHugh-Nagumo) the parameter also stops while the period grows, but the orbit grows with it
HOMOCLINIC_SHAPE = 0.1
#: a family from a Hopf point whose parameter has not moved after this many steps is vertical (l1 = 0)
VERTICAL_STEPS = 5


@dataclass
class _Point:
    system: CycleSystem
    X: np.ndarray
    t: np.ndarray
    mu: np.ndarray  # non-trivial multipliers
    label: str = ""
    approximate: bool = False
    trivial: complex = 1.0  # the trivial multiplier as computed: its distance from 1 is the multipliers' error
    r: np.ndarray | None = None  # system.row(t), kept: the next step's arclength row and the tangents' angle
    amplitude: float | None = None  # _amplitude's, kept
    #: the tangent's rate of turn along the family, d t / d s (the curvature vector), from the step that found this
    #: point: the next step's predictor's second-order term; None at a start
    curvature: np.ndarray | None = None

    def row(self) -> np.ndarray:
        """``r`` with ``r . X = <t, X>`` on this point's system (computed once)."""
        if self.r is None:
            self.r = self.system.row(self.t)
        return self.r


def _pd(mu: np.ndarray) -> float:
    real_neg = mu[(mu.imag == 0) & (mu.real < 0)].real
    return float(np.prod(1.0 + real_neg)) if len(real_neg) else 1.0


def _ns(mu: np.ndarray) -> float:
    pairs = mu[mu.imag > 0]
    return float(np.prod(np.abs(pairs) - 1.0)) if len(pairs) else 1.0


def _period_runs_away(a: _Point, b: _Point, p_weight: float) -> bool:
    """True when the period grows from ``a`` to ``b`` while the parameter hardly moves (HOMOCLINIC_RATIO) and the
    orbit's extent hardly changes (HOMOCLINIC_SHAPE): the family approaching a homoclinic orbit, where the period
    tends to infinity at a finite parameter value and the orbit to the homoclinic loop."""
    Ta, pa, Tb, pb = a.X[-2], a.X[-1], b.X[-2], b.X[-1]
    if not (Tb > Ta > 0):
        return False
    scale = max(abs(pa), 1.0 / math.sqrt(p_weight) if p_weight > 0 else 0.0, 1e-300)
    growth = (Tb - Ta) / Ta
    if not abs(pb - pa) / scale < HOMOCLINIC_RATIO * growth:
        return False
    ea, eb = _extent(a), _extent(b)
    return float(np.linalg.norm(eb - ea)) < HOMOCLINIC_SHAPE * growth * float(np.linalg.norm(ea))


def _extent(pt: _Point) -> np.ndarray:
    """Each state's max - min over the orbit's nodes, times its weight."""
    u, _, _ = pt.system.split(pt.X)
    return (u.max(axis=0) - u.min(axis=0)) * np.sqrt(pt.system.weights)


def _fold_confirmed(pt: _Point) -> bool:
    """True when a second multiplier of ``pt`` is at 1 to within the multipliers' accuracy.

    The trivial multiplier is exactly 1 in exact arithmetic: its computed distance from 1 is the collocation's
    (and the monodromy product's) error. At a fold the trivial one and the second one form a Jordan block, which
    turns an error ``e`` of the matrix into a split of ``sqrt(e)``: the tolerance is the larger of
    FOLD_MULTIPLIER and ten times that square root (at most FOLD_MULTIPLIER_MAX).
    """
    if len(pt.mu) == 0:
        return False
    tol = min(max(FOLD_MULTIPLIER, 10.0 * math.sqrt(abs(pt.trivial - 1.0))), FOLD_MULTIPLIER_MAX)
    return bool(np.min(np.abs(pt.mu - 1.0)) <= tol)


def _deviation(pt: _Point, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The orbit part of ``X`` (an orbit or a tangent on ``pt``'s mesh) at the Gauss points minus its mean, and the
    quadrature weights of the mesh's inner product (Mesh.gram_row) broadcast over it."""
    me, n = pt.system.mesh, pt.system.n
    V = me.gauss_values(X[:-2].reshape(-1, n))
    q = me.quadrature()[:, :, None]
    return V - np.add.reduce(q * V, axis=(0, 1)), q


def _amplitude(pt: _Point) -> float:
    """The orbit's weighted L2 distance from its mean (0 for an equilibrium); computed once per point."""
    if pt.amplitude is None:
        dev, q = _deviation(pt, pt.X)
        pt.amplitude = math.sqrt(max(float(np.add.reduce(q * dev * dev, axis=(0, 1)) @ pt.system.weights), 0.0))
    return pt.amplitude


def _amplitude_slope(pt: _Point) -> float:
    """d(amplitude^2)/ds along ``pt``'s tangent (the way the family goes): negative while the orbits shrink.

    Through a Hopf point the orbit's deviation from the equilibrium changes sign (``u = u0 + eps phi``, ``eps``
    crossing 0), so its amplitude ``|eps| |phi|`` shrinks to 0 and grows again: the slope turns from negative to
    positive within the step, where at a fold of cycles it keeps its sign."""
    dev, q = _deviation(pt, pt.X)
    dt, _ = _deviation(pt, pt.t)
    return 2.0 * float(np.add.reduce(q * dev * dt, axis=(0, 1)) @ pt.system.weights)
