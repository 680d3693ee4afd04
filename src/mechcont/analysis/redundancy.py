"""Redundant constraints along a branch: where the joints over-constrain the mechanism, and which
reactions statics cannot determine there.

At each point of a branch the constraint Jacobian ``Phi_q`` (rigid rows only: compliant joint rows
are springs) is decomposed by SVD. Its rank gives the degrees of freedom ``n_q - rank``; its left
null space (``w`` with ``w^T Phi_q = 0``) holds the self-stresses: reactions along ``w`` can be
added to any solution without upsetting equilibrium, so every row with a non-zero entry in some
``w`` has a reaction that statics alone cannot determine. Where the rank changes along the branch
the mechanism gains or loses a degree of freedom (a singular configuration: two links aligned, a
lock-up, a bifurcation); where it stays, the redundancy is structural (e.g. a planar loop built of
spatial joints, a Bennett linkage).

Rows dropped (``redundant = "drop"``) hold their reactions at zero instead of their constraint;
the mechanics keeps every rigid row, so the reactions reported indeterminate here are those of the
whole over-constrained set, as ``mechcont check`` names them, whichever rows are dropped. The rows
dropped at build are chosen again along a branch where the kept ones lose rank (``RC`` points);
:func:`redundancy_along` reports how far the rows dropped at build stay satisfied
(``dropped_residual``): zero while the geometry keeps them implied.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..equations import Model
from ..errors import InputError

if TYPE_CHECKING:
    from ..continuation import Branch

__all__ = ["redundancy_along", "RedundancyReport", "RedundancyState"]


@dataclass(frozen=True)
class RedundancyState:
    """The constraint structure on a stretch of the branch that starts at row ``start``.

    ``rank`` of the rigid constraint rows, ``dof`` = coordinates - rank, ``indeterminate`` the
    reactions that statics cannot determine there and ``joints`` the joints they belong to."""

    start: int
    rank: int
    dof: int
    indeterminate: tuple[str, ...]
    joints: tuple[str, ...]


@dataclass(frozen=True)
class RedundancyReport:
    """Redundancy along a branch: per row ``rank`` and ``dof`` (arrays), the stretches of equal
    structure (:class:`RedundancyState`, in branch order), the rows dropped at build and their
    largest residual over the branch (m or rad; 0.0 when none were dropped), and the rows where the
    dropped rows were chosen again (``RC`` points of the branch)."""

    rank: np.ndarray
    dof: np.ndarray
    states: tuple[RedundancyState, ...]
    dropped: tuple[str, ...]
    dropped_residual: float
    switches: tuple[int, ...] = ()

    @property
    def changes(self) -> tuple[RedundancyState, ...]:
        """The states after the first: where the structure changes along the branch."""
        return self.states[1:]

    def lines(self, labels: Sequence[str] | None = None) -> list[str]:
        """A plain-text account, one line per stretch (``labels``: the branch's point labels)."""
        out = []
        if self.dropped:
            out.append(f"dropped at build (reactions indeterminate): {', '.join(self.dropped)}; their largest "
                       f"residual along the branch {self.dropped_residual:.3g}"
                       + (f"; chosen again where the kept rows lost rank (RC at rows {', '.join(map(str, self.switches))})"
                          if self.switches else ""))
        for st in self.states:
            where = f"from row {st.start}" + (f" ({labels[st.start]})" if labels is not None and labels[st.start]
                                              else "")
            what = (f"statically indeterminate: {', '.join(st.indeterminate)} (joints {', '.join(st.joints)})"
                    if st.indeterminate else "every reaction determinate")
            out.append(f"{where}: {st.dof} degree(s) of freedom, rank {st.rank}; {what}")
        return out


def _row_joint(name: str) -> str:
    """The joint of a constraint row named ``<joint>_<suffix>`` (``pin_x``, ``knee_rot1``, ``act_length``)."""
    return name.rsplit("_", 1)[0]


def redundancy_along(system: Model, branch: Branch, *, rtol: float = 1e-9) -> RedundancyReport:
    """The constraint rank, degrees of freedom and statically indeterminate reactions at every point
    of ``branch`` (a :class:`~mechcont.continuation.Branch` of ``system``), see the module docstring.

    ``rtol``: singular values below ``rtol`` times the largest count as zero.
    """
    mech = system.mechanics
    if mech is None:
        raise InputError("model", f"'{system.name}' has no mechanics (constraints): no redundancy to report")
    nq = len(mech.coordinates)
    rows = mech.constraint_names if mech.constraint_names is not None else system.equation_names[nq:nq + mech.n_constraints]
    reactions = dict(zip(system.equation_names[nq:], system.reaction_names))
    if mech.constraint_names is not None:  # a row dropped from the equations (spatial: rigid rows first, in order)
        reactions.update((r, lam) for r, lam in zip(rows, system.reaction_names) if r not in reactions)
    ranks: list[int] = []
    dofs: list[int] = []
    states: list[tuple[int, int, tuple[str, ...]]] = []  # (first row, rank, rows in the redundancy)
    for i, x in enumerate(branch.values):
        A = mech.phi_q(x)
        bad: tuple[str, ...]
        if A.shape[0] == 0:
            rank, bad = 0, ()
        else:
            U, sv, _ = np.linalg.svd(A)
            rank = int(np.sum(sv > rtol * max(sv[0], 1e-300)))
            W = U[:, rank:]
            part = np.max(np.abs(W), axis=1) if W.shape[1] else np.zeros(A.shape[0])
            bad = tuple(rows[int(k)] for k in np.flatnonzero(part > 1e-6) if not rows[int(k)].startswith("norm_"))
        ranks.append(rank)
        dofs.append(nq - rank)
        if not states or states[-1][1:3] != (rank, bad):
            states.append((i, rank, bad))
    out = []
    for start, rank, bad in states:
        joints = tuple(dict.fromkeys(_row_joint(r) for r in bad))
        out.append(RedundancyState(start, rank, nq - rank, tuple(reactions.get(r, r) for r in bad), joints))
    dropped = tuple(system.dropped_constraints)
    residual = 0.0
    if dropped:
        assert system.dropped_residual is not None, "a model with dropped rows has their residual"
        residual = max((system.dropped_residual(x) for x in branch.values), default=0.0)
    switches = tuple(p.index for p in getattr(branch, "special_points", ()) if p.label == "RC")
    return RedundancyReport(np.array(ranks), np.array(dofs), tuple(out), dropped, float(residual), switches)
