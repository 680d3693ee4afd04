"""A study's folder: its spec, one Parquet part per finished chunk, and the combined results.

::

    OUT/study.json               the spec (what is computed; a resumed study must match it)
    OUT/parts/chunk-000012.parquet   one per finished chunk, each written atomically
    OUT/results.parquet          all samples in order, written when every chunk is done

A part is moved into place only once complete (:func:`mechcont._io.atomic_write`), so a
study killed at any moment (even SIGKILL) leaves finished parts whole and no part
half-written; ``--resume`` reads which chunks have a part and computes only the others.
Units and meanings of the columns are in the Parquet schema's metadata (``units``,
``meaning``) and so are the spec and, for a grid, its shape.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..._io import atomic_write
from ...errors import InputError
from ._kernels import COLUMNS
from ._spec import StudySpec

__all__ = ["StudyStore", "to_arrow"]

_PART = "chunk-{:06d}.parquet"


def to_arrow(columns: dict, spec: StudySpec, units: dict[str, str]):
    """A :class:`pyarrow.Table` of one chunk's ``columns`` with units and meanings in its metadata."""
    import pyarrow as pa

    arrays, fields = [], []
    for name, col in columns.items():
        col = np.asarray(col)
        if col.dtype == object:
            values = list(col)
            kind = pa.bool_() if name == "stable" else pa.string()
            arr = pa.array(values, type=kind)
        else:
            arr = pa.array(col)
        meta = {"unit": units.get(name, COLUMNS.get(name, ("", ""))[0]), "meaning": COLUMNS.get(name, ("", ""))[1]}
        arrays.append(arr)
        fields.append(pa.field(name, arr.type, metadata=meta))
    meta = {"mechcont.study": json.dumps(spec.to_mapping())}  # key order kept: the parameters' order matters
    if spec.grid_shape:
        meta["mechcont.grid_shape"] = json.dumps(list(spec.grid_shape))
    return pa.Table.from_arrays(arrays, schema=pa.schema(fields, metadata=meta))


class StudyStore:
    """The folder of one study (see the module docstring).

    Parameters
    ----------
    folder:
        Where the study lives (created if missing).
    spec:
        The study.
    resume:
        Continue a study already in ``folder`` (it must have the same spec). Without it a
        folder that already holds a study is refused, so nothing is overwritten by mistake.
    """

    def __init__(self, folder: str | Path, spec: StudySpec, *, resume: bool = False):
        self.folder = Path(folder)
        self.spec = spec
        self.parts = self.folder / "parts"
        self.spec_file = self.folder / "study.json"
        self.results = self.folder / "results.parquet"
        if self.folder.exists() and not self.folder.is_dir():
            raise InputError("--out", f"'{self.folder}' is a file; give a folder for the study")
        if self.spec_file.exists():
            if not resume:
                raise InputError("--out", f"'{self.folder}' already holds a study; add --resume to continue it, or "
                                          "choose another folder")
            try:
                old = json.loads(self.spec_file.read_text(encoding="utf-8"))
            except (OSError, ValueError) as exc:
                raise InputError("--resume", f"cannot read {self.spec_file}: {exc}") from None
            new = json.loads(json.dumps(spec.to_mapping()))
            if json.dumps(old) != json.dumps(new):  # order-sensitive: the parameters' order fixes the samples
                diff = sorted(k for k in set(old) | set(new) if json.dumps(old.get(k)) != json.dumps(new.get(k)))
                raise InputError("--resume", f"the study in '{self.folder}' was made with other settings "
                                             f"({', '.join(diff)} differ: {old.get(diff[0])!r} there, "
                                             f"{new.get(diff[0])!r} now); resume it with the same settings")

    def open(self) -> set[int]:
        """Create the folder and ``study.json`` if needed; the indices of the chunks already done."""
        self.parts.mkdir(parents=True, exist_ok=True)
        if not self.spec_file.exists():
            text = json.dumps(self.spec.to_mapping(), indent=2) + "\n"
            atomic_write(self.spec_file, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
        for stale in self.parts.glob(".chunk-*"):  # temporaries of a killed run (never complete parts)
            stale.unlink(missing_ok=True)
        return self.done()

    def done(self) -> set[int]:
        """Indices of the chunks that have a part on disk."""
        out = set()
        for p in self.parts.glob("chunk-*.parquet"):
            try:
                k = int(p.stem.split("-")[1])
            except (IndexError, ValueError):
                continue
            if 0 <= k < self.spec.n_chunks:
                out.add(k)
        return out

    def write(self, k: int, columns: dict, units: dict[str, str]) -> Path:
        """Write chunk ``k``'s part atomically."""
        import pyarrow.parquet as pq

        table = to_arrow(columns, self.spec, units)
        return atomic_write(self.parts / _PART.format(k), lambda tmp: pq.write_table(table, tmp))

    def combine(self) -> Path:
        """Write ``results.parquet`` (every part, in sample order) atomically; all chunks must be done."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        missing = sorted(set(range(self.spec.n_chunks)) - self.done())
        if missing:
            raise InputError("--out", f"chunks {missing[:5]} are not done yet; resume the study")
        tables = [pq.read_table(self.parts / _PART.format(k)) for k in range(self.spec.n_chunks)]
        table = pa.concat_tables(tables)
        return atomic_write(self.results, lambda tmp: pq.write_table(table, tmp))
