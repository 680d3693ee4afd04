"""What a study computes: the model, the sampled parameters and their distributions, the analyses.

A :class:`StudySpec` is plain data (it round-trips through :meth:`StudySpec.to_mapping` /
:meth:`StudySpec.from_mapping`, the form of ``study.json`` and of a TOML study file), and
the samples are a pure function of it: the same spec gives the same samples, row for row,
on any machine. That is what lets ``--resume`` recompute nothing: chunk ``k`` always holds
the same samples.

(About 450 lines: :class:`StudySpec` validates every field of a study file and round-trips it, in one
place, so that a spec read from ``study.json`` is checked exactly as one given on the command line.)

Distributions are parsed from a short whitelist (numbers only, never evaluated):

* ``uniform:LO:HI``
* ``normal:MEAN:SD``
* ``truncnormal:MEAN:SD:LO:HI`` (a tolerance: normal, cut at LO and HI)

and grid axes as ``LO:HI:N`` (N evenly spaced values, both ends included). Every sampler
draws uniform numbers in [0, 1) (Monte Carlo: NumPy's PCG64 from the seed; Latin hypercube:
:class:`scipy.stats.qmc.LatinHypercube` from the seed) and maps them through each
distribution's inverse CDF.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import InputError, finite_number

__all__ = ["Distribution", "GridAxis", "StudySpec", "ANALYSES", "SAMPLINGS", "parse_distribution", "parse_axis"]

#: Most samples of a study (a grid's points too): their values alone are then 80 MB per parameter.
MAX_SAMPLES = 10_000_000
#: Sampling schemes: a full grid, a Latin hypercube, plain Monte Carlo.
SAMPLINGS = ("grid", "lhs", "mc")
#: Analyses of each sample (see :mod:`mechcont.analysis.study._kernels`).
ANALYSES = ("downlock", "unlock", "branch", "freefall")
#: Samples per chunk when not given: a chunk should take >= 0.1 s (the batched downlock
#: solves ~15,000 nose-gear samples per second; the unlock folds cost one release run per chunk and
#: a batched fold polish, or a release run per sample where the batch does not apply).
DEFAULT_CHUNK = {"downlock": 1000, "unlock": 100, "branch": 10, "freefall": 4}
#: Longest simulated time (s) a freefall sample may ask for (as ``mechcont simulate``).
MAX_UNTIL = 3600.0
#: Fields of each distribution, in the order of the ``KIND:A:B...`` form.
_FIELDS = {"uniform": ("low", "high"), "normal": ("mean", "sd"), "truncnormal": ("mean", "sd", "low", "high")}


@dataclass(frozen=True)
class Distribution:
    """A parameter's distribution: ``kind`` (``uniform``, ``normal``, ``truncnormal``) and its numbers (SI).

    ``uniform``: ``low``, ``high``; ``normal``: ``mean``, ``sd``; ``truncnormal``: ``mean``,
    ``sd``, ``low``, ``high`` (the normal distribution cut at ``low`` and ``high``).
    """

    kind: str
    args: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.kind not in _FIELDS:
            raise InputError("distribution", f"unknown distribution '{self.kind}'; valid: {', '.join(_FIELDS)}")
        names = _FIELDS[self.kind]
        if len(self.args) != len(names):
            raise InputError(self.kind, f"needs {len(names)} numbers ({', '.join(names)}), got {len(self.args)}")
        p = dict(zip(names, self.args))
        if "sd" in p and not p["sd"] > 0:
            raise InputError(f"{self.kind} sd", f"must be positive, got {p['sd']:g}")
        if "low" in p and not p["low"] < p["high"]:
            raise InputError(f"{self.kind} low:high", f"empty or inverted interval {p['low']:g}:{p['high']:g}")

    @property
    def fields(self) -> dict[str, float]:
        """``{field: value}``, e.g. ``{"mean": 1.3, "sd": 0.005}``."""
        return dict(zip(_FIELDS[self.kind], self.args))

    def ppf(self, q: np.ndarray) -> np.ndarray:
        """Inverse CDF at the probabilities ``q`` (in [0, 1)): the sampled values (SI)."""
        from scipy import stats

        p = self.fields
        q = np.asarray(q, dtype=float)
        if self.kind == "uniform":
            return p["low"] + q * (p["high"] - p["low"])
        if self.kind == "normal":
            return stats.norm.ppf(q, loc=p["mean"], scale=p["sd"])
        a, b = (p["low"] - p["mean"]) / p["sd"], (p["high"] - p["mean"]) / p["sd"]
        return stats.truncnorm.ppf(q, a, b, loc=p["mean"], scale=p["sd"])

    @property
    def centre(self) -> float:
        """The nominal value: the mean, or the middle of a uniform interval."""
        p = self.fields
        return p["mean"] if "mean" in p else 0.5 * (p["low"] + p["high"])

    def text(self) -> str:
        """The ``KIND:A:B`` form (parses back to an equal distribution)."""
        return ":".join([self.kind, *(repr(a) for a in self.args)])


@dataclass(frozen=True)
class GridAxis:
    """``n`` evenly spaced values from ``low`` to ``high`` (both included; SI)."""

    low: float
    high: float
    n: int

    def __post_init__(self) -> None:
        if not 1 <= self.n <= 100_000:
            raise InputError("grid", f"the number of values must be 1..100000, got {self.n}")
        if self.n > 1 and not self.low < self.high:
            raise InputError("grid", f"empty or inverted interval {self.low:g}:{self.high:g}; need LO < HI")

    def values(self) -> np.ndarray:
        """The axis values (SI)."""
        return np.linspace(self.low, self.high, self.n)

    def text(self) -> str:
        """The ``LO:HI:N`` form."""
        return f"{self.low!r}:{self.high!r}:{self.n}"


def parse_distribution(text: str, name: str) -> Distribution:
    """``"normal:1.3:0.005"`` -> :class:`Distribution`; :class:`InputError` naming ``name`` otherwise."""
    kind, *nums = str(text).split(":")
    kind = kind.strip().lower()
    if kind not in _FIELDS:
        raise InputError(name, f"unknown distribution '{kind}'; valid: uniform:LO:HI, normal:MEAN:SD, "
                               "truncnormal:MEAN:SD:LO:HI")
    if len(nums) != len(_FIELDS[kind]):
        raise InputError(name, f"{kind} needs {len(_FIELDS[kind])} numbers, {kind}:{':'.join(_FIELDS[kind]).upper()}; "
                               f"got '{text}'")
    try:
        return Distribution(kind, tuple(finite_number(v.strip(), f"{name} {f}") for v, f in zip(nums, _FIELDS[kind])))
    except InputError as exc:
        raise InputError(name, str(exc)) from None


def parse_axis(text: str, name: str) -> GridAxis:
    """``"1.25:1.35:11"`` -> :class:`GridAxis`; :class:`InputError` naming ``name`` otherwise."""
    parts = str(text).split(":")
    if len(parts) != 3:
        raise InputError(name, f"'{text}' is not LO:HI:N")
    lo, hi = (finite_number(p.strip(), name) for p in parts[:2])
    try:
        n = int(parts[2].strip())
    except ValueError:
        raise InputError(name, f"'{parts[2]}' is not a whole number of values") from None
    try:
        return GridAxis(lo, hi, n)
    except InputError as exc:
        raise InputError(name, str(exc).partition(": ")[2]) from None


def _file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@dataclass(frozen=True)
class StudySpec:
    """A study: which model, which parameters sampled how, which analyses, in which chunks.

    Parameters
    ----------
    model:
        A built-in model name or a description file (as :func:`~mechcont.models.load_model`).
    sampling:
        ``"grid"``, ``"lhs"`` (Latin hypercube) or ``"mc"`` (Monte Carlo).
    parameters:
        ``((name, GridAxis), ...)`` for a grid (the last name varies fastest), else
        ``((name, Distribution), ...)``.
    n:
        Number of samples (Latin hypercube and Monte Carlo; a grid has the product of its axes).
    seed:
        Seed of the random numbers (same seed, same samples).
    analyses:
        Subset of :data:`ANALYSES`, in order; each includes the downlock solve.
    values:
        ``((name, value), ...)``: parameters fixed for the whole study (SI).
    hold, condition, force:
        The downlock condition (default the model's; see
        :func:`~mechcont.analysis.downlock_condition`). For the ``freefall`` analysis ``hold`` is
        the released (retracted) pose instead (coordinates or conditions held while assembling).
    lock, until:
        The ``freefall`` analysis (alone: it has no downlock solve): each sample released at rest
        from ``hold`` and simulated with its stops for at most ``until`` s; it locks when every
        stop named in ``lock`` is in contact at rest (:func:`~mechcont.dynamics.freefall.freefall`).
    chunk:
        Samples per chunk (the unit of work, of a written part, and of resuming).
    model_hash:
        SHA-256 of a description file's text ("" for a built-in model): a resumed study
        refuses a changed file.
    """

    model: str
    sampling: str
    parameters: tuple
    n: int = 0
    seed: int = 0
    analyses: tuple[str, ...] = ("downlock",)
    values: tuple[tuple[str, float], ...] = ()
    hold: tuple[tuple[str, float], ...] = ()
    condition: str | None = None
    force: str | None = None
    chunk: int = 0
    model_hash: str = field(default="")
    lock: tuple[str, ...] = ()
    until: float = 0.0

    def __post_init__(self) -> None:
        if self.sampling not in SAMPLINGS:
            raise InputError("sampling", f"unknown sampling '{self.sampling}'; valid: {', '.join(SAMPLINGS)}")
        if not self.parameters:
            raise InputError("parameters", "give at least one sampled parameter")
        names = [n for n, _ in self.parameters]
        if len(set(names)) != len(names):
            raise InputError(sorted(n for n in names if names.count(n) > 1)[0], "is sampled twice")
        want = GridAxis if self.sampling == "grid" else Distribution
        for n, d in self.parameters:
            if not isinstance(d, want):
                what = "a grid axis LO:HI:N" if want is GridAxis else "a distribution (uniform/normal/truncnormal)"
                raise InputError(n, f"a {self.sampling} study needs {what} for every parameter")
            if n in dict(self.values):
                raise InputError(n, "is both sampled and fixed (--set)")
        if self.sampling != "grid" and not 1 <= self.n <= MAX_SAMPLES:
            raise InputError("n", f"the number of samples must be 1..{MAX_SAMPLES}, got {self.n}")
        if self.sampling == "grid" and self.size > MAX_SAMPLES:  # decided before the points are made
            raise InputError("grid", f"{' x '.join(str(a.n) for _, a in self.parameters)} = {self.size} points; a "
                                     f"study takes at most {MAX_SAMPLES} samples (fewer values per axis)")
        if not self.analyses or any(a not in ANALYSES for a in self.analyses):
            raise InputError("analysis", f"unknown analysis in {', '.join(self.analyses) or 'none'}; valid: "
                                         f"{', '.join(ANALYSES)}")
        if "freefall" in self.analyses:
            self._check_freefall()
        elif self.lock or self.until:
            raise InputError("lock" if self.lock else "until", "applies to the freefall analysis only (--analysis freefall)")
        if self.chunk < 0 or self.chunk > 1_000_000:
            raise InputError("chunk", f"must be 1..1000000 samples, got {self.chunk}")
        if self.chunk == 0:
            object.__setattr__(self, "chunk", min(DEFAULT_CHUNK[a] for a in self.analyses))
        if not 0 <= self.seed < 2**63:
            raise InputError("seed", f"must be a non-negative whole number, got {self.seed}")

    def _check_freefall(self) -> None:
        if len(self.analyses) != 1:
            raise InputError("analysis", "freefall is a study of its own (a time simulation per sample, no downlock "
                                         "solve): give --analysis freefall alone")
        if self.condition is not None or self.force is not None:
            raise InputError("condition" if self.condition is not None else "force",
                             "is a downlock setting; a freefall study takes --hold (the released pose), --lock, --until")
        if not self.hold:
            raise InputError("hold", "give the released (retracted) pose of the freefall, e.g. --hold angle=3.0")
        if not self.lock:
            raise InputError("lock", "give the lock stop(s) of the freefall, e.g. --lock downlock")
        if not (math.isfinite(self.until) and 0 < self.until <= MAX_UNTIL):
            raise InputError("until", f"must be a number of seconds, 0 < SECONDS <= {MAX_UNTIL:g}, got {self.until:g}")

    # -- the samples -----------------------------------------------------------------------
    @property
    def names(self) -> tuple[str, ...]:
        """The sampled parameters, in order."""
        return tuple(n for n, _ in self.parameters)

    @property
    def size(self) -> int:
        """Number of samples."""
        if self.sampling == "grid":
            return math.prod(a.n for _, a in self.parameters)  # exact: no int64 overflow for many axes
        return self.n

    @property
    def grid_shape(self) -> tuple[int, ...] | None:
        """Shape of a grid study's results (one axis per parameter, in order); None otherwise."""
        return tuple(a.n for _, a in self.parameters) if self.sampling == "grid" else None

    @property
    def n_chunks(self) -> int:
        """Number of chunks (the last may be shorter)."""
        return -(-self.size // self.chunk)

    def samples(self) -> np.ndarray:
        """All sampled values, array ``(size, len(names))`` (SI), the same for the same spec."""
        d = len(self.parameters)
        if self.sampling == "grid":
            axes = [a.values() for _, a in self.parameters]
            return np.stack([g.reshape(-1) for g in np.meshgrid(*axes, indexing="ij")], axis=1)
        if self.sampling == "mc":
            q = np.random.Generator(np.random.PCG64(self.seed)).random((self.n, d))
        else:
            from scipy.stats import qmc

            q = qmc.LatinHypercube(d=d, seed=np.random.Generator(np.random.PCG64(self.seed))).random(self.n)
        return np.column_stack([dist.ppf(q[:, j]) for j, (_, dist) in enumerate(self.parameters)])

    def chunk_rows(self, k: int) -> tuple[int, int]:
        """``(start, stop)`` sample indices of chunk ``k``."""
        if not 0 <= k < self.n_chunks:
            raise IndexError(f"chunk {k} of {self.n_chunks}")
        return k * self.chunk, min((k + 1) * self.chunk, self.size)

    # -- plain data ------------------------------------------------------------------------
    def to_mapping(self) -> dict:
        """The spec as JSON/TOML-ready data (see :meth:`from_mapping`)."""
        out = {"model": self.model, "sampling": self.sampling,
               "parameters": {n: a.text() for n, a in self.parameters},
               "analyses": list(self.analyses), "chunk": self.chunk}
        if self.sampling != "grid":
            out.update(n=self.n, seed=self.seed)
        if self.values:
            out["set"] = dict(self.values)
        if self.hold:
            out["hold"] = dict(self.hold)
        for k in ("condition", "force"):
            if getattr(self, k) is not None:
                out[k] = getattr(self, k)
        if self.model_hash:
            out["model_hash"] = self.model_hash
        if self.lock:
            out["lock"] = list(self.lock)
        if self.until:
            out["until"] = self.until
        return out

    @classmethod
    def read(cls, path: str | Path, model: str | None = None, *, field: str = "spec") -> StudySpec:
        """A spec from a TOML study file (:meth:`from_mapping`'s form); its ``model`` defaults to ``model``
        and, when both are given, must be it. Errors (unreadable, not TOML, another model) name ``field``."""
        import tomllib

        try:
            data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
        except OSError as exc:
            raise InputError(field, f"cannot read '{path}': {exc.strerror}") from None
        except UnicodeDecodeError:
            raise InputError(field, f"'{path}' is not a text file (UTF-8 TOML)") from None
        except tomllib.TOMLDecodeError as exc:
            raise InputError(field, f"'{path}' is not valid TOML: {exc}") from None
        except (RecursionError, MemoryError):
            raise InputError(field, f"'{path}' is nested too deeply (arrays or tables inside each other)") from None
        except ValueError as exc:  # an integer of more than 4300 digits
            raise InputError(field, f"'{path}' has a number the TOML reader refuses ({exc.args[0].split(';')[0]})") from None
        if model is not None:
            data.setdefault("model", model)
            if str(data["model"]) != model:
                raise InputError(field, f"the file is a study of '{data['model']}', not of '{model}'")
        return cls.from_mapping(data, where=Path(path).name)

    @classmethod
    def from_mapping(cls, data: Mapping, *, where: str = "study") -> StudySpec:
        """A spec from :meth:`to_mapping`'s form (a TOML study file, ``study.json``); keys whitelisted.

        ``parameters`` maps each name to ``"KIND:A:B..."`` (or ``"LO:HI:N"`` for a grid), or
        to a table ``{distribution = "normal", mean = ..., sd = ...}`` /
        ``{low = ..., high = ..., n = ...}``.
        """
        if not isinstance(data, Mapping):
            raise InputError(where, "must be a table of study settings")
        known = {"model", "sampling", "parameters", "n", "seed", "analyses", "set", "hold", "condition", "force",
                 "chunk", "model_hash", "lock", "until"}
        for k in data:
            if k not in known:
                raise InputError(f"{where}.{k}", f"unknown key; valid: {', '.join(sorted(known))}")
        for k in ("model", "sampling", "parameters"):
            if k not in data:
                raise InputError(f"{where}.{k}", "is missing")
        sampling = str(data["sampling"])
        params = data["parameters"]
        if not isinstance(params, Mapping):
            raise InputError(f"{where}.parameters", "must be a table NAME = \"KIND:A:B\"")
        parsed = []
        for name, d in params.items():
            label = f"{where}.parameters.{name}"
            if isinstance(d, Mapping):
                parsed.append((str(name), _from_table(d, label, sampling)))
            elif sampling == "grid":
                parsed.append((str(name), parse_axis(d, label)))
            else:
                parsed.append((str(name), parse_distribution(d, label)))

        def pairs(key: str) -> tuple[tuple[str, float], ...]:
            table = data.get(key, {})
            if not isinstance(table, Mapping):
                raise InputError(f"{where}.{key}", "must be a table NAME = VALUE")
            return tuple((str(k), finite_number(v, f"{where}.{key}.{k}")) for k, v in table.items())

        def whole(key: str, default: int) -> int:
            v = data.get(key, default)
            if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v) or v != int(v):
                raise InputError(f"{where}.{key}", f"must be a whole number, got {v!r}")
            return int(v)

        lock = data.get("lock", [])
        lock = [lock] if isinstance(lock, str) else lock
        if not isinstance(lock, list | tuple) or not all(isinstance(n, str) and n.isidentifier() for n in lock):
            raise InputError(f"{where}.lock", "must be a stop's name or a list of them")
        analyses = data.get("analyses", ["downlock"])
        if isinstance(analyses, str) or not isinstance(analyses, list | tuple):
            raise InputError(f"{where}.analyses", f"must be a list of analyses ({', '.join(ANALYSES)})")
        return cls(model=str(data["model"]), sampling=sampling, parameters=tuple(parsed), n=whole("n", 0),
                   seed=whole("seed", 0), analyses=tuple(str(a) for a in analyses), values=pairs("set"),
                   hold=pairs("hold"), condition=_text(data.get("condition"), f"{where}.condition"),
                   force=_text(data.get("force"), f"{where}.force"), chunk=whole("chunk", 0),
                   model_hash=str(data.get("model_hash", "")), lock=tuple(lock),
                   until=finite_number(data.get("until", 0.0), f"{where}.until"))

    def with_model_hash(self) -> StudySpec:
        """This spec with :attr:`model_hash` of its description file filled in (unchanged for a built-in).

        A ``model_hash`` the spec already gives is checked, not kept: InputError when it is not the
        SHA-256 of the description file's text now (the file changed since the spec was written),
        or when the model is built in (it has none)."""
        from dataclasses import replace

        from ...models import BUILTIN_MODELS

        given = self.model_hash
        if given and not re.fullmatch(r"[0-9a-f]{64}", given):
            raise InputError("model_hash", f"{given[:80]!r} is not a SHA-256 (64 hex digits); remove the key to take the "
                                           "model as it is")
        if self.model in BUILTIN_MODELS:
            if given:
                raise InputError("model_hash", f"{self.model} is a built-in model, which has no description file to "
                                               "hash; remove the key")
            return self
        from ...mechanism import find_description

        path = find_description(self.model)
        if path is None:
            return self
        actual = _file_hash(Path(path))
        if given and given != actual:
            raise InputError("model_hash", f"{given[:12]}... is not the hash of {path} ({actual[:12]}...): the "
                                           "description changed since the spec was written; remove the key to run on "
                                           "the file as it is")
        return replace(self, model_hash=actual)


