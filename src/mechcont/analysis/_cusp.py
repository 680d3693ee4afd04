"""A cusp's location and its sensitivities: a fold of the augmented fold system (see :func:`cusp_sensitivity`).

Split from :mod:`mechcont.analysis.sensitivity`, which re-exports :func:`cusp_sensitivity`.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from ..continuation import (
    Sensitivity,
    check_parameters,
    derivative_units,
    equilibrate,
    fold_scaling,
    solve_equilibrated,
    state_table,
    variable_indices,
)
from ..equations import Model
from ..errors import ConvergenceError

__all__ = ["cusp_sensitivity"]


def _fold_system(system: Model, x: np.ndarray, vh: np.ndarray, s_idx: np.ndarray,
                 cs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Residual and Jacobian of the augmented fold system ``R = (G, G_s C v_hat, (|v_hat|^2 - 1)/2)``.

    The Jacobian is with respect to every variable of the model and then ``v_hat``: exact, from
    the generated first and second derivatives of ``G``.
    """
    n, N = len(s_idx), len(x)
    vf = np.zeros(N)
    vf[s_idx] = cs * vh
    G, J = system.residual_and_jacobian(x)
    H = system.jacobian_derivative(x, vf)
    R = np.concatenate([G, J[:, s_idx] @ (cs * vh), [(vh @ vh - 1.0) / 2]])
    JR = np.zeros((2 * n + 1, N + n))
    JR[:n, :N], JR[n:2 * n, :N] = J, H
    JR[n:2 * n, N:] = J[:, s_idx] * cs
    JR[2 * n, N:] = vh
    return R, JR


