"""Problems handed to the continuation engine: which names are unknown, and how to evaluate.

An :class:`EquilibriumProblem` is an :class:`~mechcont.equations.EquationSystem` seen
through a *lens*: a list of unknown names (as many as there are equations) plus the one
continuation parameter. Everything else is held at the values of a base point. Changing
the lens ("hold theta4, free F") never touches the equations.

The engine only needs the small :class:`ContinuationProblem` interface, so the
two-parameter fold problem (:mod:`._folds`) is handed to the very same engine.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol

import numpy as np

from ..equations import EquationSystem, Model
from ..errors import InputError

if TYPE_CHECKING:
    from ._events import Event, PointState

__all__ = ["ContinuationProblem", "EquilibriumProblem", "choose_unknowns", "CompiledModel", "CompiledFold"]


class CompiledFold(NamedTuple):
    """What a fold curve's extra row needs in the compiled corrector (:meth:`~._folds.FoldProblem.compiled_model`):
    the problem's ``evaluate`` (called where the state Jacobian is exactly singular), the compiled second
    derivatives ``(fn2, n_out2, src2)`` of the entries that enter ``dA``, with their equation ``i``, state
    position ``pos``, column ``c`` and factor ``R_i C_pos``, and the equilibration's ``rowcol`` (``R C``) and
    ``log_norm`` (``log N``)."""

    evaluate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    fn2: Any
    n_out2: int
    src2: np.ndarray
    i: np.ndarray
    pos: np.ndarray
    c: np.ndarray
    factor: np.ndarray
    rowcol: np.ndarray
    log_norm: float


class CompiledModel(NamedTuple):
    """A problem's model as the compiled corrector (:mod:`._kernel`) calls it from C.

    ``fn`` the compiled residual-and-Jacobian function of the full variable vector (SymEngine's),
    writing ``n_out`` values; ``src`` where the residuals and then the Jacobian's columns of the
    unknowns (``idx``, column by column) are read among them; ``base`` the full vector the unknowns
    are written into; ``fold`` a fold curve's extra row (:class:`CompiledFold`), None for equilibria.
    """

    fn: Any
    n_out: int
    src: np.ndarray
    base: np.ndarray
    idx: np.ndarray
    fold: CompiledFold | None = None


class ContinuationProblem(Protocol):
    """What the continuation engine needs of a problem G(u) = 0, u in R^(n+1).

    A typed protocol: equilibria (:class:`EquilibriumProblem`) and fold curves
    (:class:`~._folds.FoldProblem`) implement it and are handed to the same engine.
    Subclasses inherit the defaults below.

    Attributes
    ----------
    names:
        Name of each component of ``u`` (the last one need not be the parameter).
    param_index:
        Index in ``u`` of the continuation parameter (folds are its turning points).
    scale:
        Typical magnitude of each component of ``u``.
    idx:
        Index in the full variable vector of each leading component of ``u`` (bounds on
        those are solved for directly), or None.
    system:
        The equation system whose full variable vectors :meth:`full` makes (events read
        variables of the branch by name in it).
    """

    system: EquationSystem
    names: tuple[str, ...]
    param_index: int
    scale: np.ndarray
    idx: np.ndarray | None = None

    def residual(self, u: np.ndarray) -> np.ndarray:  # pragma: no cover - interface
        """G(u): n residuals (units of each equation) at the n+1 unknowns ``u``."""
        raise NotImplementedError

    def jacobian(self, u: np.ndarray) -> np.ndarray:  # pragma: no cover - interface
        """dG/du: array (n, n+1), exact."""
        raise NotImplementedError

    def full(self, u: np.ndarray) -> np.ndarray:
        """The full variable vector recorded in the branch at ``u``."""
        raise NotImplementedError  # pragma: no cover - interface

    def evaluate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Residual and Jacobian at ``u`` together (override when sharing work pays)."""
        return self.residual(u), self.jacobian(u)

    def stability(self, u: np.ndarray) -> int:
        """Number of unstable directions at ``u`` (-1 when unknown)."""
        return -1

    def stability_batch(self, U: np.ndarray) -> list[int]:
        """:meth:`stability` at every row of ``U`` (override when a batch is cheaper)."""
        return [self.stability(u) for u in U]

    def test_functions(self) -> list[Event]:
        """Extra events particular to this problem (e.g. cusp detection)."""
        return []

    def compiled_model(self) -> CompiledModel | None:
        """The problem's compiled model for the compiled corrector (:mod:`._kernel`), or None: then
        the corrector calls :meth:`evaluate` (see :meth:`EquilibriumProblem.compiled_model`)."""
        return None

    def refine_fold(self, state: PointState) -> tuple[np.ndarray, dict[str, Any]] | None:
        """Polish a fold found at ``state``: ``(u, info)`` with ``info["status"]``, or None
        when the problem has no fold polish (the located guess then stays approximate)."""
        return None


def choose_unknowns(system: EquationSystem, hold: Iterable[str] = (), free: Iterable[str] = (),
                    exclude: Iterable[str] = ()) -> list[str]:
    """The unknown names of a square solve: states not held, plus freed names.

    Raises :class:`InputError` when a name is unknown, or when the count does not equal
    the number of equations (saying how many to hold or free).
    """
    hold, free, exclude = list(hold), list(free), list(exclude)
    for n in (*hold, *free, *exclude):
        system.index(n)
    for n in hold:
        if n in free:
            raise InputError(n, "cannot be both held and freed")
    unknowns = [n for n in system.state_names if n not in hold and n not in exclude]
    for n in free:
        if n in exclude:
            raise InputError(n, "is the continuation parameter; it cannot also be freed")
        if n not in unknowns:
            unknowns.append(n)
    n_eq = system.n_equations
    if len(unknowns) != n_eq:
        diff = len(unknowns) - n_eq
        what = f"hold {diff} more state(s)" if diff > 0 else f"free {-diff} more parameter(s)"
        raise InputError(
            "free" if diff < 0 else "hold",
            f"{len(unknowns)} unknowns ({', '.join(unknowns)}) for {n_eq} equations: {what}",
        )
    return unknowns


class EquilibriumProblem(ContinuationProblem):
    """Equilibria of ``system`` in the continuation parameter ``vary``.

    Parameters
    ----------
    system:
        The compiled equation system.
    base:
        Full variable vector supplying the held values.
    vary:
        Name of the continuation parameter (any variable, state or parameter).
    unknowns:
        Names solved for (one per equation), not including ``vary``.
    scales:
        Optional ``{name: typical magnitude}`` overrides.
    """

    def __init__(self, system: EquationSystem, base: np.ndarray, vary: str, unknowns: Sequence[str],
                 scales: Mapping[str, float] | None = None, stability: bool = True) -> None:
        self.system = system.compile()
        self.base = np.array(base, dtype=float)
        if vary in unknowns:
            raise InputError(vary, "the continuation parameter must not be among the unknowns")
        self.names = (*unknowns, vary)
        self.idx = np.array([system.index(n) for n in self.names])
        self.param_index = len(self.names) - 1
        sc = system.scales()
        for n, v in (scales or {}).items():
            sc[system.index(n)] = v
        self.scale = sc[self.idx]
        # an ODE model's stability is its Jacobian's (unstable_rates); an algebraic one has none
        ode = system.ode if isinstance(system, Model) else None
        self._ode = ode is not None and not ode.algebraic
        self._stability = stability and (system.mechanics is not None or self._ode)
        self._columns = self.system.columns(self.idx)

    def u_of(self, x: np.ndarray) -> np.ndarray:
        """Restrict a full vector to this problem's unknowns + parameter."""
        return np.asarray(x, float)[self.idx]

    def full(self, u: np.ndarray) -> np.ndarray:
        x = self.base.copy()
        x[self.idx] = u
        return x

    def residual(self, u: np.ndarray) -> np.ndarray:
        return self.system.residual(self.full(u))

    def jacobian(self, u: np.ndarray) -> np.ndarray:
        return self._columns.residual_and_jacobian(self.full(u))[1]

    def evaluate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = self.base.copy()  # self.full(u), inline: this runs at every Newton iteration
        x[self.idx] = u
        return self._columns.residual_and_jacobian(x)

    def compiled_model(self) -> CompiledModel | None:
        """The :class:`CompiledModel` of the equilibrium rows for the compiled corrector (:mod:`._kernel`),
        or None when nothing is compiled (a constant model)."""
        gather = self._columns.gather_parts()
        if gather is None:
            return None
        fn, n_out, src = gather
        return CompiledModel(fn, n_out, src, self.base, np.asarray(self.idx))

    def stability(self, u: np.ndarray) -> int:
        if self._stability and self._ode and isinstance(self.system, Model):  # _ode: a Model's facts
            return unstable_rates(self.system, self.full(u))
        mechanics = self.system.mechanics
        if not self._stability or mechanics is None:
            return -1
        return mechanics.stability(self.full(u)).n_unstable

    def stability_batch(self, U: np.ndarray) -> list[int]:
        if self._stability and self._ode:
            return [self.stability(u) for u in U]
        mechanics = self.system.mechanics
        if not self._stability or mechanics is None:
            return [-1] * len(U)
        X = np.tile(self.base, (len(U), 1))
        X[:, self.idx] = U
        counts: list[int] = mechanics.count_unstable(X).tolist()
        return counts


def unstable_rates(model: Model, x: np.ndarray, rtol: float = 1e-9) -> int:
    """The number of eigenvalues of an ODE model's ``df/du`` at the full vector ``x`` with a positive real
    part (the dimension of the unstable manifold of the equilibrium there); a real part within ``rtol``
    of the largest eigenvalue's modulus counts as zero (neutral: a fold, a Hopf point)."""
    from ..equations import dynamics_of

    lam = dynamics_of(model).linearise(x).eigenvalues()
    if not len(lam):
        return 0
    tol = rtol * max(float(np.abs(lam).max()), 1e-300)
    return int(np.count_nonzero(lam.real > tol))
