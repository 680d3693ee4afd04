"""A labelled point of a branch (:class:`SpecialPoint`): a fold, a branch point, a cusp, an end or an event.

What a stop adds to its points is typed: the stop(s) switching at ``SC``/``SR``/``NSF``
(:attr:`SpecialPoint.stop`), and at a non-smooth fold a :class:`NonSmoothFold` with, when the
mechanism jumps there and comes to rest, its :class:`Landing`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from .._status import Status

if TYPE_CHECKING:
    from ..equations import EquationSystem
    from ._sensitivity import Sensitivity

__all__ = ["SpecialPoint", "NonSmoothFold", "Landing"]

#: How many values a :class:`SpecialPoint`'s repr shows.
_REPR_VALUES = 60


@dataclass(frozen=True)
class Landing:
    """Where the mechanism comes to rest after jumping at a non-smooth fold.

    ``x`` the full variable vector of the equilibrium it lands on (SI units, ordered like the
    branch's names), at the fold's value of the continuation parameter, further along the branch;
    ``contact`` the stops in contact there; ``stable`` whether it is stable there (None for a model
    without mechanics).
    """

    x: np.ndarray
    contact: tuple[str, ...]
    stable: bool | None


@dataclass(frozen=True)
class NonSmoothFold:
    """What an ``NSF`` point (a contact switch where no contact set continues the branch) carries.

    ``stop`` the stop(s) switching there (comma-joined); ``vary`` the continuation parameter and
    ``value`` its value there (SI); ``sign`` the sense (+1/-1) ``vary`` was pushed in arriving;
    ``jump`` True when a stable mechanism reaches it as ``vary`` is pushed in ``sign``: the piece the
    run arrived on is stable, or the piece it leaves on is (both pieces end there and exist on the same
    side of ``value``, so which one the run walked first does not change the physics); ``behind`` True
    when the stable piece is the one the run leaves on, so the mechanism jumps back along the run (its
    landing is searched before the fold's row, not after it); ``landing`` where it lands (None when
    it does not jump, or no equilibrium was found along the branch at ``value``); ``sides`` the number of
    unstable directions at the fold on each of the two pieces that meet there (their contact sets), fewest
    first, whichever the run walked first: ``(0, 1)`` a stable piece meets an unstable one (``jump``), ``(1, 2)``
    two unstable ones; one number when only one piece was found, ``()`` when not computed.
    """

    stop: str
    vary: str
    value: float
    sign: int
    jump: bool
    landing: Landing | None = None
    behind: bool = False
    sides: tuple[int, ...] = ()

    def fields(self) -> dict[str, Any]:
        """The fold as the flat keys of before (:attr:`SpecialPoint.info`, the JSON): ``{vary: value}``,
        ``sign``, ``jump``, ``landing`` (its ``x``), ``landing_contact``, ``landing_stable``."""
        land = self.landing
        return {self.vary: self.value, "sign": self.sign, "jump": self.jump,
                "landing": None if land is None else land.x, "landing_contact": None if land is None else land.contact,
                "landing_stable": None if land is None else land.stable}


@dataclass(init=False, frozen=True)
class SpecialPoint:
    """A labelled point of a branch (AUTO's vocabulary).

    Attributes
    ----------
    label:
        ``"LP"`` limit point (fold), ``"BP"`` branch point, ``"CP"`` cusp, ``"EP"`` end
        point, ``"HB"`` Hopf point (its :class:`~._hopf_point.HopfPoint` in ``extra["hopf"]``), ``"BT"``
        and ``"GH"`` on Hopf curves, ``"UZ"`` a user point, or a user event name.
    index:
        Row of the point in the branch.
    x:
        Full variable vector at the point.
    names:
        Variable names, ordered like ``x``.
    tangent:
        Unit tangent of the branch at the point in the problem's scaled unknowns (when known).
    status:
        :attr:`Status.LOCATED <mechcont._status.Status.LOCATED>` (solved to the tolerances: a
        fold polished on the augmented system, an event's zero found by root finding) or
        ``APPROXIMATE`` (detected by a sign change but not located; :attr:`reason` says why).
    reason:
        Why the point is approximate, or why a branch ended there (``""`` when none).
    residual, singular_value:
        The precision of a located fold (None elsewhere): the largest equation residual
        relative to its terms, and the smallest singular value of the equilibrated state
        Jacobian over the norm of the whole equilibrated Jacobian.
    vary, unknowns:
        The lens the point was found with: the continuation parameter and the names solved
        for (None for a point read from a table).
    null_vector:
        The null vector over :attr:`unknowns`' states at a fold (None elsewhere).
    stop:
        The stop(s) whose contact switches at an ``SC``, ``SR`` or ``NSF`` point (comma-joined; None
        elsewhere).
    nonsmooth:
        At an ``NSF`` point its :class:`NonSmoothFold` (None elsewhere).
    extra:
        What an analysis adds otherwise (a bound's name, dropped rows, a Hopf point's data...).
    info:
        All of the above as one read-only dict (the keys of before: ``"status"``,
        ``"null_vector"``, ``"residual"``, ...); pass ``info=`` to the constructor to fill
        the typed fields from such a dict (its other keys go to :attr:`extra`).
    """

    label: str
    index: int
    x: np.ndarray
    names: tuple[str, ...]
    tangent: np.ndarray | None
    status: Status
    reason: str
    residual: float | None
    singular_value: float | None
    vary: str | None
    unknowns: tuple[str, ...] | None
    null_vector: np.ndarray | None
    stop: str | None
    nonsmooth: NonSmoothFold | None
    extra: dict[str, Any]

    def __init__(self, label: str, index: int, x: np.ndarray, names: tuple[str, ...], tangent: np.ndarray | None = None,
                 info: Mapping[str, Any] | None = None, *, status: Status | str | None = None, reason: str | None = None,
                 residual: float | None = None, singular_value: float | None = None, vary: str | None = None,
                 unknowns: Sequence[str] | None = None, null_vector: np.ndarray | None = None,
                 stop: str | None = None, nonsmooth: NonSmoothFold | None = None,
                 extra: Mapping[str, Any] | None = None) -> None:
        rest = dict(info or {})
        typed = {k: rest.pop(k, None) for k in _TYPED}
        if nonsmooth is not None:  # its flat keys (an NSF point's info passed back in) are the record's
            for k in nonsmooth.fields():
                rest.pop(k, None)
        lens = _first(unknowns, typed["unknowns"])
        fields = {"label": label, "index": index, "x": x, "names": names, "tangent": tangent,
                  "status": Status.of(status or typed["status"] or Status.LOCATED),
                  "reason": str(reason if reason is not None else typed["reason"] or ""),
                  "residual": _first(residual, typed["residual"]),
                  "singular_value": _first(singular_value, typed["singular_value"]),
                  "vary": _first(vary, typed["vary"]), "unknowns": None if lens is None else tuple(lens),
                  "null_vector": _first(null_vector, typed["null_vector"]),
                  "stop": _first(stop, None if nonsmooth is None else nonsmooth.stop, typed["stop"]),
                  "nonsmooth": nonsmooth, "extra": {**rest, **(extra or {})}}
        for k, v in fields.items():  # frozen: the one place its fields are set
            object.__setattr__(self, k, v)

    @property
    def info(self) -> Mapping[str, Any]:
        """The point's data as a read-only dict (the compatibility view of the typed fields and
        :attr:`extra`): ``"status"`` always, the other typed fields when set, then :attr:`extra`,
        ``"stop"`` and a non-smooth fold's keys (:meth:`NonSmoothFold.fields`)."""
        typed = {"status": self.status, "reason": self.reason or None, "null_vector": self.null_vector,
                 "residual": self.residual, "singular_value": self.singular_value, "unknowns": self.unknowns,
                 "vary": self.vary}
        stop = {} if self.stop is None else {"stop": self.stop}
        fold = {} if self.nonsmooth is None else self.nonsmooth.fields()
        return MappingProxyType({**{k: v for k, v in typed.items() if v is not None}, **self.extra, **stop, **fold})

    @property
    def values(self) -> dict[str, float]:
        """``{name: value}`` at the point."""
        return {n: float(v) for n, v in zip(self.names, self.x)}

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    @property
    def located(self) -> bool:
        """True when :attr:`status` is ``LOCATED``."""
        return self.status is Status.LOCATED

    @property
    def tag(self) -> str:
        """The label as written in tables: ``"LP"``, or ``"LP?"`` when only approximate."""
        return self.label if self.located else self.label + "?"

    def __repr__(self) -> str:
        """``SpecialPoint(CP at row 40, located: LU=1.5, F=9.81, ...)``: its values to 10 digits (SI units),
        the first :data:`_REPR_VALUES` of them (a large model's point would fill the screen)."""
        shown = ", ".join(f"{n}={float(v):.10g}" for n, v in zip(self.names[:_REPR_VALUES], self.x))
        more = len(self.names) - _REPR_VALUES
        rest = f", ... ({more} more; .values has all)" if more > 0 else ""
        return f"SpecialPoint({self.tag} at row {self.index}, {self.status}: {shown}{rest})"

    def sensitivity(self, system: EquationSystem, params: Iterable[str], *, of: str | None = None,
                    keep: str | None = None, vary: str | None = None,
                    values: Mapping[str, float] | None = None) -> Sensitivity:
        """Exact derivatives of this point's quantity with respect to ``params`` (SI units per SI unit).

        At a fold (``LP``) the fold load (the continuation parameter's value there); elsewhere
        the continuation parameter at the state ``keep`` held at its value here; or ``of``, an
        unknown of the branch, with the continuation parameter held. ``system`` is the model
        of the branch; ``vary`` is needed only for a point read from a table; ``values``
        (``{name: value}``, SI) moves the point to those held values first (followed there,
        :func:`~._move.move_point`). Returns a :class:`~mechcont.analysis.sensitivity.Sensitivity` (see
        :func:`~mechcont.analysis.sensitivity.point_sensitivity`).
        """
        from ._sensitivity import point_sensitivity

        return point_sensitivity(system, self, params, vary=vary, of=of, keep=keep, values=values)


#: The keys of an ``info`` dict that are typed fields of a :class:`SpecialPoint`.
_TYPED = ("status", "reason", "residual", "singular_value", "vary", "unknowns", "null_vector", "stop")


_T = TypeVar("_T")


def _first(*values: _T | None) -> _T | None:
    """The first of ``values`` that is not None (None when all are)."""
    return next((v for v in values if v is not None), None)
