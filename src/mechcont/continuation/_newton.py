"""Square solves: a first equilibrium from a guess, with any states held and parameters freed."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

import numpy as np

from .. import _dense
from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError
from ._problem import choose_unknowns

__all__ = ["find_equilibrium", "newton_square", "residual_met", "step_noise"]

_FLOOR = 100 * np.finfo(float).eps
#: Rounding of one evaluation of a residual row, relative to the sum of its terms' sizes:
#: the noise model of :func:`step_noise` (the floor of :func:`residual_met` is a generous 100x that).
_ROUNDING = np.finfo(float).eps


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


def step_noise(solve: Callable[[np.ndarray, np.ndarray], np.ndarray | None], A: np.ndarray, J: np.ndarray,
               u: np.ndarray) -> float:
    """Largest change of a Newton step that rounding of the residual alone can cause.

    At a solution a residual row cannot be computed better than the rounding of its terms,
    ``f_i = eps sum_j |J_ij u_j|``; a Newton step computed from such a residual, ``A^-1 r``,
    is noise of the size ``|A^-1 f|``. On a well-conditioned system that is far
    below any tolerance and never matters. On an ill-conditioned one (a joint compliance of
    1e10 N/m beside newton-sized loads: condition number 1e11 and more) the steps at the
    solution stall at that size while the residual sits at its floor, and no tolerance on the
    step can be met: the iterate is then as converged as double precision allows. ``A`` is the
    (square) matrix the step was solved with, whose first ``len(J)`` rows are ``J``; ``solve``
    solves with it. Returns the largest entry of the noise step, in the unknowns of ``A``, over
    two sign patterns of ``f`` (one could cancel), or ``inf`` if ``A`` is singular.
    """
    f = np.zeros(A.shape[0])
    f[: J.shape[0]] = _ROUNDING * np.abs(J * u).sum(axis=1)
    alternating = np.where(np.arange(len(f)) % 2 == 0, 1.0, -1.0)
    noise = 0.0
    for rhs in (f, f * alternating):
        d = solve(A, rhs)
        if d is None or not np.all(np.isfinite(d)):
            return np.inf
        noise = max(noise, float(np.max(np.abs(d))))
    return noise


def newton_square(fun: Callable[[np.ndarray], np.ndarray], jac: Callable[[np.ndarray], np.ndarray], u0: np.ndarray, *,
                  tol: float = 1e-10, residual_tol: float = 1e-10, max_iter: int = 50,
                  scale: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Damped Newton for a square system ``fun(u) = 0``.

    The full Newton step is tried first and halved while it does not reduce the residual
    norm (a backtracking line search), so a rough guess still converges. The merit
    function divides each row by the size of its terms (``max_j |J_ij scale_j|``, 1 for a row
    without terms) so the line search weighs equations in N, N m and m alike, in any units (a
    floor of 1 would leave a description in km weighing its metre-sized rows a thousandth). Converged when the
    residuals pass :func:`residual_met` and the scaled step is below ``tol``, or has stopped
    shrinking at most ten times the noise that rounding of the residual causes in it
    (:func:`step_noise`: an ill-conditioned system, e.g. a very stiff joint compliance,
    whose steps stall there).

    Returns ``(u, iterations)``. Raises :class:`ConvergenceError` (with ``partial`` = the
    last iterate) if the Jacobian is singular or ``max_iter`` is reached.
    """
    u = np.array(u0, dtype=float)
    scale = np.ones_like(u) if scale is None else scale
    r = fun(u)
    step = np.inf
    for it in range(1, max_iter + 1):
        J = jac(u)
        # rows measured against the size of their terms: the merit function and the
        # convergence test then treat equations in N, N m and m alike
        row = np.abs(J * scale).max(axis=1)
        row[~(row > 0)] = 1.0
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
        prev_step, step = step, np.max(np.abs(lam * du / scale))
        if residual_met(r, J, u, residual_tol) and (
                step < tol or (step > 0.5 * prev_step  # stalled, no longer converging
                               and step <= 10 * step_noise(_dense.solve, J * scale, J * scale, u / scale))):
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
        system.check_values({n: x[system.index(n)] for n in system.parameter_names})
    system.check_limits(x)
    unknowns = choose_unknowns(system, hold=hold, free=free)
    idx = np.array([system.index(n) for n in unknowns])

    def fun(u: np.ndarray) -> np.ndarray:
        y = x.copy()
        y[idx] = u
        return system.residual(y)

    def jac(u: np.ndarray) -> np.ndarray:
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
