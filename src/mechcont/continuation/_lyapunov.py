"""The first Lyapunov coefficient of a Hopf point, and the states' typical sizes its differences are taken in.

Kuznetsov's invariant formula (Elements of Applied Bifurcation Theory, 3rd ed., eq. (3.20)):

    l1 = Re( <p, C(q,q,qb)> - 2 <p, B(q, A^-1 B(q,qb))> + <p, B(qb, (2 i omega - A)^-1 B(q,q))> ) / (2 omega)

with ``A q = i omega q``, ``A^T p = -i omega p``, ``<q, q> = 1``, ``<p, q> = 1`` (``<a, b> = a^H b``), ``B``,
``C`` the second and third derivatives of the rates ``f(z)``. ``A``, ``q`` and ``p`` come from the critical pair of
the Hopf point's linearisation where it is at hand (:func:`critical_vectors`: a mechanism's turned from its allowed
motions into ``z``), else from the rates' Jacobian. Two ways to the derivatives:

* an ODE model with its equation system: ``B`` exact (the generated second derivatives), ``C``
  Richardson-extrapolated central differences of ``B`` (step ``eps^(1/5)``: about 1e-13 relative);
* any other dynamics (a mechanism's rates in minimal coordinates): the rates alone, along a few directions.
  With ``q = a + i b`` (its phase turned so that ``a`` and ``b`` are equally long in the states' scales),
  ``B(q, qb) = Q(a) + Q(b)``, ``B(q, q) = Q(a) - Q(b) + 2 i B(a, b)`` and ``C(q, q, qb) = c(a) + C(a, b, b) +
  i (C(a, a, b) + c(b))``, where ``Q(d) = B(d, d)`` and ``c(d) = C(d, d, d)`` are second and third derivatives
  of ``f`` along one direction and the mixed terms follow by polarisation (``4 B(u, v) = Q(u + v) - Q(u - v)``,
  ``6 C(a, b, b) = c(a + b) + c(a - b) - 2 c(a)``, ``6 C(a, a, b) = c(a + b) - c(a - b) - 2 c(b)``). ``Q`` by
  Richardson-extrapolated central second differences (step ``eps^(1/6)`` of the states' scales: rounding and
  truncation balance near ``eps^(2/3)``, 4e-11), ``c`` by extrapolated central third differences (step
  ``eps^(1/7)``: near ``eps^(4/7)``, 1e-9): about a hundred rates in two batches, where differences of
  differenced Jacobians took nearly four times as many and were noisy at 1e-5 (a Jacobian's differencing
  noise, ``eps^(2/3)``, divided by the second step).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..equations import Dynamics, EquationSystem, OdeDynamics, velocity_coordinate
from ._hopf_plane import CriticalPair

__all__ = ["critical_vectors", "first_lyapunov", "state_scales"]

_EPS = float(np.finfo(float).eps)


def state_scales(dynamics: Dynamics, system: EquationSystem | None, omega: float) -> np.ndarray:
    """Each state's typical size near a Hopf point or on a cycle of angular frequency ``omega`` (rad/s): its
    variable's scale in ``system``; a velocity state ``NAME_dot`` that is no variable (a mechanism's), its
    coordinate's scale times ``omega`` (it swings ``omega`` times its coordinate's amplitude); else 1."""
    if system is None:
        return np.ones(len(dynamics.state_names))
    known = dict(zip(system.names, np.abs(np.asarray(system.scales(), float))))

    def scale(n: str) -> float:
        if n in known:
            return float(known[n]) or 1.0
        if (c := velocity_coordinate(n, known)) is not None:
            return (float(known[c]) or 1.0) * max(omega, _EPS)
        return 1.0
    return np.array([scale(n) for n in dynamics.state_names])


def critical_vectors(dynamics: Dynamics, x: np.ndarray,
                     pair: CriticalPair) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``(A, q, p)`` of :func:`first_lyapunov` from the critical ``pair`` of the linearisation at ``x`` (``pair.lam[0]
    = i omega``): ``A = df/dz`` (the rates' state ``z``), ``A q = i omega q`` with ``|q| = 1`` (its largest
    component real and positive), ``A^T p = -i omega p`` with ``<p, q> = 1``. The pair's own matrix and
    eigenvectors, turned into ``z`` (an ODE model's linearisation is in ``z`` already; a mechanism's is in
    ``(eta, eta', ds)``, turned by its :meth:`~mechcont.equations.MechanismDynamics.linearisation_basis`): exact
    derivatives where the rates' Jacobian would be differenced, and no eigenvalue problem solved again. None
    where that cannot be done (a descriptor pencil, a pair that is not complex, dynamics that do not say their
    basis at ``x``)."""
    if pair.E is not None or not pair.complex:
        return None
    A, v, w = np.asarray(pair.A, float), pair.right[:, 0], pair.left[:, 0]
    if not isinstance(dynamics, OdeDynamics):
        basis = getattr(dynamics, "linearisation_basis", None)
        T = None if basis is None else basis(x)
        if T is None or T.shape != A.shape:
            return None
        try:
            # T A T^-1, T v and T^-H w: the same matrix and eigenvectors in the rates' state
            A = np.linalg.solve(T.T, (T @ A).T).T
            v, w = T @ v, np.linalg.solve(T.conj().T, w)
        except np.linalg.LinAlgError:
            return None
    big = v[int(np.argmax(np.abs(v)))]
    q = v * (abs(big) / big) / np.linalg.norm(v)
    p = w / np.conj(np.vdot(w, q))
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(p))):
        return None
    return A, q, p