class _Cusp:
    """A cusp as a fold in ``second`` of the augmented fold system ``R(s, lam, v_hat; second) = 0``.

    ``R``'s Jacobian ``A`` in ``z = (s, lam, v_hat)`` is exact (second derivatives of ``G``) and
    singular at the cusp. The cusp's location in ``second`` has the fold-load formula's
    sensitivity ``-psi^T R_p / psi^T R_second`` (``psi`` the left null vector of ``A``): exact.
    Locating the cusp, and the derivatives of its other coordinates, need the bordered system
    ``R = 0, A phi = 0, |phi_hat| = 1``, whose Jacobian holds ``d(A phi)/dz``: third derivatives
    of ``G``. That block is a central difference of the exact second-derivative matrix along
    ``phi`` (one pair of evaluations: ``d(A phi)/dz_j = d/de [dR/dz_j](z + e phi)`` by symmetry).
    """

    EPS = 1e-5  # step along the unit equilibrated null vector: error ~EPS^2 relative, far below 1e-6

    def __init__(self, system: Model, x: np.ndarray, states: Sequence[str], vary: str, second: str):
        self.system = system
        self.s_idx = variable_indices(system, states)
        self.N, self.n = len(x), len(states)
        idx = np.concatenate([self.s_idx, [system.index(vary)]])
        _, col = fold_scaling(system, x, idx)
        self.cs = col[:self.n]
        # no fold polish: at a cusp the augmented fold system is singular (that is the cusp). Columns scaled
        # only: at a symmetric cusp (the overcentre's) an equation's row of G_s vanishes, and equilibrating
        # rows would blow its rounding up into the null space
        self.vh = np.linalg.svd(system.jacobian(x)[:, self.s_idx] * self.cs)[2][-1]
        self.z_idx = np.concatenate([idx, self.N + np.arange(self.n)])  # columns of z in [x, v_hat]
        self.y = system.index(second)
        self.x = np.array(x, dtype=float)
        self.scale = np.ones(self.N + self.n)

    def evaluate(self, E: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(R, dR/d[x, v_hat])`` at the extended vector ``E = [x, v_hat]``."""
        return _fold_system(self.system, E[:self.N], E[self.N:], self.s_idx, self.cs)

    def third(self, E: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """``d(A phi)/d[x, v_hat]`` by a central difference of the exact Jacobian along ``phi`` (full length)."""
        h = self.EPS / max(float(np.linalg.norm(phi / self.scale)), 1e-300)
        return (self.evaluate(E + h * phi)[1] - self.evaluate(E - h * phi)[1]) / (2 * h)

    def locate(self, max_iter: int = 30, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
        """Newton on the bordered cusp system from the start; returns ``(E, phi)`` (``phi`` over ``z``, full length)."""
        E = np.concatenate([self.x, self.vh])
        _, JR = self.evaluate(E)
        A = JR[:, self.z_idx]
        row, col = equilibrate(A)
        self.scale = np.ones(len(E))
        self.scale[self.z_idx] = col
        _, _, vt = np.linalg.svd(A * row[:, None] * col)
        ph = vt[-1]
        m = len(self.z_idx)
        for _ in range(max_iter):
            phi = np.zeros(len(E))
            phi[self.z_idx] = col * ph
            R, JR = self.evaluate(E)
            A = JR[:, self.z_idx]
            M = self.third(E, phi)
            res = np.concatenate([R, A @ (col * ph), [(ph @ ph - 1.0) / 2]])
            K = np.zeros((2 * m + 1, 2 * m + 1))
            K[:m, :m], K[:m, m] = A, JR[:, self.y]
            K[m:2 * m, :m], K[m:2 * m, m], K[m:2 * m, m + 1:] = M[:, self.z_idx], M[:, self.y], A * col
            K[2 * m, m + 1:] = ph
            d = -solve_equilibrated(K, res[:, None], np.zeros(2 * m + 1, dtype=bool), "cusp location")[:, 0]
            E[self.z_idx] += d[:m]
            E[self.y] += d[m]
            ph = ph + d[m + 1:]
            if np.max(np.abs(d[:m] / col)) < tol and abs(d[m]) < tol * max(abs(E[self.y]), 1.0):
                break
        else:
            raise ConvergenceError(f"cusp location did not converge in {max_iter} iterations")
        phi = np.zeros(len(E))
        phi[self.z_idx] = col * ph / np.linalg.norm(ph)
        return E, phi


def cusp_sensitivity(system: Model, x: np.ndarray, states: Sequence[str], vary: str, second: str,
                     params: Iterable[str]) -> Sensitivity:
    """Derivatives of a cusp's location (the value of ``second`` there) and of its other coordinates.

    The cusp of the fold curve of ``vary`` (states ``states`` solved) continued in ``second`` is
    where ``second`` turns along the curve: a fold in ``second`` of the augmented fold system
    (:class:`_Cusp`). ``d second_c/dp`` (the derivatives) is exact, from second derivatives of
    ``G``; the states' and ``vary``'s derivatives at the cusp (``states`` of the result, with
    ``second``'s own, equal to the former) use third derivatives of ``G`` taken as a central
    difference of the exact second derivatives (relative error ~1e-10).

    Parameters
    ----------
    system, x:
        The model and a point near the cusp (e.g. a fold curve's ``CP``; it is located first).
    states:
        The unknowns of the equilibrium (not ``vary`` nor ``second``).
    vary, second:
        The fold's parameter and the one it is continued in.
    params:
        Held names to differentiate by.

    Returns a :class:`Sensitivity` of kind ``"cusp"`` (quantity ``second``; ``x`` the located cusp).
    """
    states = list(states)
    params = check_parameters(system, params, [*states, vary, second])
    cusp = _Cusp(system, np.asarray(x, dtype=float), states, vary, second)
    E, phi = cusp.locate()
    R, JR = cusp.evaluate(E)
    A = JR[:, cusp.z_idx]
    p_idx = variable_indices(system, params)
    row, col = equilibrate(A)
    u, _, _ = np.linalg.svd(A * row[:, None] * col)
    psi = row * u[:, -1]
    exact = -(psi @ JR[:, p_idx]) / (psi @ JR[:, cusp.y])
    m = len(cusp.z_idx)
    M = cusp.third(E, phi)
    ph = phi[cusp.z_idx]
    K = np.zeros((2 * m + 1, 2 * m + 1))
    K[:m, :m], K[:m, m] = A, JR[:, cusp.y]
    K[m:2 * m, :m], K[m:2 * m, m], K[m:2 * m, m + 1:] = M[:, cusp.z_idx], M[:, cusp.y], A
    K[2 * m, m + 1:] = ph / (col * col)  # |phi_hat|^2 with phi_hat = phi / col
    B = np.zeros((2 * m + 1, len(params)))
    B[:m], B[m:2 * m] = JR[:, p_idx], M[:, p_idx]
    D = -solve_equilibrated(K, B, np.zeros(2 * m + 1, dtype=bool), "cusp sensitivity")
    names = [*states, vary, second]
    rows = np.vstack([D[:cusp.n + 1], D[m]])
    xc = E[:cusp.N]
    return Sensitivity(second, float(xc[cusp.y]), system.variable(second).unit, "cusp",
                       {p: float(d) for p, d in zip(params, exact)}, derivative_units(system, second, params),
                       state_table(names, params, rows), xc.copy())
