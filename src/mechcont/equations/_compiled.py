"""The compiled code of an equation system: each part made from the system's SymEngine form
(:func:`generate_code`: residual and Jacobian in one function, then the second derivatives), and the
evaluation of some Jacobian columns only (:class:`ColumnView`, a continuation's lens in its hot loop).

Apart from :mod:`._system`, which holds what a system is (its variables, equations and the methods every
layer calls): this is how its numbers are made fast, which changes with performance work, not with what a
model means. Its source is part of the disk cache's key (:mod:`._cache`), as :mod:`._system`'s is.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ._backend import Kernel
from ._chunks import compile_chunked
from ._codegen import CompiledFunction, _Gather, compile_scattered, derivative_entries, is_smooth

if TYPE_CHECKING:
    from ._system import EquationSystem

__all__ = ["ColumnView", "generate_code", "SECOND_DERIVATIVES_OPT_LEVEL", "SECOND_DERIVATIVES_CHUNK"]


class ColumnView:
    """Residual and some Jacobian columns of an :class:`EquationSystem`, from one compiled call.

    ``view.residual_and_jacobian(x)`` is ``(G(x), dG/dx[:, columns])`` and
    ``view.jacobian_derivative(x, v)`` is ``system.jacobian_derivative(x, v)[:, columns]``,
    the same values (bit for bit: the same compiled code, and the same sums in the same
    order), without building and then discarding the other columns. Built by
    :meth:`EquationSystem.columns`; the second derivatives are compiled on first use.
    """

    def __init__(self, system: EquationSystem, columns: Sequence[int] | np.ndarray) -> None:
        self.system = system.compile()
        self.columns = np.asarray(columns, dtype=np.intp).reshape(-1)
        if len(set(self.columns.tolist())) != len(self.columns):  # not np.unique: it imports numpy.ma (10 ms)
            raise ValueError("ColumnView: the columns must be distinct")
        n_eq, n = system.n_equations, len(system.names)
        # column by column: the arrays come out in Fortran order, as ``J[:, columns]`` makes
        # them (the layout decides the summation order of later reductions and products)
        self.n_eq, self._shape = n_eq, (len(self.columns), n_eq)
        flat = n_eq + (self.columns[:, None] + np.arange(n_eq, dtype=np.intp) * n).reshape(-1)
        self._res_jac: _Gather = system._code["res_jac"].gather(np.concatenate([np.arange(n_eq, dtype=np.intp), flat]))
        self._hess: tuple[_Gather, np.ndarray, np.ndarray, np.ndarray] | None = None
        self._bins: np.ndarray | None = None

    def residual_and_jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(G(x), dG/dx[:, columns])`` at the full vector ``x`` (the Jacobian in Fortran order)."""
        out = self._res_jac(x)
        return out[:self.n_eq], out[self.n_eq:].reshape(self._shape).T

    def gather_parts(self) -> tuple[Kernel, int, np.ndarray] | None:
        """``(fn, n_out, src)`` of :meth:`residual_and_jacobian`: the compiled function, how many
        values it writes, and where each output entry reads them (``n_out``: a structural zero);
        None when nothing is compiled (a constant model)."""
        return self._res_jac.parts()

    def second_derivative_entries(self) -> tuple[_Gather, np.ndarray, np.ndarray, np.ndarray]:
        """The non-zero second derivatives ``d2 G_i / dx_j dx_k`` with ``k`` among the columns.

        Returns ``(values, i, j, c)``: ``values(x)`` computes them (one compiled call), ``i``
        the equation, ``j`` the full variable index, ``c`` the position of ``k`` in
        :attr:`columns`. ``d/dx (J v)[i, columns[c]]`` is the sum of ``values * v[j]`` over
        the entries with that ``(i, c)``, added in this order (see :meth:`jacobian_derivative`).
        """
        if self._hess is None:
            code = self.system.compile(second_derivatives=True)._code
            n = len(self.system.names)
            where = np.full(n, -1, dtype=np.intp)
            where[self.columns] = np.arange(len(self.columns), dtype=np.intp)
            i, k = np.divmod(code["hess_ik"], n)
            keep = np.flatnonzero(where[k] >= 0)  # entries of other columns only fill bins dropped anyway
            self._hess = (code["hess_values"].gather(keep), i[keep], code["hess_j"][keep], where[k[keep]])
        return self._hess

    def jacobian_derivative(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """``d/dx (J(x) v)[:, columns]`` (Fortran order), ``v`` a full-length vector (see
        :meth:`EquationSystem.jacobian_derivative`)."""
        values, i, j, c = self.second_derivative_entries()
        if self._bins is None:
            self._bins = c * self.n_eq + i
        w = values(x) * np.asarray(v)[j]
        return np.bincount(self._bins, weights=w, minlength=self._shape[0] * self._shape[1]).reshape(self._shape).T


#: LLVM optimisation level of the compiled second derivatives (the residual and Jacobian use 3).
SECOND_DERIVATIVES_OPT_LEVEL = 0
#: Most second-derivative entries compiled as one function; more are compiled as several, each distinct
#: expression once (:func:`~mechcont.equations._chunks.compile_chunked`). SymEngine's CSE and LLVM cost more
#: than linearly in a function's length: the dual-sidestay gear's 19,871 entries (8,537 distinct) compile in
#: 21 s CPU as two functions of distinct entries against 34 s as one (23-25 s as four chunks of every entry,
#: as before). Per call (same process, alternated, loaded machine) 371-425 us against 365-387 us as one; the
#: four chunks of every entry cost 487-514 us, as each computed again the entries it shared with the others.
#: Chunks of 2,500 (of every entry) compiled a little faster (15-18 s) but cost 580-920 us per call. Every model below it
#: (four-bar, shimmy, nose gear) keeps one function, its compiled code unchanged.
SECOND_DERIVATIVES_CHUNK = 5000


def generate_code(sym: dict[str, Any], part: str) -> dict[str, CompiledFunction | np.ndarray]:
    """Differentiate exactly (SymEngine) and compile one part; see :meth:`EquationSystem.compile`.

    ``sym`` holds the positional argument symbols ``syms`` and the equations ``eqs`` in them
    (:func:`~mechcont.equations._codegen.engine_arguments`); the Jacobian's entries are
    kept there for the other part.
    """
    syms, eqs = sym["syms"], sym["eqs"]
    n_eq, n = len(eqs), len(syms)
    if "jac" not in sym:
        sym["smooth"] = [is_smooth(e) for e in eqs]
        sym["jac"] = derivative_entries(eqs, syms, sym["smooth"])
    jac_entries, smooth = sym["jac"], sym["smooth"]
    if part == "residual_jacobian":
        # residual and Jacobian in one compiled function: they share sub-expressions and the
        # engine always needs both (one call instead of two per Newton iteration). Only the
        # Jacobian's non-zero entries are compiled, at their flat positions.
        jac_pos = np.array([i * n + j for (i, j), _ in jac_entries], dtype=np.intp)
        flat = np.concatenate([np.arange(n_eq, dtype=np.intp), n_eq + jac_pos])
        return {"res_jac": compile_scattered(syms, flat, [*eqs, *(d for _, d in jac_entries)], (n_eq + n_eq * n,))}
    hess_idx, hess_expr = [], []
    for (i, j), d in jac_entries:
        for (_, k), d2 in derivative_entries([d], syms, smooth[i]):
            hess_idx.append((i, j, k))
            hess_expr.append(d2)
    h = np.array(hess_idx, dtype=np.intp).reshape(-1, 3)
    # LLVM's optimisation of these long expressions (every product rule twice) costs 5x the
    # compilation (0.6 s vs 0.13 s on the nose gear) for code 1.5x faster, a difference lost
    # in a fold system's linear algebra (< 1 % of the nose gear's fold locus)
    return {"hess_values": compile_chunked(syms, hess_expr, SECOND_DERIVATIVES_CHUNK, opt_level=SECOND_DERIVATIVES_OPT_LEVEL),
            "hess_j": h[:, 1], "hess_ik": h[:, 0] * n + h[:, 2]}