def first_lyapunov(dynamics: Dynamics, x: np.ndarray, omega: float, system: EquationSystem | None = None,
                   pair: CriticalPair | None = None) -> tuple[float, np.ndarray, str]:
    """The first Lyapunov coefficient at the Hopf point ``x`` of frequency ``omega`` (rad/s), by the module's
    formula: exact second derivatives for an ODE model with its ``system``, directional differences of the
    rates otherwise. The steps are relative to each state's scale (:func:`state_scales`): a mechanism's
    velocity states swing ``omega`` times their coordinates, and a step sized by them would move the
    coordinates, where the nonlinearity is, by almost nothing. ``pair``: the critical pair of the linearisation
    at ``x`` where already at hand, whose matrix and eigenvectors are then used (:func:`critical_vectors`)
    instead of the rates' Jacobian and its eigenvectors.

    Returns ``(l1, q, method)``: ``l1`` in 1/s per squared state unit (negative: supercritical), the
    eigenvector ``q`` (``A q = i omega q``, ``|q| = 1``) and how the derivatives were taken."""
    dyn = dynamics
    z0 = dyn.state_at(x)
    sc = state_scales(dyn, system, omega)
    known = None if pair is None else critical_vectors(dyn, x, pair)
    if known is not None:
        A, q, p = known
    else:
        A = np.asarray(dyn.rates_jacobian(z0, x), float)
        lam, V = np.linalg.eig(A)
        q = V[:, int(np.argmin(np.abs(lam - 1j * omega)))]
        q = q / np.linalg.norm(q)
        lamT, W = np.linalg.eig(A.T)
        p = W[:, int(np.argmin(np.abs(lamT + 1j * omega)))]
        p = p / np.conj(np.vdot(p, q))
    terms: _Terms
    if isinstance(dyn, OdeDynamics) and system is not None:
        terms = _exact_terms(dyn, system, x, z0, sc, q)
        method = "exact second derivatives, third by extrapolated central differences"
    else:
        terms = _DifferenceTerms(dyn, x, z0, sc, q)
        method = "finite differences of the rates along directions (second and third, extrapolated)"
    n = len(z0)
    h11 = np.linalg.solve(A, terms.b_q_qb)
    h20 = np.linalg.solve(2j * omega * np.eye(n) - A, terms.b_q_q)
    b_q_h11, b_qb_h20 = terms.products(h11, h20)
    l1 = float(np.real(np.vdot(p, terms.c) - 2 * np.vdot(p, b_q_h11) + np.vdot(p, b_qb_h20)) / (2 * omega))
    return l1, q, method