def _text(v: object, where: str) -> str | None:
    """``v`` (a value of a spec file) as a name, None for none; :class:`InputError` naming ``where`` otherwise."""
    if v is None:
        return None
    if not isinstance(v, str) or not v.isidentifier():
        raise InputError(where, f"must be a name, got {v!r}")
    return v


def _from_table(d: Mapping, label: str, sampling: str) -> GridAxis | Distribution:
    """A sampled parameter's table (``low``/``high``/``n`` of a grid, ``distribution`` and its fields) as its axis or
    distribution; :class:`InputError` naming the key that is wrong."""
    if sampling == "grid":
        allowed = ("low", "high", "n")
        for k in d:
            if k not in allowed:
                raise InputError(f"{label}.{k}", f"unknown key; valid: {', '.join(allowed)}")
        if "n" not in d or isinstance(d["n"], bool) or not isinstance(d["n"], int):
            raise InputError(f"{label}.n", "give the number of values (a whole number)")
        return GridAxis(finite_number(d.get("low"), f"{label}.low"), finite_number(d.get("high"), f"{label}.high"), int(d["n"]))
    kind = str(d.get("distribution", "")).lower()
    if kind not in _FIELDS:
        raise InputError(f"{label}.distribution", f"give one of {', '.join(_FIELDS)}")
    for k in d:
        if k != "distribution" and k not in _FIELDS[kind]:
            raise InputError(f"{label}.{k}", f"unknown key for {kind}; valid: {', '.join(_FIELDS[kind])}")
    return Distribution(kind, tuple(finite_number(d.get(f), f"{label}.{f}") for f in _FIELDS[kind]))
