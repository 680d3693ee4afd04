"""Square solves: a first equilibrium from a guess, with any states held and parameters freed."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence

import numpy as np
import scipy.linalg.lapack  # already imported with the package (._condensation): costs nothing here

from .. import _dense
from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError
from ._problem import choose_unknowns

__all__ = ["find_equilibrium", "newton_square", "residual_met", "step_noise"]

_FLOOR = 100 * np.finfo(float).eps
#: Rounding of one evaluation of a residual row, relative to the sum of its terms' sizes:
#: the noise model of :func:`step_noise` (the floor of :func:`residual_met` is a generous 100x that).
_ROUNDING = np.finfo(float).eps
#: Condition number (2-norm) of the equilibrated Jacobian (rows over the size of their terms, columns times the
#: unknowns' scales) above which :func:`newton_square` calls it singular.
SINGULAR_CONDITION = 1e14
#: How far below the 1-norm condition number LAPACK's estimate (``dgecon``) may fall: it is a lower bound, in
#: practice rarely by more than a factor 3 (Higham, Accuracy and Stability of Numerical Algorithms, ch. 15).
_ESTIMATE_MARGIN = 10.0

_NOT_FIXED = "the held/freed choice does not fix the configuration here; hold a different state or free a different parameter"
_GETRF, _GECON = scipy.linalg.lapack.dgetrf, scipy.linalg.lapack.dgecon


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


def _singular(A: np.ndarray, J: np.ndarray, r: np.ndarray, it: int, names: Sequence[str]) -> str | None:
    """Why the step cannot be trusted at iteration ``it`` (a one-line message), or None when it can.

    ``A`` is the equilibrated Jacobian (its 2-norm condition number, from an SVD, is what is tested
    against :data:`SINGULAR_CONDITION`), ``J`` the raw one and ``r`` the residual. The message says
    where (iteration, residual, the equations with a non-finite entry or the unknowns along the
    near-null direction, by ``names`` or position) and why.
    """
    where = f"at iteration {it} (residual {np.linalg.norm(r):.3g})"
    for what, bad in (("Jacobian", ~np.all(np.isfinite(J), axis=1)), ("residual", ~np.isfinite(r))):
        if bad.any():
            rows = ", ".join(map(str, np.nonzero(bad)[0][:5]))
            return f"non-finite {what} {where} in equation(s) {rows}: the model is not defined there; try a closer guess"
    try:
        _, s, Vt = _dense.svd(A)
    except np.linalg.LinAlgError:
        return f"singular Jacobian {where}: its SVD did not converge"
    with np.errstate(divide="ignore"):
        cond = s[0] / s[-1]
    if cond <= SINGULAR_CONDITION:
        return None
    v = np.abs(Vt[-1])
    big = [int(i) for i in np.argsort(-v, kind="stable") if v[i] >= 0.1 * v.max()][:4]
    along = ", ".join(names[i] if i < len(names) else f"unknown {i}" for i in big)
    return (f"singular Jacobian at iteration {it} (residual {np.linalg.norm(r):.3g}, condition number {cond:.2g} of "
            f"the scaled Jacobian; null direction along {along}): {_NOT_FIXED}")


def newton_square(fun: Callable[[np.ndarray], np.ndarray], jac: Callable[[np.ndarray], np.ndarray], u0: np.ndarray, *,
                  tol: float = 1e-10, residual_tol: float = 1e-10, max_iter: int = 50,
                  scale: np.ndarray | None = None, names: Sequence[str] = ()) -> tuple[np.ndarray, int]:
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

    The condition number of that equilibrated Jacobian is estimated from its LU factors
    (LAPACK's ``dgecon``, a few solves); only when the estimate comes within
    :data:`_ESTIMATE_MARGIN` ``n`` times of :data:`SINGULAR_CONDITION` is the exact 2-norm
    condition number computed (an SVD), and the Jacobian refused above it.
    ``names`` (of the unknowns, optional) serve the error message.

    Returns ``(u, iterations)``. Raises :class:`ConvergenceError` (with ``partial`` = the
    last iterate) if the Jacobian is singular or not finite (the message says at which
    iteration, and along which unknowns), or ``max_iter`` is reached.
    """
    u = np.array(u0, dtype=float)
    scale = np.ones_like(u) if scale is None else scale
    n = len(u)
    # trip the exact test where kappa_2 <= n kappa_1 could exceed the limit, allowing for the estimate's shortfall
    trip = n * _ESTIMATE_MARGIN / SINGULAR_CONDITION
    r = fun(u)
    step = np.inf
    for it in range(1, max_iter + 1):
        J = jac(u)
        # rows measured against the size of their terms: the merit function and the
        # convergence test then treat equations in N, N m and m alike
        row = np.abs(J * scale).max(axis=1)
        row[~(row > 0)] = 1.0
        norm = np.linalg.norm(r / row)
        A = J * scale / row[:, None]
        du = why = None
        if np.isfinite(np.add.reduce(A, None)) and np.isfinite(norm):
            lu, piv, info = _GETRF(A)
            if info == 0:
                rcond, _ = _GECON(lu, np.abs(A).sum(axis=0).max())
                if rcond < trip:  # possibly singular: the SVD decides (the estimate passing needs none)
                    why = _singular(A, J, r, it, names)
                if why is None:  # the step itself from J, as it always was: the iterates do not move
                    du = _dense.solve(J, -r)
        if du is None:
            why = why or _singular(A, J, r, it, names) or (
                f"singular Jacobian at iteration {it} (a zero pivot or a non-finite step): {_NOT_FIXED}")
            raise ConvergenceError(why, partial=u)
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
                             scale=system.scales()[idx], names=unknowns)
    except ConvergenceError as exc:
        partial = x.copy()
        if exc.partial is not None:
            partial[idx] = exc.partial
        held = ", ".join(f"{k}={v:g}" for k, v in hold.items()) or "nothing held"
        raise ConvergenceError(f"start did not converge ({held}): {exc}", partial=partial) from None
    x[idx] = u
    return x
