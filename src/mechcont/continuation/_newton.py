"""Square solves: a first equilibrium from a guess, with any states held and parameters freed."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError
from ._problem import choose_unknowns

__all__ = ["find_equilibrium", "newton_square", "residual_met"]

_FLOOR = 100 * np.finfo(float).eps


def residual_met(r: np.ndarray, J: np.ndarray, u: np.ndarray, tol: float) -> bool:
    """True when every residual is below ``tol``, or at its floating-point floor.

    The floor of row ``i`` is ``100 eps sum_j |J_ij u_j|``: an equilibrium row whose terms
    are tens of kilonewton-metres cannot be met to ``tol`` = 1e-10 in double precision,
    while a constraint row in metres still must be. ``J`` and ``u`` may both be scaled.
    """
    size = np.abs(r)
    if size.max(initial=0.0) <= tol:  # the usual case at convergence: no floor can matter
        return True
    floor = _FLOOR * np.abs(J * u).sum(axis=1)
    return bool(np.all(size <= np.maximum(tol, floor)))


def newton_square(fun, jac, u0: np.ndarray, *, tol: float = 1e-10, residual_tol: float = 1e-10,
                  max_iter: int = 50, scale: np.ndarray | None = None, names=None):
    """Damped Newton for a square system ``fun(u) = 0``.

    The full Newton step is tried first and halved while it does not reduce the residual
    norm (a backtracking line search), so a rough guess still converges. The merit
    function divides each row by the size of its terms (``max(1, max_j |J_ij scale_j|)``)
    so the line search weighs equations in N, N m and m alike. Converged when the scaled
    step is below ``tol`` and the residuals pass :func:`residual_met`.

    Returns ``(u, iterations)``. Raises :class:`ConvergenceError` (with ``partial`` = the
    last iterate) if the Jacobian is singular or ``max_iter`` is reached.
    """
    u = np.array(u0, dtype=float)
    scale = np.ones_like(u) if scale is None else scale
    r = fun(u)
    for it in range(1, max_iter + 1):
        J = jac(u)
        # rows measured against the size of their terms: the merit function and the
        # convergence test then treat equations in N, N m and m alike
        row = np.maximum(1.0, np.abs(J * scale).max(axis=1))
        norm = np.linalg.norm(r / row)
        try:
            du = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            du = None
        if du is None or not np.all(np.isfinite(du)) or np.linalg.cond(J * scale / row[:, None]) > 1e14:
            raise ConvergenceError(
                f"singular Jacobian at iteration {it} (residual {np.linalg.norm(r):.3g}): the held/freed choice does "
                "not fix the configuration here; hold a different state or free a different parameter", partial=u)
        lam = 1.0
        while True:
            trial = u + lam * du
            r_trial = fun(trial)
            n_trial = np.linalg.norm(r_trial / row)
            if np.isfinite(n_trial) and (n_trial < norm or lam < 1 / 64 or n_trial < residual_tol):
                break
            lam *= 0.5
        u, r = trial, r_trial
        if np.max(np.abs(lam * du / scale)) < tol and residual_met(r, J, u, residual_tol):
            return u, it
    worst = int(np.argmax(np.abs(r)))
    raise ConvergenceError(
        f"Newton did not converge in {max_iter} iterations: residual {np.linalg.norm(r):.3g}, largest in equation "
        f"{worst}; "
        "try a closer guess or a different held value", partial=u)


def find_equilibrium(system: EquationSystem, values: Mapping[str, float] | None = None,
                     hold: Mapping[str, float] | None = None, free: Iterable[str] = (),
                     guess: Mapping[str, float] | np.ndarray | None = None, *, tol: float = 1e-10,
                     residual_tol: float = 1e-10, max_iter: int = 50) -> np.ndarray:
    """Solve for one equilibrium with chosen states held and parameters freed.

    Parameters
    ----------
    system:
        The equation system.
    values:
        ``{name: value}`` for parameters (SI units), overriding the defaults.
    hold:
        ``{state: value}``: states held at a value during this solve (e.g. ``theta1=0.3``).
    free:
        Parameters solved for instead (e.g. ``["F"]``); their values act as guesses.
    guess:
        Initial guess for unknowns, by name, or a full vector; defaults otherwise. A full
        vector also supplies every parameter value not given in ``values`` (a point of
        another branch keeps its parameters): pass ``values`` for those that must change.

    Returns
    -------
    numpy.ndarray
        The full variable vector (ordered like ``system.names``) at equilibrium.

    Raises
    ------
    InputError
        Unknown names, non-finite or physically impossible values (the model's
        ``check_values``), or a count of unknowns different from the number of equations.
    ConvergenceError
        Newton failed; ``partial`` holds the last full vector.
    """
    system.compile()
    hold = dict(hold or {})
    for src in (values or {}), hold:
        for k, v in src.items():
            if not np.isfinite(float(v)):
                raise InputError(k, f"value must be a finite number, got {v!r}")
    if isinstance(guess, np.ndarray):
        x = np.array(guess, dtype=float)
        x = system.vector(values or {}, base=x)
    else:
        x = system.vector({**(guess or {}), **(values or {})})
    x = system.vector(hold, base=x)
    if system.check_values is not None:
        system.check_values({n: x[system.index(n)] for n in system.parameter_names})  # type: ignore[operator]
    system.check_limits(x)
    unknowns = choose_unknowns(system, hold=hold, free=free)
    idx = np.array([system.index(n) for n in unknowns])

    def fun(u):
        y = x.copy()
        y[idx] = u
        return system.residual(y)

    def jac(u):
        y = x.copy()
        y[idx] = u
        return system.jacobian(y)[:, idx]

    try:
        u, _ = newton_square(fun, jac, x[idx], tol=tol, residual_tol=residual_tol, max_iter=max_iter,
                             scale=system.scales()[idx])
    except ConvergenceError as exc:
        partial = x.copy()
        if exc.partial is not None:
            partial[idx] = exc.partial
        held = ", ".join(f"{k}={v:g}" for k, v in hold.items()) or "nothing held"
        raise ConvergenceError(f"start did not converge ({held}): {exc}", partial=partial) from None
    x[idx] = u
    return x
