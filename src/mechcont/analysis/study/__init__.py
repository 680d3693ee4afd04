"""Design and tolerance studies: many samples of one model, batched, resumable, on Dask if wanted.

A study samples parameters of a model (a grid, a Latin hypercube, or Monte Carlo draws from
uniform, normal or truncated-normal tolerances), runs the downlock analysis (and optionally
the unlock folds) at every sample, and writes a labelled table to Parquet chunk by chunk, so
an interrupted study keeps what it computed and a resumed one recomputes nothing::

    from mechcont.analysis.study import StudySpec, Distribution, run_study, failure_probability

    spec = StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (1.3, 0.01))),), n=10_000, seed=1)
    result = run_study(spec, "study-out", scheduler="auto")   # or None: in this process; "local": a cluster
    df = result.frame()
    print(failure_probability(df).line())
"""

from ._dask import STUDY_EXTRA_HINT
from ._execute import ModelSource, StudyResult, load_study_model, run_study
from ._kernels import COLUMNS, check_spec, run_chunk
from ._results import (
    FailureProbability,
    SampledSensitivity,
    Sensitivity,
    failure_probability,
    grid_values,
    read_results,
    sensitivity,
    study_report,
    study_spec_of,
)
from ._schedule import CLUSTER_START_SECONDS, SCHEDULERS, Choice, check_scheduler, choose, cluster_threshold, run_parts
from ._spec import ANALYSES, SAMPLINGS, Distribution, GridAxis, StudySpec, parse_axis, parse_distribution
from ._store import StudyStore

__all__ = ["StudySpec", "Distribution", "GridAxis", "parse_distribution", "parse_axis", "ANALYSES", "SAMPLINGS",
           "run_study", "StudyResult", "ModelSource", "load_study_model", "STUDY_EXTRA_HINT", "run_chunk",
           "check_spec", "COLUMNS", "StudyStore", "read_results", "failure_probability", "FailureProbability",
           "sensitivity", "SampledSensitivity", "Sensitivity", "grid_values", "study_spec_of", "study_report",
           "run_parts", "check_scheduler", "choose", "Choice", "cluster_threshold", "CLUSTER_START_SECONDS", "SCHEDULERS"]
