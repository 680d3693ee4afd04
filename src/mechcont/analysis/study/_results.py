"""Reading a study's results and summarising them: probability of not locking, sensitivities, grids.

* :func:`failure_probability`: the fraction of samples that do not lock unaided
  (``downlock_force <= 0``) with an exact Clopper–Pearson confidence interval
  (:func:`scipy.stats.binomtest`); failed samples are counted apart, never as locking.
* :func:`sensitivity`: how much each sampled parameter moves the downlock force, ranked:
  standardised regression coefficients (SRC: the least-squares slope times the
  parameter's standard deviation over the force's), the share of the variance the linear
  model explains, and Spearman's rank correlation as a check that does not assume linearity.
* :func:`grid_values`: a grid study's column as an array with one axis per parameter.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..._status import Status

if TYPE_CHECKING:
    import pandas as pd

    from ._execute import StudyResult
    from ._spec import StudySpec

__all__ = ["read_results", "failure_probability", "FailureProbability", "sensitivity", "SampledSensitivity",
           "Sensitivity", "grid_values",
           "study_spec_of", "study_report"]


def read_results(path: str | Path) -> pd.DataFrame:
    """A study's ``results.parquet`` (or one part) as a :class:`pandas.DataFrame`.

    ``.attrs["units"]`` maps each column to its unit, ``.attrs["study"]`` is the spec
    (:meth:`~mechcont.analysis.study.StudySpec.to_mapping` form) and, for a grid,
    ``.attrs["grid_shape"]`` its shape.
    """
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    df = table.to_pandas()
    df.attrs["units"] = {f.name: (f.metadata or {}).get(b"unit", b"").decode() for f in table.schema}
    meta = table.schema.metadata or {}
    if b"mechcont.study" in meta:
        df.attrs["study"] = json.loads(meta[b"mechcont.study"])
    if b"mechcont.grid_shape" in meta:
        df.attrs["grid_shape"] = tuple(json.loads(meta[b"mechcont.grid_shape"]))
    return df


def study_spec_of(df: pd.DataFrame) -> StudySpec:
    """The :class:`~mechcont.analysis.study.StudySpec` a results frame was made with."""
    from ._spec import StudySpec

    return StudySpec.from_mapping(df.attrs["study"])


@dataclass(frozen=True)
class FailureProbability:
    """How often the gear does not lock unaided.

    Attributes
    ----------
    failures:
        Converged samples with ``downlock_force <= 0`` (N).
    samples:
        Converged samples.
    unsolved:
        Samples whose solve failed (not counted either way).
    probability:
        ``failures / samples``.
    low, high:
        Exact (Clopper–Pearson) confidence interval of the probability.
    confidence:
        Its confidence level, e.g. 0.95.
    """

    failures: int
    samples: int
    unsolved: int
    probability: float
    low: float
    high: float
    confidence: float
    what: str = "not locking unaided"

    def line(self) -> str:
        """One line for a report."""
        extra = f"; {self.unsolved} samples unsolved, not counted" if self.unsolved else ""
        return (f"P({self.what}) = {self.probability:.4g} ({self.failures} of {self.samples} samples), "
                f"{100 * self.confidence:g} % Clopper-Pearson interval [{self.low:.4g}, {self.high:.4g}]{extra}")


def failure_probability(df: pd.DataFrame, confidence: float = 0.95) -> FailureProbability:
    """Probability that a sample does not lock unaided (downlock force <= 0 N), or for a freefall study
    that its freefall fails to lock (column ``locked`` False), with its exact interval."""
    from scipy.stats import binomtest

    ok = (df["status"] == Status.CONVERGED).to_numpy()
    n = int(ok.sum())
    freefall = "locked" in df and "downlock_force" not in df
    fails = ~df["locked"].to_numpy(dtype=bool) if freefall else df["downlock_force"].to_numpy() <= 0
    k = int(fails[ok].sum())
    what = "freefall fails to lock" if freefall else "not locking unaided"
    if n == 0:
        return FailureProbability(0, 0, int((~ok).sum()), float("nan"), 0.0, 1.0, confidence, what)
    ci = binomtest(k, n).proportion_ci(confidence_level=confidence, method="exact")
    return FailureProbability(k, n, int((~ok).sum()), k / n, float(ci.low), float(ci.high), confidence, what)


@dataclass(frozen=True)
class SampledSensitivity:
    """One sampled parameter's effect on an output.

    Attributes
    ----------
    name:
        The parameter.
    src:
        Standardised regression coefficient: least-squares slope x sd(parameter) / sd(output).
    slope:
        The least-squares slope (output unit per parameter unit, e.g. N/m).
    spearman:
        Spearman's rank correlation of the parameter with the output.
    """

    name: str
    src: float
    slope: float
    spearman: float


#: its name before issue 34 (the engine's :class:`mechcont.continuation.Sensitivity` is another thing)
Sensitivity = SampledSensitivity

def sensitivity(df: pd.DataFrame, names: Sequence[str] | None = None,
                output: str = "downlock_force") -> tuple[list[SampledSensitivity], float]:
    """Rank the sampled parameters by their effect on ``output`` (converged samples only).

    Returns ``(ranking, r2)``: :class:`SampledSensitivity` per parameter, largest ``|src|`` first, and
    the share of the output's variance that the linear model explains (near 1: the SRCs are
    the whole story; squared SRCs then add up to about ``r2``).
    """
    from scipy.stats import spearmanr

    if names is None:
        names = list(df.attrs.get("study", {}).get("parameters", {}))
    ok = (df["status"] == Status.CONVERGED).to_numpy()
    y = df[output].to_numpy()[ok]
    X = np.column_stack([df[n].to_numpy()[ok] for n in names])
    if len(y) < len(names) + 2:
        raise ValueError(f"{len(y)} converged samples are too few to rank {len(names)} parameters")
    sx, sy = X.std(axis=0), y.std()
    A = np.column_stack([np.ones(len(y)), X - X.mean(axis=0)])
    coef, *_ = np.linalg.lstsq(A, y - y.mean(), rcond=None)
    slopes = coef[1:]
    fit = A @ coef
    r2 = float(1 - np.sum((y - y.mean() - fit) ** 2) / np.sum((y - y.mean()) ** 2)) if sy > 0 else float("nan")
    out = []
    for j, n in enumerate(names):
        rho = float(spearmanr(X[:, j], y).statistic) if sx[j] > 0 and sy > 0 else float("nan")
        out.append(SampledSensitivity(n, float(slopes[j] * sx[j] / sy) if sy > 0 else float("nan"), float(slopes[j]), rho))
    out.sort(key=lambda s: -abs(s.src) if np.isfinite(s.src) else 0.0)
    return out, r2


def grid_values(df: pd.DataFrame, column: str) -> np.ndarray:
    """A grid study's ``column`` with one axis per sampled parameter (in the spec's order)."""
    shape = df.attrs.get("grid_shape")
    if shape is None:
        raise ValueError("not a grid study")
    order = np.argsort(df["sample"].to_numpy())
    return df[column].to_numpy()[order].reshape(shape)


def study_report(df: pd.DataFrame, spec: StudySpec, result: StudyResult, seconds: float) -> tuple[list[str], list[str]]:
    """``(lines, warnings)`` summing up a study: samples and where they ran, the probability of not
    locking, unlock folds and release runs found, the sensitivity ranking (SI units per SI unit) and
    the results' path; ``warnings``: the three commonest reasons samples failed, with their counts."""
    from ...units import derivative_unit

    ok = df["status"] == "converged"
    done, place = len(result.computed), result.ran_on
    lines = [f"{spec.size} samples of {spec.model} ({spec.sampling}), {int(ok.sum())} converged, "
             f"{int((~ok).sum())} failed; {done} chunk(s) computed in {place}, {len(result.reused)} resumed; "
             f"{seconds:.3g} s", failure_probability(df).line()]
    warnings = [f"{count} sample(s) failed: {text}" for text, count in df.loc[~ok, "reason"].value_counts().head(3).items()
                ] if (~ok).any() else []
    if "unlock_force" in df:
        found = df["unlock_force"].notna()
        lines.append(f"unlock fold found for {int(found.sum())} of {int(ok.sum())} converged samples")
    if "branch_folds" in df:
        counts = df.loc[ok, "branch_folds"].value_counts().sort_index()
        lines.append("release runs: " + ", ".join(f"{int(c)} with {int(k)} fold(s)" for k, c in counts.items()))
    if spec.sampling != "grid" and int(ok.sum()) >= len(spec.names) + 2 and "downlock_force" in df:
        ranking, r2 = sensitivity(df, list(spec.names))
        lines.append(f"sensitivity of the downlock force (standardised regression coefficients, linear fit R^2 = {r2:.4f}):")
        units = df.attrs.get("units", {})
        for s in ranking:
            unit = derivative_unit(units.get("downlock_force", "N"), units.get(s.name, ""))
            lines.append(f"  {s.name:>10}  SRC {s.src:+.4f}  slope {s.slope:+.6g} {unit}  Spearman {s.spearman:+.4f}")
    lines.append(f"wrote {result.results}")
    return lines, warnings
