"""Tables as text and files: branch tables, record tables (Markdown or CSV), special-point tables.

No Matplotlib here: the commands that print tables stay light.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["BRANCH_SUFFIXES", "RECORD_SUFFIXES", "write_branch_table"]

#: A branch is written as CSV or JSON (by suffix).
BRANCH_SUFFIXES = (".csv", ".json")
#: A table of records (one dict per row) is written as CSV or Markdown (by suffix).
RECORD_SUFFIXES = (".csv", ".md")


def write_branch_table(branch, path: str | Path) -> Path:
    """Write ``branch`` to ``path`` as JSON when its suffix is ``.json`` (any case), else as CSV; returns the path."""
    path = Path(path)
    (branch.to_json if path.suffix.lower() == ".json" else branch.to_csv)(path)
    return path
