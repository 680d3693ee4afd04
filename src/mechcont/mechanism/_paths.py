"""Where description files are: the shipped ones and the name or path a user gives.

Apart from the reader (:mod:`._file`) so that listing models or finding a file imports no SymPy.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

__all__ = ["DATA_DIR", "MAX_TEXT", "builtin_descriptions", "find_description", "read_description_bytes",
           "is_system_file"]

#: Longest description text read, characters (the largest shipped one has 6,000).
MAX_TEXT = 2**20

DATA_DIR = Path(__file__).resolve().parent.parent / "data"


def builtin_descriptions() -> list[str]:
    """Stems of the description files shipped in ``mechcont/data`` (e.g. ``"overcentre"``)."""
    return sorted(p.stem for p in DATA_DIR.glob("*.toml"))


def find_description(name_or_path: str | Path) -> Path | None:
    """The description file meant by ``name_or_path``: an existing ``.toml`` path, or the stem
    (with or without ``.toml``) of a shipped description; None when neither."""
    p = Path(name_or_path)
    if p.suffix == ".toml" and p.is_file():
        return p
    stem = p.name[:-5] if p.name.endswith(".toml") else p.name
    shipped = DATA_DIR / f"{stem}.toml"
    return shipped if str(p.parent) in (".", "") and shipped.is_file() else None


def read_description_bytes(path: Path) -> bytes:
    """The bytes of the description file ``path``: a regular file (a FIFO or a device would block or never
    end) of at most ``4 * MAX_TEXT`` bytes, else :class:`InputError`."""
    if not path.is_file():
        raise InputError(str(path), "is not a regular file")
    try:
        with open(path, "rb") as f:
            raw = f.read(4 * MAX_TEXT + 1)  # UTF-8: at most 4 bytes a character
    except OSError as exc:
        raise InputError(str(path), f"cannot read the file ({exc.__class__.__name__})") from None
    if len(raw) > 4 * MAX_TEXT:
        raise InputError(str(path), f"is larger than {4 * MAX_TEXT} bytes; a description takes at most {MAX_TEXT} "
                                    "characters")
    return raw


def is_system_file(name_or_path: str | Path) -> bool:
    """Whether ``name_or_path`` is a readable ``.toml`` file with a ``[system]`` table (an ODE system);
    False for anything else (a mechanism, a built-in name, an unreadable file: their own readers say why)."""
    import tomllib
    from collections.abc import Mapping

    path = find_description(name_or_path)
    if path is None:
        return False
    try:
        data = tomllib.loads(read_description_bytes(path).decode("utf-8"))
    except (InputError, UnicodeDecodeError, tomllib.TOMLDecodeError, RecursionError, MemoryError, ValueError):
        return False
    return isinstance(data.get("system"), Mapping)
