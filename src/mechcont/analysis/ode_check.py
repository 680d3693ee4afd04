"""What mechcont made of an ODE file (``mechcont check`` and ``mechcont equations`` of a ``[system]`` file).

The report gives the states (initial values), the parameters, the rates (or residuals), the residual at
the initial state and, for an ODE, the eigenvalues of ``df/du`` there; then the equilibrium Newton
reaches from the initial state, with its stability (the number of eigenvalues with a positive real part).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..equations import Model, dynamics_of, ode_equations
from ..errors import ConvergenceError, InputError

__all__ = ["OdeReport", "ode_report", "ode_equations"]


@dataclass(frozen=True)
class OdeReport:
    """The check of an ODE model.

    ``x0``: the full vector at the initial state (SI); ``residual``: ``f`` (or ``g``) there;
    ``eigenvalues``: of ``df/du`` there (None for an algebraic system or a non-finite Jacobian);
    ``equilibrium``: the full vector Newton reached from ``x0`` (None when it did not);
    ``equilibrium_eigenvalues``: of ``df/du`` there (None as above); ``n_unstable``: their count
    with a positive real part (-1 when unknown); ``findings``: what is wrong (empty when all is well).
    """

    model: Model
    x0: np.ndarray
    residual: np.ndarray
    eigenvalues: np.ndarray | None
    equilibrium: np.ndarray | None
    equilibrium_eigenvalues: np.ndarray | None
    n_unstable: int
    findings: tuple[str, ...]
    why_not: str = ""

    def to_text(self) -> str:
        """The report as lines of text (values SI; units as the file gives them)."""
        m, facts = self.model, self.model.ode
        assert facts is not None
        kind = ("algebraic system 0 = g(u, p) (AUTO's IPS = 0)" if facts.algebraic
                else "ODE system du/dt = f(u, p) (AUTO's IPS = 1)")
        out = [f"{m.name}: {kind}, {len(facts.states)} state(s), {len(m.parameter_names)} parameter(s)"]
        if m.description:
            out.append(f"  {m.description}")
        out.append("states (initial values):")
        out += [f"  {n} = {self.x0[m.index(n)]:.10g}{_unit(m, n)}{_desc(m, n)}" for n in facts.states]
        out.append("parameters:" if m.parameter_names else "parameters: none")
        out += [f"  {n} = {self.x0[m.index(n)]:.10g}{_unit(m, n)}{_desc(m, n)}" for n in m.parameter_names]
        out.append("equations (= 0):" if facts.algebraic else "rates:")
        out += [f"  {line}" for line in ode_equations(m).splitlines()]
        what = "residual" if facts.algebraic else "rates"
        out.append(f"{what} at the initial state: " + ", ".join(f"{r:.6g}" for r in self.residual))
        if self.eigenvalues is not None:
            out.append(f"eigenvalues of df/du at the initial state: {_eigs(self.eigenvalues)}")
        if self.equilibrium is None:
            out.append(f"no equilibrium reached by Newton from the initial state ({self.why_not})")
        else:
            x = self.equilibrium
            out.append("equilibrium Newton reaches from the initial state: "
                       + ", ".join(f"{n} = {x[m.index(n)]:.10g}" for n in facts.states))
            if self.equilibrium_eigenvalues is not None:
                out.append(f"  eigenvalues of df/du there: {_eigs(self.equilibrium_eigenvalues)}")
                out.append("  stability: " + ("stable" if self.n_unstable == 0 else
                                               f"UNSTABLE ({self.n_unstable} eigenvalue(s) with positive real part)"))
        if self.findings:
            out.append("findings:")
            out += [f"  - {f}" for f in self.findings]
        return "\n".join(out)


def _unit(m: Model, n: str) -> str:
    u = m.variable(n).unit
    return f" {u}" if u else ""


def _desc(m: Model, n: str) -> str:
    d = m.variable(n).description
    return f"  ({d})" if d else ""


def _eigs(lam: np.ndarray) -> str:
    def one(z: complex) -> str:
        if z.imag == 0:
            return f"{z.real:.6g}"
        return f"{z.real:.6g} {'+' if z.imag > 0 else '-'} {abs(z.imag):.6g}i"

    return ", ".join(one(complex(z)) for z in lam)


def ode_report(model: Model) -> OdeReport:
    """Check the ODE ``model`` (``model.ode`` set) at its initial state (the file's values): the residual,
    the eigenvalues of ``df/du``, the equilibrium Newton reaches from there and its stability. Raises
    :class:`InputError` for a model that is not an ODE system."""
    from ..continuation import find_equilibrium, unstable_rates

    facts = model.ode
    if facts is None:
        raise InputError("model", f"{model.name} is not an ODE system ([system] file)")
    x0 = model.vector({})
    findings = []
    with np.errstate(all="ignore"):
        residual = model.residual(x0)
    if not np.all(np.isfinite(residual)):
        bad = [n for n, r in zip(model.equation_names, residual) if not math.isfinite(r)]
        findings.append(f"the {'residual' if facts.algebraic else 'rates'} {', '.join(bad)} are not finite at the "
                        "initial state")
    eigs = None if facts.algebraic else _eigenvalues(model, x0)
    equilibrium = eq_eigs = None
    n_unstable, why = -1, ""
    try:
        with np.errstate(all="ignore"):
            equilibrium = find_equilibrium(model, guess=x0)
    except (ConvergenceError, InputError) as exc:
        why = str(exc)
        findings.append("no equilibrium found from the initial state by Newton")
    if equilibrium is not None and not facts.algebraic:
        eq_eigs = _eigenvalues(model, equilibrium)
        if eq_eigs is not None:
            n_unstable = unstable_rates(model, equilibrium)
    return OdeReport(model, x0, residual, eigs, equilibrium, eq_eigs, n_unstable, tuple(findings), why)


def _eigenvalues(model: Model, x: np.ndarray) -> np.ndarray | None:
    """The eigenvalues of ``df/du`` at ``x``, or None where the Jacobian is not finite."""
    with np.errstate(all="ignore"):
        lin = dynamics_of(model).linearise(x)
    return lin.eigenvalues() if np.all(np.isfinite(lin.A)) else None
