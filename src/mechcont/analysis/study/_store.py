"""A study's folder: its spec, one Parquet part per finished chunk, and the combined results.

::

    OUT/study.json               the spec (what is computed; a resumed study must match it)
    OUT/parts/chunk-000012.parquet   one per finished chunk, each written atomically
    OUT/results.parquet          all samples in order, written when every chunk is done

A part is moved into place only once complete (:func:`mechcont._io.atomic_write`), so a
study killed at any moment (even SIGKILL) leaves finished parts whole and no part
half-written; ``--resume`` reads which chunks have a part and computes only the others.
Units and meanings of the columns are in the Parquet schema's metadata (``units``,
``meaning``) and so are the spec, its settings hash (``mechcont.study_hash``) and, for a
grid, its shape. On resume every part is verified before it is kept: its settings hash, its
columns and its sample ids must be this study's and this chunk's; a part that fails (another
study's, truncated, not Parquet) is recomputed, and the caller is told why.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..._io import atomic_write
from ...errors import InputError
from ._kernels import COLUMNS
from ._spec import StudySpec

if TYPE_CHECKING:
    import pyarrow as pa

__all__ = ["StudyStore", "to_arrow", "settings_hash"]

_PART = "chunk-{:06d}.parquet"
_HASH_KEY = "mechcont.study_hash"


def settings_hash(spec: StudySpec) -> str:
    """SHA-256 of the spec's settings (order-sensitive: the parameters' order fixes the samples)."""
    return hashlib.sha256(json.dumps(spec.to_mapping()).encode("utf-8")).hexdigest()


def to_arrow(columns: dict, spec: StudySpec, units: dict[str, str]) -> pa.Table:
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
    meta = {"mechcont.study": json.dumps(spec.to_mapping()),  # key order kept: the parameters' order matters
            _HASH_KEY: settings_hash(spec)}
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
            raise InputError("folder", f"'{self.folder}' is a file; give a folder for the study")
        if self.spec_file.exists():
            if not resume:
                raise InputError("folder", f"'{self.folder}' already holds a study; add --resume to continue it, or "
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
        #: chunk -> why its part on disk is not this study's (recomputed; removed by :meth:`open`)
        self.rejected: dict[int, str] = {}

    def verify(self, columns: list[str]) -> dict[int, str]:
        """Check every part on disk against this study: settings hash, ``columns`` and sample ids.

        Returns (and keeps in :attr:`rejected`) ``{chunk: why}`` for the parts that fail; those
        chunks are not :meth:`done` and :meth:`open` removes their parts. A folder where a part
        should be is an :class:`InputError` (nothing of the user's is deleted).
        """
        self.rejected = {}
        for k in sorted(self._on_disk()):
            why = self._check_part(k, columns)
            if why:
                self.rejected[k] = why
        return dict(self.rejected)

    def _check_part(self, k: int, columns: list[str]) -> str:
        import pyarrow.parquet as pq

        path = self.parts / _PART.format(k)
        if path.is_dir():
            raise InputError("--resume", f"'{path}' is a folder where a part of the study should be; remove it")
        try:
            f = pq.ParquetFile(path)
            schema = f.schema_arrow
            meta = schema.metadata or {}
            if meta.get(_HASH_KEY.encode()) != settings_hash(self.spec).encode():
                return "made with other settings (or by an older mechcont)"
            if schema.names != columns:
                return "has other columns than this study's"
            ids = f.read(columns=["sample"]).column("sample").to_numpy()
        except (OSError, ValueError, KeyError) as exc:  # pyarrow's ArrowInvalid/ArrowIOError are among these
            return f"cannot be read ({type(exc).__name__})"
        start, stop = self.spec.chunk_rows(k)
        if not np.array_equal(ids, np.arange(start, stop)):
            return f"does not hold samples {start}..{stop - 1}"
        return ""

    def open(self) -> set[int]:
        """Create the folder and ``study.json`` if needed; the indices of the chunks already done."""
        self.parts.mkdir(parents=True, exist_ok=True)
        if not self.spec_file.exists():
            text = json.dumps(self.spec.to_mapping(), indent=2) + "\n"
            atomic_write(self.spec_file, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
        for stale in self.parts.glob(".chunk-*"):  # temporaries of a killed run (never complete parts)
            stale.unlink(missing_ok=True)
        for k in self.rejected:
            (self.parts / _PART.format(k)).unlink(missing_ok=True)
        self.rejected = {}
        return self.done()

    def done(self) -> set[int]:
        """Indices of the chunks that have a part on disk (and that :meth:`verify` did not reject)."""
        return self._on_disk() - set(self.rejected)

    def _on_disk(self) -> set[int]:
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
            raise InputError("folder", f"chunks {missing[:5]} are not done yet; resume the study")
        tables = [pq.read_table(self.parts / _PART.format(k)) for k in range(self.spec.n_chunks)]
        table = pa.concat_tables(tables)
        return atomic_write(self.results, lambda tmp: pq.write_table(table, tmp))
