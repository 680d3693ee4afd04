"""Parsing of the CLI's NAME=VALUE and NAME=LO:HI arguments into checked values."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING, TypedDict, TypeVar

from ..errors import InputError, finite_number

if TYPE_CHECKING:
    from ..dynamics import OdeHistory, SimulationResult
    from ..equations import Model

__all__ = ["assignments", "bounds", "names", "number", "renamed", "named_as", "integrator_options", "integrator", "Integrator",
           "check_count", "MAX_SCAN", "named_item", "branch_row", "at_values", "span"]

#: An option's value whichever its type (:func:`renamed`).
T = TypeVar("T")
class Integrator(TypedDict):
    """The integrator settings of a time simulation (:func:`integrator`), passed on as keywords."""

    method: str
    rtol: float
    atol: float


#: A click command function (:func:`integrator_options`).
F = TypeVar("F", bound=Callable[..., object])

#: Most values of a scan (``freefall --scan``: each repeats a bisection of runs) unless raised by its option.
MAX_SCAN = 50

#: The integrator defaults of simulate, sweep and freefall: 1e-6 relative or better on the time to lock and
#: the impact speed of the shipped gears (docs/reference.md, "Integrator and tolerances").
METHOD, RTOL, ATOL = "RK45", 1e-8, 1e-10


def number(text: str, field: str) -> float:
    """``text`` as a finite float, else InputError naming ``field``."""
    return finite_number(text, field)


def named_item(item: str, option: str, form: str) -> tuple[str, str]:
    """``"NAME=REST"`` -> ``("NAME", "REST")``, the one split of every ``NAME=...`` option (``--set``, ``--start``,
    ``--hold``, ``--bounds``, ``--dist``, ``--grid``, ``--ramp``, ``--at``, ...); :class:`InputError` naming
    ``option`` ("'ITEM' is not ``form``") when there is no ``=`` or no name."""
    name, sep, rest = item.partition("=")
    if not sep or not name.strip():
        raise InputError(option, f"'{item}' is not {form}")
    return name.strip(), rest


def assignments(items: Iterable[str], option: str) -> dict[str, float]:
    """``["k=127", "LU=0.4"]`` -> ``{"k": 127.0, "LU": 0.4}``; errors name the option and item."""
    out: dict[str, float] = {}
    for item in items:
        name, value = named_item(item, f"--{option}", "NAME=VALUE")
        out[name] = number(value.strip(), f"--{option} {name}")
    return out


def span(item: str, option: str, *, unbounded: bool = False) -> tuple[str, float, float]:
    """``"F=-100:100"`` -> ``("F", -100.0, 100.0)``: a range ``NAME=LO:HI`` (``--bounds``, ``--design``,
    ``--critical``); with ``unbounded`` an empty side is -inf or inf. :class:`InputError` naming ``option`` for
    another form, and naming ``option NAME`` for a side that is not a number or an empty or inverted range."""
    name, rng = named_item(item, option, "NAME=LO:HI")
    lo, colon, hi = rng.partition(":")
    if not colon:
        raise InputError(option, f"'{item}' is not NAME=LO:HI")
    low = -math.inf if unbounded and lo.strip() == "" else number(lo.strip(), f"{option} {name}")
    high = math.inf if unbounded and hi.strip() == "" else number(hi.strip(), f"{option} {name}")
    if not low < high:
        raise InputError(f"{option} {name}", f"empty or inverted interval {lo}:{hi}; need LO < HI")
    return name, low, high


def bounds(items: Iterable[str], option: str = "--bounds") -> dict[str, tuple[float, float]]:
    """``["F=-100:100"]`` -> ``{"F": (-100.0, 100.0)}``; an empty side means unbounded (:func:`span`)."""
    out: dict[str, tuple[float, float]] = {}
    for item in items:
        name, low, high = span(item, option, unbounded=True)
        out[name] = (low, high)
    return out


def at_values(items: Iterable[str], vary: str) -> tuple[float, ...]:
    """``--at P=V1,V2,...`` (repeatable): the values (SI units) of the continuation parameter ``vary`` at which
    rows or orbits are located exactly (``UZ``), in the order given; ``()`` when none. :class:`InputError` (field
    ``--at``) for another form, another parameter than ``vary`` or a value that is not a finite number."""
    out: list[float] = []
    for item in items:
        name, values = named_item(item, "--at", f"P=V1,V2,... (e.g. --at {vary}=0.1,0.2)")
        if not values.strip():
            raise InputError("--at", f"'{item}' is not P=V1,V2,... (e.g. --at {vary}=0.1,0.2)")
        if name != vary:
            raise InputError("--at", f"names '{name}'; the values are of the --vary parameter, {vary}")
        out += [number(v.strip(), f"--at {vary}") for v in values.split(",")]
    return tuple(out)


def branch_row(text: str, option: str = "--point", example: str = "ROW (e.g. branch.csv:LP1)") -> tuple[str, str]:
    """``"branch.csv:LP1"`` -> ``("branch.csv", "LP1")``: a row of a branch table (``--point``), split at its last
    colon; :class:`InputError` naming ``option`` ("'TEXT' is not BRANCH.csv:``example``") without a path or a row."""
    path, sep, row = text.rpartition(":")
    if not sep or not path or not row:
        raise InputError(option, f"'{text}' is not BRANCH.csv:{example}")
    return path, row


def check_count(count: int, option: str, limit: int, raise_option: str, what: str = "values") -> None:
    """InputError naming ``option`` when it gives more than ``limit`` ``what`` (each a run, or a series of runs:
    decided before any starts); ``raise_option`` raises the limit."""
    if count > limit:
        raise InputError(option, f"gives {count} {what}; at most {limit} unless raised with {raise_option} "
                                 "(each is a run of its own)")


def names(text: str | None, option: str) -> tuple[str, ...]:
    """Comma-separated names -> tuple (empty tuple for None)."""
    if text is None:
        return ()
    out = tuple(n.strip() for n in text.split(",") if n.strip())
    if not out:
        raise InputError(f"--{option}", "give comma-separated variable names, e.g. F,theta1")
    return out


def freed_parameters(system: Model, frees: Iterable[str], option: str = "--free") -> list[str]:
    """``frees`` checked: each a parameter of ``system`` (a state is always solved for, so freeing
    one would be silently ignored)."""
    out = list(frees)
    for n in out:
        if system.variable(n).kind != "parameter":
            valid = ", ".join(system.parameter_names)
            raise InputError(option, f"{n} is a state, which is always solved for; free a parameter: {valid}")
    return out


def renamed(value: T, old_value: T, option: str, old: str) -> tuple[T, str]:
    """``(value, the spelling given)`` of an option that also takes its old spelling ``old`` (a hidden alias kept
    for scripts): the one given, or ``value`` (its default) when neither; InputError when both are given."""
    given_old = old_value not in (None, (), False)
    if given_old and value not in (None, (), False):
        raise InputError(option, f"give {option} or its old spelling {old}, not both")
    return (old_value, old) if given_old else (value, option)


@contextmanager
def named_as(options: Mapping[str, str]) -> Iterator[None]:
    """Re-raise an :class:`InputError` of the library whose field is a key of ``options`` (``{"folder": "--dir"}``)
    as one naming the command-line option the value came from."""
    try:
        yield
    except InputError as exc:
        if exc.field not in options:
            raise
        raise InputError(options[exc.field], str(exc)[len(exc.field) + 2:]) from None


def integrator_options(f: F) -> F:
    """The integrator options of the time-simulation commands: ``--method``, ``--rtol``, ``--atol``."""
    import click

    from ..dynamics import METHODS

    opts = [click.option("--method", default=METHOD, show_default=True, metavar="|".join(METHODS),
                         help="Integrator method (SciPy's names; Radau, BDF or LSODA for a stiff mechanism)."),
            click.option("--rtol", default=RTOL, show_default=True, help="Integrator relative tolerance."),
            click.option("--atol", default=ATOL, show_default=True,
                         help="Integrator absolute tolerance (each state's unit: m, rad, m/s, rad/s).")]
    for o in reversed(opts):
        f = o(f)
    return f


def integrator(method: str, rtol: float, atol: float) -> Integrator:
    """``{"method", "rtol", "atol"}`` checked (:func:`mechcont.dynamics._simulate.check_integrator`), an error
    naming the option."""
    from ..dynamics import check_integrator

    with named_as({"method": "--method", "rtol": "--rtol", "atol": "--atol"}):
        check_integrator(method, rtol, atol)
    return {"method": method, "rtol": rtol, "atol": atol}


def check_integration(result: SimulationResult | OdeHistory, method: str, written: Iterable[str] = ()) -> None:
    """After a time simulation's outputs are written: where its integrator stopped early (the tolerance
    cannot be met there, or the forces blew up), a :class:`~mechcont.errors.ConvergenceError` (one line,
    exit status 2) saying when, why, what to change and which files hold the history up to there."""
    from ..errors import ConvergenceError

    if not result.integrator_failure:
        return
    files = list(written)
    kept = f"; the history up to there is in {', '.join(files)}" if files else ""
    if result.integrator_failure == "step budget":  # stiff: the detail names the element (dynamics._budget)
        raise ConvergenceError("--step-budget: " + result.detail.replace("(max_steps)", "(--step-budget)")
                               .replace("use method Radau", "use --method Radau").rstrip(".") + kept)
    raise ConvergenceError(f"--rtol/--atol: the integrator ({method}) could not go on at t = {result.t[-1]:.6g} s "
                           f"({result.integrator_failure.rstrip('.')}): loosen --rtol/--atol, or choose an implicit "
                           f"--method (Radau, BDF) for a stiff mechanism; check the loads where it stopped{kept}")
