"""Exact sensitivities of equilibria and folds to parameters (implicit-function theorem).

The engine's part of :mod:`mechcont.analysis.sensitivity` (which adds the downlock force and
sensitivity columns of a branch), here so that :meth:`Branch.sensitivity` needs no analysis.

Every quantity of interest is a solution of a square system with exact Jacobians, so its
derivative with respect to a held parameter ``p`` is one linear solve, not a re-solve:

* an equilibrium ``G(u, p) = 0`` in the unknowns ``u`` (states, freed parameters):
  ``du/dp = -G_u^-1 G_p``. The downlock force is one of these (the lock condition held,
  the force among ``u``), and so is the continuation parameter at a point defined by a
  state kept at its value there (that state held, the continuation parameter freed);
* a fold in ``lam`` (the continuation parameter): ``G(s, lam, p) = 0`` with ``G_s`` singular.
  Differentiating ``G(s*(p), lam*(p), p) = 0`` and multiplying by the left null vector
  ``w`` (``w^T G_s = 0``) removes the unknown ``ds*/dp``:
  ``dlam*/dp = -w^T G_p / w^T G_lam``. The states' derivatives at the fold come from the
  standard augmented system ``G = 0, G_s v = 0, |v_hat| = 1`` (second derivatives of
  ``G``, exact), whose ``lam`` row must give the same number.

``G_p`` is a column of the system's full Jacobian (:meth:`EquationSystem.jacobian` is with
respect to every named variable): nothing is differenced. Results are in SI units per SI
unit (``N/(N/m)`` for a force by a stiffness); angles in radians.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..equations import EquationSystem
from ..errors import ConvergenceError, InputError
from ..units import derivative_unit
from ._fold_point import fold_quantities, fold_scaling, polish_fold
from ._move import move_point
from ._problem import choose_unknowns
from ._scaling import equilibrate

if TYPE_CHECKING:
    from ._special_point import SpecialPoint

__all__ = ["Sensitivity", "equilibrium_sensitivity", "fold_sensitivity", "point_sensitivity", "derivative_unit",
           "check_parameters", "write_json"]

#: Above this condition number of the equilibrated Jacobian the solve is taken to be singular (a fold of that lens).
_SINGULAR = 1e13


@dataclass(frozen=True)
class Sensitivity:
    """Derivatives of one quantity with respect to parameters, exact at a solved point.

    Attributes
    ----------
    quantity:
        Name of the differentiated variable (e.g. ``"F"``, the fold load or downlock force).
    value:
        Its value at the point (SI).
    unit:
        Its SI unit.
    kind:
        ``"fold"`` (the fold load), ``"equilibrium"`` (an unknown of a square solve) or
        ``"downlock"`` (the downlock force).
    derivatives:
        ``{parameter: d quantity / d parameter}`` in SI units (see :attr:`units`).
    units:
        ``{parameter: unit of the derivative}``, e.g. ``{"k": "N/(N/m)"}``.
    states:
        ``{parameter: {unknown: d unknown / d parameter}}`` for every unknown of the point's
        system (the states' derivatives at the point, SI).
    x:
        The full variable vector at the point (SI), as solved.
    point:
        Where the point came from (e.g. ``"LP1"``), written into the JSON when set.
    """

    quantity: str
    value: float
    unit: str
    kind: str
    derivatives: dict[str, float]
    units: dict[str, str]
    states: dict[str, dict[str, float]] = field(default_factory=dict)
    x: np.ndarray | None = None
    point: str = ""

    def __post_init__(self) -> None:
        # -0.0 (an exact zero) prints as 0; frozen: set once here
        object.__setattr__(self, "derivatives", {p: float(d) + 0.0 for p, d in self.derivatives.items()})

    def __getitem__(self, name: str) -> float:
        try:
            return self.derivatives[name]
        except KeyError:
            raise InputError(name, f"no derivative with respect to it; computed: {', '.join(self.derivatives)}") from None

    def to_dict(self) -> dict:
        """``{param: derivative, ..., "units": {param: unit}, "quantity": {name, value, unit, kind[, point]}}`` (SI)."""
        quantity = {"name": self.quantity, "value": self.value, "unit": self.unit, "kind": self.kind}
        return {**self.derivatives, "units": dict(self.units),
                "quantity": {**quantity, "point": self.point} if self.point else quantity}

    def to_json(self, path: str | os.PathLike) -> Path:
        """Write :meth:`to_dict` as JSON, atomically (no partial file on failure)."""
        return write_json(path, self.to_dict())

    def table(self) -> str:
        """The derivatives as plain text, one parameter per line (SI units)."""
        head = f"d{self.quantity}/dp at {self.quantity} = {self.value:.10g} {self.unit} ({self.kind})"
        width = max(len(p) for p in self.derivatives) if self.derivatives else 1
        return "\n".join([head, *(f"  {p:<{width}}  {d: .10g} {self.units[p]}" for p, d in self.derivatives.items())])


def write_json(path: str | os.PathLike, doc: dict) -> Path:
    """Write ``doc`` as indented JSON at ``path`` atomically (no partial file left on failure)."""
    import json  # here: importing this module (for the special points' loads) writes nothing

    from .._io import atomic_write

    def write(tmp: str) -> None:
        with open(tmp, "w") as f:
            json.dump(doc, f, indent=1)

    return atomic_write(path, write)



def check_parameters(system: EquationSystem, params: Iterable[str], excluded: Iterable[str]) -> list[str]:
    """``params`` as a list, each a variable held at the point; else one :class:`InputError` listing the valid names.

    ``excluded``: the names solved for at the point (and the quantity itself); a derivative
    with respect to them is not defined.
    """
    excluded = set(excluded)
    valid = [n for n in system.names if n not in excluded]
    params = list(params)
    if not params:
        raise InputError("params", f"name at least one parameter; valid: {', '.join(valid)}")
    for p in params:
        if p not in valid:
            why = "is solved for at this point" if p in excluded else f"is not a variable of model '{system.name}'"
            raise InputError("params", f"'{p}' {why}; valid: {', '.join(valid)}")
    if len(set(params)) != len(params):
        raise InputError("params", "a parameter is named twice")
    return params


def variable_indices(system: EquationSystem, names: Sequence[str]) -> np.ndarray:
    """The indices of the variables ``names`` in ``system``'s vector (an integer array)."""
    return np.array([system.index(n) for n in names], dtype=np.intp)


def solve_equilibrated(A: np.ndarray, B: np.ndarray, reference: np.ndarray, what: str) -> np.ndarray:
    """``A^-1 B`` on the equilibrated matrix (mixed units); :class:`ConvergenceError` when singular."""
    row, col = equilibrate(A, reference)
    As = A * row[:, None] * col
    if not np.isfinite(As).all() or np.linalg.cond(As) > _SINGULAR:
        raise ConvergenceError(f"{what}: the Jacobian is singular at this point (a fold or branch point of this "
                               "system); the quantity is not differentiable here")
    return col[:, None] * np.linalg.solve(As, row[:, None] * B)


def derivative_units(system: EquationSystem, quantity: str, params: Sequence[str]) -> dict[str, str]:
    """``{parameter: unit of d quantity / d parameter}`` for each of ``params``."""
    u = system.variable(quantity).unit
    return {p: derivative_unit(u, system.variable(p).unit) for p in params}


def state_table(names: Sequence[str], params: Sequence[str], D: np.ndarray) -> dict[str, dict[str, float]]:
    """``{parameter: {name: D[i, j]}}``: the derivatives ``D`` (rows ``names``, columns ``params``) as nested dicts."""
    return {p: {n: float(D[i, j]) for i, n in enumerate(names)} for j, p in enumerate(params)}


def _radians(system: EquationSystem, names: Sequence[str]) -> np.ndarray:
    return np.array([system.variable(n).unit == "rad" for n in names], dtype=bool)


def equilibrium_sensitivity(system: EquationSystem, x: np.ndarray, unknowns: Sequence[str], params: Iterable[str],
                            quantity: str, kind: str = "equilibrium") -> Sensitivity:
    """Derivatives of the unknown ``quantity`` of the square solve ``G(u, p) = 0`` at ``x``: ``du/dp = -G_u^-1 G_p``.

    Parameters
    ----------
    system:
        The model.
    x:
        A solved full variable vector (SI).
    unknowns:
        The names solved for (one per equation); everything else is held.
    params:
        Held names to differentiate by.
    quantity:
        One of ``unknowns``: the quantity whose derivatives are returned.

    Returns a :class:`Sensitivity` (with every unknown's derivatives in ``states``). Raises
    :class:`InputError` for bad names, :class:`~mechcont.errors.ConvergenceError` where
    ``G_u`` is singular (a fold of this solve).
    """
    unknowns = list(unknowns)
    if len(unknowns) != system.n_equations:
        raise InputError("unknowns", f"{len(unknowns)} unknowns for {system.n_equations} equations")
    if quantity not in unknowns:
        raise InputError(quantity, f"is not solved for at this point; unknowns: {', '.join(unknowns)}")
    params = check_parameters(system, params, unknowns)
    x = np.asarray(x, dtype=float)
    J = system.jacobian(x)
    D = -solve_equilibrated(J[:, variable_indices(system, unknowns)], J[:, variable_indices(system, params)],
                            _radians(system, unknowns), f"sensitivity of {quantity}")
    q = unknowns.index(quantity)
    return Sensitivity(quantity, float(x[system.index(quantity)]), system.variable(quantity).unit, kind,
                       {p: float(D[q, j]) for j, p in enumerate(params)}, derivative_units(system, quantity, params),
                       state_table(unknowns, params, D), x.copy())


def fold_sensitivity(system: EquationSystem, x: np.ndarray, states: Sequence[str], vary: str, params: Iterable[str],
                     *, polish: bool = True, null_vector: np.ndarray | None = None) -> Sensitivity:
    """Derivatives of the fold load (the value of ``vary`` at a fold) with respect to ``params``.

    ``dlam*/dp = -w^T G_p / w^T G_lam`` with ``w`` the left null vector of ``G_s`` at the
    fold (``s``: the unknown ``states``); the states' derivatives (``states`` of the result,
    and ``vary``'s own, equal to the former) from the standard augmented fold system.

    Parameters
    ----------
    system, x:
        The model and a point at (or, with ``polish``, near) a fold in ``vary``.
    states:
        The unknowns of the equilibrium branch (not ``vary``).
    vary:
        The parameter in which the point is a fold (its continuation parameter).
    params:
        Held names to differentiate by.
    polish:
        Locate the fold to machine precision first (:func:`~mechcont.continuation._fold_point.polish_fold`).
    null_vector:
        A guess of the right null vector over ``states`` for the polish.

    Returns a :class:`Sensitivity` of kind ``"fold"``; its ``x`` is the polished fold.
    """
    states = [s for s in states]
    if vary in states:
        raise InputError(vary, "is the fold's parameter; it cannot be among the unknown states")
    params = check_parameters(system, params, [*states, vary])
    x = np.asarray(x, dtype=float)
    if polish:
        x = polish_fold(system, x, states, vary, v0=null_vector).x
    s_idx, lam = variable_indices(system, states), system.index(vary)
    v, w, _ = fold_quantities(system, x, s_idx, lam)
    J = system.jacobian(x)
    p_idx = variable_indices(system, params)
    d_lam = -(w @ J[:, p_idx]) / (w @ J[:, lam])
    D = _fold_states_derivative(system, x, s_idx, lam, v, p_idx)
    return Sensitivity(vary, float(x[lam]), system.variable(vary).unit, "fold",
                       {p: float(d) for p, d in zip(params, d_lam)}, derivative_units(system, vary, params),
                       state_table([*states, vary], params, D), x)


def _fold_states_derivative(system: EquationSystem, x: np.ndarray, s_idx: np.ndarray, lam: int, v: np.ndarray,
                            p_idx: np.ndarray) -> np.ndarray:
    """``d(s, lam)/dp`` (rows: states then ``lam``) from the augmented system ``G = 0, G_s C v_hat = 0, |v_hat|^2/2 = 1/2``.

    The null vector is carried equilibrated (``v = C v_hat``, ``C`` the fold's column scales)
    as the fold polish carries it, so the normalisation does not mix units.
    """
    n = len(s_idx)
    idx = np.concatenate([s_idx, [lam]])
    row, col = fold_scaling(system, x, idx)
    cs = col[:n]
    vh = v / cs
    vh /= np.linalg.norm(vh)
    vf = np.zeros(len(x))
    vf[s_idx] = cs * vh
    J, H = system.jacobian(x), system.jacobian_derivative(x, vf)
    A = np.zeros((2 * n + 1, 2 * n + 1))
    A[:n, :n + 1] = J[:, idx]
    A[n:2 * n, :n + 1] = H[:, idx]
    A[n:2 * n, n + 1:] = J[:, s_idx] * cs
    A[2 * n, n + 1:] = vh
    B = np.zeros((2 * n + 1, len(p_idx)))
    B[:n], B[n:2 * n] = J[:, p_idx], H[:, p_idx]
    reference = np.concatenate([_radians(system, [system.names[i] for i in idx]), np.zeros(n, dtype=bool)])
    return -solve_equilibrated(A, B, reference, "fold sensitivity")[:n + 1]


#: Special points whose quantity a higher layer defines: a stop's release (``SR``: the load where its
#: reaction reaches zero) and a fold curve's cusp (``CP``). ``label -> handler(system, x, params, vary,
#: label, info, unknowns, values)``, registered by :mod:`mechcont.analysis` when it is imported (it
#: owns stops and cusps; this layer does not import it).
SPECIAL_POINTS: dict[str, Callable[..., Sensitivity]] = {}


def point_sensitivity(system: EquationSystem, point: SpecialPoint | np.ndarray, params: Iterable[str], *,
                      vary: str | None = None, unknowns: Sequence[str] | None = None, of: str | None = None,
                      keep: str | None = None, label: str | None = None,
                      values: Mapping[str, float] | None = None) -> Sensitivity:
    """Derivatives of a branch point's quantity ``of`` (default: the continuation parameter ``vary``).

    * ``of`` is ``vary`` at a fold (``label`` ``"LP"``): the fold load, :func:`fold_sensitivity`.
    * ``of`` is ``vary`` elsewhere: the point is defined by the state ``keep`` held at its
      value there, ``vary`` solved for (:func:`equilibrium_sensitivity`); without ``keep``
      an :class:`InputError` says so.
    * ``of`` is one of the branch's ``unknowns`` (e.g. the downlock force of a downlock
      branch): ``vary`` held, :func:`equilibrium_sensitivity`.

    ``vary``, ``unknowns`` and ``label`` default to the point's (a :class:`SpecialPoint`
    from a continuation records them; one read from a CSV does not); ``unknowns`` else to
    the model's states. ``values`` (``{name: value}``, SI) moves the point to those held values
    first: followed there by a homotopy in the changed parameters (:func:`~._move.move_point`:
    a fold as a fold curve that keeps the sign of its normal-form coefficient, an ordinary point
    with its lens), never re-solved blindly from the old row; :class:`~._move.PointLost` (an
    :class:`InputError`) in one line when the point ends on the way (a fold past a cusp).
    """
    # a bare vector (array, list) or a recorded point, told apart without importing the point's class, whose
    # ``sensitivity`` method calls this function
    sp: SpecialPoint | None = None if isinstance(point, (np.ndarray, Sequence)) else point
    x = np.asarray(point if sp is None else sp.x, dtype=float)
    if x.shape != (len(system.names),):
        raise InputError("point", f"has {x.size} values; model '{system.name}' has {len(system.names)} variables")
    vary = vary or (sp.vary if sp else None)
    if not vary:
        raise InputError("vary", "the point does not say its continuation parameter; give it")
    system.variable(vary)
    label = label if label is not None else (sp.label if sp is not None else "")
    of = of or vary
    if of == vary and label in ("SR", "NSF", "CP"):
        handler = SPECIAL_POINTS.get(label)
        if handler is None:
            raise InputError("point", f"the load at a {label} point is defined by mechcont.analysis: import it (or "
                                      "use mechcont.analysis.sensitivity.point_sensitivity)")
        return handler(system, x, params, vary, label, sp.info if sp else {}, unknowns, values)
    lens = list(unknowns or (sp.unknowns if sp else None) or choose_unknowns(system, exclude=[vary]))
    fold = of == vary and label == "LP"
    if of != vary:
        solved = lens
    elif fold:
        solved = [*lens, vary]
    elif keep is None and label == "HB":  # keeping a state there is not the Hopf condition: not its sensitivity
        raise InputError("point", f"a Hopf point (HB): the sensitivity of {vary} there is the slope of its Hopf "
                                  f"curve, mechcont folds MODEL --point BRANCH.csv:HB1 --along P2")
    elif keep is None:
        raise InputError("keep", f"the point is not a fold: name the state that defines it (kept at its value there, "
                                 f"{vary} solved for); one of: {', '.join(lens)}")
    elif keep not in lens:
        raise InputError("keep", f"'{keep}' is not solved for on the branch; one of: {', '.join(lens)}")
    else:
        solved = [n for n in lens if n != keep] + [vary]
    v0 = sp.null_vector if sp else None
    if values:
        moved = move_point(system, x, values, solved=solved, vary=vary if fold else None, states=lens,
                           null_vector=v0, name=_name(sp, label))
        x, v0 = moved.x, moved.v
        system.check_limits(x)
    if fold:
        return fold_sensitivity(system, x, lens, vary, params, null_vector=v0)
    return equilibrium_sensitivity(system, x, solved, params, of)


def _name(sp: SpecialPoint | None, label: str | None) -> str:
    """How messages name the point: its label (``LP``) or "the point"."""
    return f"the {label} point" if label else "the point"
