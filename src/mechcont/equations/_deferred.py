"""Symbolic parts of a pickled model, kept apart so that loading it does not import SymPy.

A model loaded from the disk cache is used through its compiled code; its SymPy
expressions (equations, limits, potential energy, the mechanism's constraints) are needed
only to print, differentiate again or build another model. Importing SymPy costs about
0.5 s, as much as a whole continuation run, so the pickled state of
:class:`~mechcont.equations.EquationSystem`, :class:`~mechcont.equations.Limit` and
:class:`~mechcont.equations.MechanicalModel` holds every attribute whose pickle needs SymPy
as one inner pickle (bytes). It is unpickled, importing SymPy, on the first access to any of
those attributes (the classes' ``__getattr__``, reached only for attributes missing from the
instance). An attribute set on the instance since (a copy's own value) is kept.
"""

from __future__ import annotations

import contextlib
import io
import pickle
from collections.abc import Iterator
from contextvars import ContextVar
from typing import IO, Any

__all__ = ["needs_heavy", "pack", "materialize", "defaults_off_the_class", "Apart", "DEFERRED", "HEAVY",
           "compiling_later", "later"]

#: The instance attribute that holds the inner pickle until it is needed.
DEFERRED = "_deferred_symbolic"
#: Modules whose import a loaded model should not need before its symbolic parts are used.
HEAVY = ("sympy",)


class _Recorder(pickle.Pickler):
    """A pickler that notes the modules of the classes and functions it pickles."""

    def __init__(self, file: IO[bytes]) -> None:
        super().__init__(file, protocol=pickle.HIGHEST_PROTOCOL)
        self.modules: set[str] = set()

    def reducer_override(self, obj: object) -> Any:
        module = getattr(obj, "__module__", None) if isinstance(obj, type) or callable(obj) else None
        self.modules.add(module if isinstance(module, str) else type(obj).__module__)
        return NotImplemented


def needs_heavy(value: object) -> bool:
    """True when unpickling ``value`` would import one of :data:`HEAVY` (raises if it does not pickle)."""
    rec = _Recorder(io.BytesIO())
    rec.dump(value)
    return any(m == h or m.startswith(h + ".") for m in rec.modules for h in HEAVY)


def pack(values: dict[str, object]) -> bytes:
    """``values`` (attribute name -> value) as the inner pickle :func:`materialize` reads."""
    return pickle.dumps(values, protocol=pickle.HIGHEST_PROTOCOL)


def defaults_off_the_class(cls: type) -> None:
    """Remove the class attributes a dataclass makes of its fields' default values.

    A field kept apart in the inner pickle is missing from the instance; with a default on the
    class, reading it would give that default instead of reaching ``__getattr__``. Instances
    made by ``__init__`` set every field, so removing them changes nothing else.
    """
    from dataclasses import MISSING, fields

    for f in fields(cls):
        if f.default is not MISSING and f.name in cls.__dict__:
            delattr(cls, f.name)


def materialize(obj: object, name: str) -> Any:
    """The attribute ``name`` of ``obj`` from its inner pickle (unpickled once, into ``obj.__dict__``).

    Raises :class:`AttributeError` when ``obj`` has no inner pickle or it does not hold ``name``.
    """
    d = obj.__dict__
    blob = d.pop(DEFERRED, None)
    if blob is not None:
        for k, v in pickle.loads(blob).items():
            d.setdefault(k, v)  # a value set on this instance since wins
    try:
        return d[name]
    except KeyError:
        raise AttributeError(f"{type(obj).__name__!r} object has no attribute {name!r}") from None


class Apart:
    """Base of a class whose attributes named in ``_APART`` are pickled apart (see the module docstring)."""

    _APART: tuple[str, ...] = ()

    def __getstate__(self) -> dict[str, object]:
        state = dict(self.__dict__)
        apart = {k: state.pop(k) for k in self._APART if k in state}
        if apart:
            state[DEFERRED] = pack(apart)
        return state

    def __setstate__(self, state: dict[str, object]) -> None:
        self.__dict__.update(state)

    def __getattr__(self, name: str) -> Any:
        # reached only for attributes missing from the instance: those still in the inner pickle
        if name.startswith("__"):
            raise AttributeError(name)
        return materialize(self, name)


_LATER: ContextVar[bool] = ContextVar("mechcont_compile_later", default=False)


@contextlib.contextmanager
def later() -> Iterator[None]:
    """While active, a model pickled for the disk cache leaves the parts it has not compiled yet (second
    derivatives, the mechanics' groups) to be compiled on first use, keeping their entries' keys
    (see :meth:`~mechcont.equations.EquationSystem.compiled_state`); any other pickle (a model sent
    to another process) holds every part compiled."""
    token = _LATER.set(True)
    try:
        yield
    finally:
        _LATER.reset(token)


def compiling_later() -> bool:
    """True inside :func:`later`."""
    return _LATER.get()
