"""Where description files are: the shipped ones and the name or path a user gives.

Apart from the reader (:mod:`._file`) so that listing models or finding a file imports no SymPy.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["DATA_DIR", "builtin_descriptions", "find_description"]

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
