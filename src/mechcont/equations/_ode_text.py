"""An ODE model's equations as text or LaTeX (``mechcont equations`` on a ``[system]`` file)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:
    from ._model import Model

__all__ = ["ode_equations"]


def ode_equations(model: Model, latex: bool = False) -> str:
    """The ODE ``model``'s equations as text, ``du/dt = f`` (or ``0 = g``) per state, one a line; with
    ``latex`` a LaTeX ``align`` environment."""
    import sympy as sp

    facts = model.ode
    if facts is None:
        raise InputError("model", f"{model.name} is not an ODE system ([system] file)")
    if latex:
        def lhs(n: str) -> str:
            return "0" if facts.algebraic else f"\\frac{{d {sp.latex(sp.Symbol(n))}}}{{dt}}"

        rows = [f"{lhs(n)} &= {sp.latex(e)}" for n, e in zip(facts.states, model.equations)]
        return "\\begin{align}\n" + " \\\\\n".join(rows) + "\n\\end{align}"
    if facts.algebraic:
        return "\n".join(f"{n}: 0 = {sp.sstr(e)}" for n, e in zip(facts.states, model.equations))
    return "\n".join(f"d{n}/dt = {sp.sstr(e)}" for n, e in zip(facts.states, model.equations))