class _Terms:
    """What the formula needs of the derivatives: ``b_q_qb = B(q, qb)``, ``b_q_q = B(q, q)``, ``c = C(q, q, qb)``
    and :meth:`products`."""

    b_q_qb: np.ndarray
    b_q_q: np.ndarray
    c: np.ndarray

    def products(self, h11: np.ndarray, h20: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(B(q, h11), B(qb, h20))``."""
        raise NotImplementedError


class _ExactTerms(_Terms):
    """The terms from the matrices ``Ha = B(a, .)``, ``Hb = B(b, .)`` (``q = a + i b``) and ``C``."""

    def __init__(self, Ha: np.ndarray, Hb: np.ndarray, q: np.ndarray, c: np.ndarray) -> None:
        self.Ha, self.Hb, self.c = Ha, Hb, c
        self.b_q_qb, self.b_q_q = self._b(np.conj(q), False), self._b(q, False)

    def _b(self, v: np.ndarray, conj: bool) -> np.ndarray:
        """``B(q, v)``, or ``B(qb, v)`` with ``conj``."""
        return np.asarray(self.Ha @ v + (-1j if conj else 1j) * (self.Hb @ v))

    def products(self, h11: np.ndarray, h20: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self._b(h11, False), self._b(h20, True)


def _exact_terms(dyn: OdeDynamics, system: EquationSystem, x: np.ndarray, z0: np.ndarray, sc: np.ndarray,
                 q: np.ndarray) -> _ExactTerms:
    """``(B(q, .), C(q, q, qb))`` of an ODE model: ``B`` from the generated second derivatives, ``C`` from
    Richardson-extrapolated central differences of ``S(z) = B_z(a, a) + B_z(b, b)`` along ``a`` and ``b``
    (``C(q,q,qb) = D_a S + i D_b S`` by trilinearity and symmetry). The second derivatives ``d2 f_i / dz_j dz_k``
    (the states' entries, :meth:`~mechcont.equations.ColumnView.second_derivative_entries`) are computed once per
    point, at ``z0`` and the eight points of the stencils, and contracted with ``a`` and ``b`` as arrays."""
    cols = np.array([system.index(n) for n in dyn.state_names], dtype=np.intp)
    n, nv = len(cols), len(system.names)
    values, i, j, k = system.columns(cols).second_derivative_entries()
    at = np.full(nv, n, dtype=np.intp)  # the state's position, n (a zero) for the other variables
    at[cols] = np.arange(n, dtype=np.intp)
    jz = at[j]
    a, b = q.real, q.imag
    a0, b0 = np.append(a, 0.0)[jz], np.append(b, 0.0)[jz]

    # Richardson's extrapolation of central differences (error O(h^4)): h = eps^(1/5) balances rounding
    # (eps / h) and truncation (h^4) near 1e-13
    step = _EPS ** (1 / 5)
    scale = max(1.0, float(np.max(np.abs(z0) / sc)))
    # the points: z0, then z0 + h d, z0 - h d, z0 + 2 h d, z0 - 2 h d for each of d = a, b that is not zero
    nd = np.max(np.abs(np.vstack([a, b])) / sc, axis=1)
    moved = [(d, step * scale / float(size) if size > 0 else 0.0) for d, size in zip((a, b), nd)]
    Z = np.vstack([z0[None, :]] + [z0 + np.array([h, -h, 2 * h, -2 * h])[:, None] * d for d, h in moved if h > 0])
    V = _at_rows(values, dyn.full_vectors(Z, x))
    # B at z0 along a and b: Ha[i, k] = sum_j d2 f_i / dz_j dz_k a_j
    bins = i * n + k
    Ha = np.bincount(bins, weights=V[0] * a0, minlength=n * n).reshape(n, n)
    Hb = np.bincount(bins, weights=V[0] * b0, minlength=n * n).reshape(n, n)
    # S(z)_i = B_z(a, a)_i + B_z(b, b)_i at the stencils' points, one bincount over all of them
    weight = a0 * a[k] + b0 * b[k]
    m = len(Z) - 1
    S = np.bincount((np.arange(m)[:, None] * n + i).ravel(), weights=(V[1:] * weight).ravel(),
                    minlength=m * n).reshape(m, n)

    def D(rows: int, h: float) -> np.ndarray:
        # rows: S at +h, -h, +2h, -2h
        central = [(S[rows] - S[rows + 1]) / (2 * h), (S[rows + 2] - S[rows + 3]) / (4 * h)]
        return np.asarray((4 * central[0] - central[1]) / 3)

    Da, Db, r = np.zeros(n), np.zeros(n), 0
    for which, (_, h) in enumerate(moved):
        if h > 0:
            if which == 0:
                Da = D(r, h)
            else:
                Db = D(r, h)
            r += 4
    return _ExactTerms(Ha, Hb, q, Da + 1j * Db)


def _at_rows(values: Callable[[np.ndarray], np.ndarray], X: np.ndarray) -> np.ndarray:
    """``values(X[r])`` for each row of ``X`` (a :meth:`~mechcont.equations.ColumnView.second_derivative_entries`
    gather), in one call of the compiled code where its parts are at hand (the same values, row by row)."""
    parts = getattr(values, "parts", lambda: None)()
    if parts is None:
        return np.array([values(row) for row in X])
    fn, n_out, src = parts
    m = len(X)
    out = np.zeros((m, n_out + 1))  # the last column stays 0: structural zeros read it
    vals = np.empty(m * n_out)
    fn.unsafe_eval(np.ascontiguousarray(X, dtype=float), vals, m)
    out[:, :n_out] = vals.reshape(m, n_out)
    return out[:, src]


class _Directional:
    """Second and third derivatives of the rates at ``z0`` along given directions, from the rates alone: ``Q(d) =
    f''[d, d]`` and ``c(d) = f'''[d, d, d]`` (Richardson-extrapolated central differences, all the directions
    of one call in one batch of rates)."""

    def __init__(self, dyn: Dynamics, x: np.ndarray, z0: np.ndarray, sc: np.ndarray) -> None:
        self.dyn, self.x, self.z0, self.sc = dyn, x, z0, sc
        self.unit = max(1.0, float(np.max(np.abs(z0) / sc)))  # the steps' unit: the state's size in its scales
        self._f0: np.ndarray | None = None

    def _rates(self, Z: np.ndarray) -> np.ndarray:
        batch = getattr(self.dyn, "rates_batch", None)
        if batch is not None:
            return np.asarray(batch(Z, self.x), float)
        return np.array([np.asarray(self.dyn.rates(z, self.x), float) for z in Z])

    def forms(self, second: list[np.ndarray], third: list[np.ndarray]) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """``([Q(d) for d in second], [c(d) for d in third])``."""
        h2, h3 = _EPS ** (1 / 6) * self.unit, _EPS ** (1 / 7) * self.unit
        n = len(self.z0)
        D2 = np.asarray(second, float).reshape(len(second), n)
        D3 = np.asarray(third, float).reshape(len(third), n)
        # each direction's size in the states' scales; one that is not finite (h11 where A is singular, at a
        # Bogdanov-Takens point) gives NaN: l1 undefined
        norms2, norms3 = self._norms(D2), self._norms(D3)
        use2, use3 = norms2 > 0, norms3 > 0
        # the stencils' rows: z0 + k h d / |d| for k = 1, -1, 2, -2 (second) and 1, -1, 2, -2, 4, -4 (third)
        rows = [self.z0[None, :]] if self._f0 is None else []
        for D, norms, use, h, ks in ((D2, norms2, use2, h2, (1, -1, 2, -2)), (D3, norms3, use3, h3, (1, -1, 2, -2, 4, -4))):
            kh = (np.array(ks, float) * h)[None, :, None]
            rows.append((self.z0 + kh * D[use][:, None, :] / norms[use][:, None, None]).reshape(-1, n))
        Z = np.concatenate(rows)
        F = self._rates(Z) if len(Z) else np.zeros((0, n))
        if self._f0 is None:
            self._f0, F = F[0], F[1:]
        f0 = self._f0
        k2 = int(np.count_nonzero(use2))
        P2, P3 = F[:4 * k2].reshape(k2, 4, n), F[4 * k2:].reshape(-1, 6, n)
        # Richardson's extrapolation of the central second and third differences at h and 2 h
        d_h = (P2[:, 0] + P2[:, 1] - 2 * f0) / h2 ** 2
        d_2h = (P2[:, 2] + P2[:, 3] - 2 * f0) / (2 * h2) ** 2
        t_h = (P3[:, 2] - 2 * P3[:, 0] + 2 * P3[:, 1] - P3[:, 3]) / (2 * h3 ** 3)
        t_2h = (P3[:, 4] - 2 * P3[:, 2] + 2 * P3[:, 3] - P3[:, 5]) / (2 * (2 * h3) ** 3)
        Q = np.where(np.isnan(norms2)[:, None], math.nan, 0.0) * np.ones((len(D2), n))
        Q[use2] = (4 * d_h - d_2h) / 3 * norms2[use2][:, None] ** 2
        C = np.where(np.isnan(norms3)[:, None], math.nan, 0.0) * np.ones((len(D3), n))
        C[use3] = (4 * t_h - t_2h) / 3 * norms3[use3][:, None] ** 3
        return list(Q), list(C)

    def _norms(self, D: np.ndarray) -> np.ndarray:
        """Each row's largest component relative to the states' scales; NaN for a row that is not finite."""
        with np.errstate(invalid="ignore"):
            norms = np.max(np.abs(D) / self.sc, axis=1, initial=0.0)
        return np.where(np.isfinite(D).all(axis=1), norms, math.nan)


class _DifferenceTerms(_Terms):
    """The terms from the rates alone (the module docstring's second way): ``q`` turned to ``q' = turn q`` with
    its real and imaginary parts ``a``, ``b`` equally long in the states' scales (l1 does not depend on ``q``'s
    phase; the polarisation's differences then cancel no more than ``a``'s or ``b``'s own size), the terms
    turned back (``B(q, v) = B(q', v) conj(turn)``, ``B(qb, v) = B(qb', v) turn``, ``C(q, q, qb) = C' conj(turn)``)."""

    def __init__(self, dyn: Dynamics, x: np.ndarray, z0: np.ndarray, sc: np.ndarray, q: np.ndarray) -> None:
        qs = q / sc
        square = complex(np.sum(qs * qs))
        self.turn = complex(np.exp(0.5j * (0.5 * np.pi - np.angle(square)))) if square != 0 else 1.0 + 0j
        a, b = np.real(q * self.turn), np.imag(q * self.turn)
        self.forms, self.a, self.b = _Directional(dyn, x, z0, sc), a, b
        (Qa, Qb, Qp, Qm), (ca, cb, cp, cm) = self.forms.forms([a, b, a + b, a - b], [a, b, a + b, a - b])
        back = self.turn.conjugate()
        self.b_q_qb = Qa + Qb + 0j  # B(q', qb') = B(q, qb)
        self.b_q_q = (Qa - Qb + 0.5j * (Qp - Qm)) * back ** 2  # B(q', q') = Q(a) - Q(b) + 2 i B(a, b)
        c_abb, c_aab = (cp + cm - 2 * ca) / 6, (cp - cm - 2 * cb) / 6
        self.c = ((ca + c_abb) + 1j * (c_aab + cb)) * back

    def products(self, h11: np.ndarray, h20: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``B(a, .)`` and ``B(b, .)`` of ``h11`` (real) and of ``h20``'s real and imaginary parts, by
        polarisation ``4 s B(u, w) = Q(u + s w) - Q(u - s w)`` with ``s w`` as long as ``u``: one batch."""
        sc = self.forms.sc
        parts = [(u, w) for w in (np.real(h11), np.real(h20), np.imag(h20)) for u in (self.a, self.b)]
        dirs: list[np.ndarray] = []
        scales: list[float] = []
        for u, w in parts:
            nw = float(np.max(np.abs(w) / sc)) if np.all(np.isfinite(w)) else math.nan
            with np.errstate(over="ignore", divide="ignore"):
                s = float(np.max(np.abs(u) / sc)) / nw if nw > 0 else 0.0 if nw == 0 else math.nan
            s = 0.0 if s == math.inf else s  # w below the smallest normal number: B(u, w) is 0 to rounding
            scales.append(s)
            if s > 0:
                dirs += [u + s * w, u - s * w]
        Qs, _ = self.forms.forms(dirs, [])
        B, i = [], 0
        for s in scales:
            if s > 0:
                B.append((Qs[i] - Qs[i + 1]) / (4 * s))
                i += 2
            else:
                B.append(np.full(len(sc), 0.0 if s == 0 else math.nan))
        a_h11, b_h11, a_r, b_r, a_i, b_i = B
        # B(q', h11) = B(a, h11) + i B(b, h11); B(qb', h20) = B(a, h20) - i B(b, h20), h20 = r + i m
        b_q_h11 = (a_h11 + 1j * b_h11) * self.turn.conjugate()
        b_qb_h20 = ((a_r + 1j * a_i) - 1j * (b_r + 1j * b_i)) * self.turn
        return b_q_h11, b_qb_h20
