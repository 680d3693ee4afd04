"""Exceptions raised by mechcont.

Every error message is one line that names the offending field and says what would be
valid, so the CLI can print it as is and exit with status 2.
"""

from __future__ import annotations

import math

__all__ = ["MechcontError", "InputError", "ConvergenceError", "finite_number", "one_line"]


class MechcontError(Exception):
    """Base class of all mechcont errors."""


class InputError(MechcontError, ValueError):
    """Bad user input: an unknown name, an impossible value, inconsistent choices.

    Parameters
    ----------
    field:
        The name of the offending item (variable, option, file key).
    message:
        What is wrong and what would be valid.
    """

    def __init__(self, field: str, message: str):
        self.field = one_line(str(field))
        super().__init__(f"{self.field}: {one_line(str(message))}")


def one_line(text: str) -> str:
    """``text`` with line breaks and other control characters escaped (``\\n``), so that an
    error naming a user's odd key or value still prints as one line."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


class ConvergenceError(MechcontError):
    """A solve that did not converge; ``partial`` holds what was computed up to there."""

    def __init__(self, message: str, partial: object = None):
        self.partial = partial
        super().__init__(message)


def finite_number(text: object, field: str) -> float:
    """``text`` (a string or number from the command line or a file) as a finite float, else
    :class:`InputError` naming ``field``; ``True``/``False`` are not numbers."""
    if isinstance(text, bool):
        raise InputError(field, f"'{text}' is not a number (SI units, radians)")
    try:
        v = float(text)  # type: ignore[arg-type]  # anything float() takes; the rest is refused below
    except (TypeError, ValueError):
        raise InputError(field, f"'{text}' is not a number (SI units, radians)") from None
    if not math.isfinite(v):
        raise InputError(field, f"'{text}' is not a finite number")
    return v
