"""The analyses of one chunk of samples: batched downlock solves, stragglers one by one, unlock folds.

:func:`run_chunk` is the unit of work of a study (the same function runs in-process and on a
Dask worker, so both give the same bits). For every sample it records a status:
``converged``, or ``failed`` and why (a value outside the model's valid range, Newton
that did not converge even from the single-point path's start); a failing sample never
stops the chunk.

* ``downlock``: the downlock condition held, the force solved for
  (:func:`mechcont.continuation._batch.newton_batch` for the whole chunk from the model's
  downlocked pose; a row that does not converge there, or whose configuration moved further
  than :data:`MAX_MOVE` from it, is solved again by :func:`mechcont.analysis.downlock_point`,
  the single-point path, and marked ``single``).
  ``locks_unaided`` is ``downlock_force > 0``.
* ``unlock``: the folds bounding the locked state through the downlocked point
  (:func:`mechcont.analysis.unlock_folds`, a release run, for the chunk's first sample; the
  others' folds polished all at once from its folds by
  :func:`mechcont.continuation._batch.fold_batch`, and a release run of their own for those
  whose fold is not found so, lies on the wrong side of the downlock force, or moved further
  than :data:`MAX_MOVE`, and for all when the first sample has no located fold; a side on
  which the first sample has no fold is not searched for the others, and their note says so): ``unlock_force``
  (reached by increasing the force), ``unlock_force_decreasing``, and the fold margin
  ``unlock_margin = unlock_force - downlock_force`` (N): the force the locked state still
  carries beyond the downlock force. ``nan`` where no fold bounds that side (with a note).
* ``branch``: a summary of every sample's own release run (no batching): its points, folds,
  unstable points, the range of the force it covered and how it ended; with ``unlock`` the
  unlock columns then come from the same runs.
* ``freefall`` (alone: no downlock solve): every sample released at rest from the retracted pose
  (the spec's ``hold``) and simulated with its stops (:func:`mechcont.dynamics.freefall.freefall`):
  its outcome, ``locked`` (every lock stop in contact at rest), the time to lock and the impact
  speed; a run ends once locked, or at rest short of the lock at a stable equilibrium (``end_at_lock``:
  nothing more can change), else at ``until``; an integrator failure is a failed sample.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._status import Status
from ...continuation import choose_unknowns, fold_batch, newton_batch
from ...errors import ConvergenceError, InputError
from ..downlock import downlock_condition, downlock_point, downlocked_pose
from ..unlock import RELEASE_FORCE_SPAN, UnlockFolds, unlock_folds
from ._spec import StudySpec

if TYPE_CHECKING:
    from ...continuation import Branch
    from ...equations import Model

__all__ = ["run_chunk", "check_spec", "result_columns", "COLUMNS", "MAX_MOVE"]

#: A batched solution is kept only if no angle (rad) or position (m) state moved by more than
#: this many of its scales from the shared start (the model's downlocked pose); further away
#: the single-point path, which starts from the model's own assembly at the sample's values
#: when it has one, decides which assembly of the mechanism is meant.
MAX_MOVE = 0.25

# a sample's status as written in the table's columns: the words of Status, plain text for the file formats
_CONVERGED, _FAILED = Status.CONVERGED.value, Status.FAILED.value

#: Result columns after the sampled parameters: name -> (unit, meaning).
COLUMNS = {
    "status": ("", "converged, or failed (see reason)"),
    "reason": ("", "why a sample failed (empty when it converged)"),
    "path": ("", "batched (solved with the chunk) or single (solved alone: a straggler)"),
    "downlock_force": ("N", "force at which the downlock condition holds (+ unlocks)"),
    "locks_unaided": ("", "downlock_force > 0: the gear locks with no help"),
    "unlock_force": ("N", "fold reached by increasing the force from the downlocked point"),
    "unlock_force_decreasing": ("N", "fold reached by decreasing the force"),
    "unlock_margin": ("N", "unlock_force - downlock_force: the fold margin"),
    "stable": ("", "the downlocked point is physically stable"),
    "unlock_note": ("", "why a side has no fold"),
    "unlock_path": ("", "batched (folds polished with the chunk from its first sample's) or single (own release run)"),
    "branch_points": ("", "points of the release run (continuation in the force, condition released)"),
    "branch_folds": ("", "folds (LP) on the release run: each direction stops at its first"),
    "branch_unstable_points": ("", "release-run points with an unstable direction (a fold point, neither, not counted)"),
    "branch_force_low": ("N", "smallest force reached by the release run (nan where it ended at its own bound)"),
    "branch_force_high": ("N", "largest force reached by the release run (nan where it ended at its own bound)"),
    "branch_status": ("", "how the release run ended: completed, stopped early, failed"),
    "branch_note": ("", "why branch_force_low or branch_force_high is nan"),
    "outcome": ("", "freefall: locked, at rest (short of locking), still moving (at until) or failed"),
    "locked": ("", "freefall: every lock stop in contact, at rest"),
    "time_to_lock": ("s", "freefall: when the last lock stop locked (nan: not locked)"),
    "impact_speed": ("", "freefall: the last lock stop's condition rate at its first impact (its unit per s; nan: none)"),
    "lock_spread": ("s", "freefall: how far apart in time the lock stops locked (nan: not all locked)"),
}

_FREEFALL = ("outcome", "locked", "time_to_lock", "impact_speed", "lock_spread")


def result_columns(spec: StudySpec) -> list[str]:
    """The columns of a chunk of ``spec``, in order (as :func:`run_chunk` returns them)."""
    if "freefall" in spec.analyses:
        return ["sample", *spec.names, "status", "reason", *_FREEFALL]
    return ["sample", *spec.names, "status", "reason", "path", "downlock_force", "locks_unaided",
            *(_UNLOCK if "unlock" in spec.analyses else ()), *(_BRANCH if "branch" in spec.analyses else ())]


def check_spec(system: Model, spec: StudySpec) -> tuple[dict, str | None]:
    """Check ``spec`` against the model before any work: every name known and a parameter
    that may be set, the downlock condition resolvable (the freefall's pose and lock stops). Returns
    ``(hold, force)`` (a freefall study: ``(released pose, None)``)."""
    if "freefall" in spec.analyses:
        pose = _check_freefall(system, spec)
        _check_values(system, spec)
        return pose, None
    h, f = downlock_condition(system.with_values(dict(spec.values)), dict(spec.hold) or None, spec.force,
                              condition=spec.condition)
    _check_chunk_memory(system, spec)
    for n in (*spec.names, *dict(spec.values)):
        v = system.variable(n)
        if n == f:
            raise InputError(n, "is the downlock force, which each sample solves for; sample a design parameter")
        if v.kind != "parameter":
            raise InputError(n, "is a state of the model; sample or set parameters only")
    _check_values(system, spec)
    return h, f


def _check_values(system: Model, spec: StudySpec) -> None:
    """The ``--set`` values and each distribution's centre checked as ``--set`` values are
    (:func:`~mechcont.equations.check_values_at`); a sample out of range (a grid may cross the model's
    range on purpose, a distribution's tail) later fails alone, with the reason."""
    from ...equations import check_values_at
    from ._spec import Distribution

    fixed = dict(spec.values)
    check_values_at(system, fixed, "--set")
    for n, d in spec.parameters:
        if isinstance(d, Distribution):
            check_values_at(system, {**fixed, n: float(d.centre)}, "--dist")


#: Most memory (bytes) the batched solves of one chunk may take; decided from the sizes before any work.
CHUNK_MEMORY = 2 * 1024**3


def _check_chunk_memory(system: Model, spec: StudySpec) -> None:
    """InputError when a chunk's batched solves would need more than :data:`CHUNK_MEMORY`: per sample
    about three Jacobians of the (fold-augmented, for ``unlock``) system, 8 bytes a number."""
    n_eq, n_var = len(system.equations), len(system.names)
    per_row = 3 * 8 * ((2 * n_eq + 1) * (2 * n_var) if "unlock" in spec.analyses else n_eq * n_var)
    rows = min(spec.chunk, spec.size)
    if rows * per_row > CHUNK_MEMORY:
        raise InputError("chunk", f"{rows} samples per chunk would need about {rows * per_row / 1024**3:.3g} GiB for "
                                  f"the batched solves of this model; give at most {CHUNK_MEMORY // per_row} (--chunk)")


def _plan(system: Model, spec: StudySpec) -> dict:
    """What every sample of a downlock chunk shares: the condition, the start, the unknowns (``system``: the
    model at the study's ``--set`` values)."""
    h, f = check_spec(system, spec)
    assert f is not None  # a downlock study (a freefall study has no _plan)
    fixed = dict(spec.values)
    base = downlocked_pose(system)
    base = system.vector(fixed, base=base) if base is not None else system.vector(fixed)
    base = system.vector(h, base=base)
    return {"hold": h, "force": f, "base": base, "fixed": fixed,
            "unknowns": choose_unknowns(system, hold=list(h), free=[f]),
            "cols": np.array([system.index(n) for n in spec.names]), "scales": system.scales(),
            "geometry": np.array([i for i, v in enumerate(system.variables)
                                  if v.kind == "state" and v.unit in ("rad", "m")], dtype=int)}


def _check_freefall(system: Model, spec: StudySpec) -> dict:
    from ...dynamics.freefall import find_lock_stops

    if system.mechanics is None:
        raise InputError("model", f"{spec.model} has no mechanics (masses, forces): it cannot be simulated")
    find_lock_stops(system, list(spec.lock))
    for n, _ in spec.hold:
        if n not in system.names or system.variable(n).kind != "state":
            raise InputError("hold", f"{n} is not a coordinate or condition of {system.name} (the released pose)")
    for n in (*spec.names, *dict(spec.values)):
        if n not in system.names or system.variable(n).kind != "parameter":
            raise InputError(n, f"is not a parameter of {system.name}; sample or set parameters only")
    return dict(spec.hold)


def _freefall_chunk(system: Model, spec: StudySpec, S: np.ndarray, start: int, stop: int) -> dict:
    """The ``freefall`` analysis of the samples ``S`` (rows ``start:stop`` of the study)."""
    from ...dynamics.freefall import freefall

    pose = _check_freefall(system, spec)
    m = len(S)
    status, reason = np.full(m, _CONVERGED, dtype=object), np.full(m, "", dtype=object)
    outcome = np.full(m, "", dtype=object)
    locked = np.zeros(m, dtype=bool)
    t_lock, impact, spread = np.full(m, np.nan), np.full(m, np.nan), np.full(m, np.nan)
    lock = spec.lock[0] if len(spec.lock) == 1 else list(spec.lock)
    system = system.with_values(dict(spec.values))  # the model at the --set values: what is written in them follows
    for i in range(m):
        values = {**dict(spec.values), **{n: float(v) for n, v in zip(spec.names, S[i])}}
        why = _valid(system, values)
        if why:
            status[i], reason[i] = _FAILED, why
            continue
        try:
            # ended once locked (or at rest where nothing more can change), as the freefall command's runs:
            # the columns read are those of the run to until, which would only repeat the locked state
            run = freefall(system, pose, lock=lock, until=spec.until, values=values, end_at_lock=True)
        except (ConvergenceError, InputError) as exc:
            status[i], reason[i] = _FAILED, f"freefall: {exc}"
            continue
        outcome[i], locked[i] = Status.of(run.outcome).value, run.locked  # plain text, as the status
        if run.outcome == Status.FAILED:
            status[i], reason[i] = _FAILED, f"freefall: {run.history.message}"
        for arr, v in ((t_lock, run.time_to_lock), (impact, run.impact_speed), (spread, run.lock_spread)):
            arr[i] = np.nan if v is None else v
    return {"sample": np.arange(start, stop, dtype=np.int64), **{n: S[:, j] for j, n in enumerate(spec.names)},
            "status": status, "reason": reason, "outcome": outcome, "locked": locked, "time_to_lock": t_lock,
            "impact_speed": impact, "lock_spread": spread}


def _valid(system: Model, values: dict) -> str:
    """The one-line reason ``values`` are outside the model's valid range (as ``--set`` checks them), or ""."""
    from ...equations import check_values_at

    try:
        check_values_at(system, values, "sample")
    except InputError as exc:
        return str(exc)
    return ""


def run_chunk(system: Model, spec: StudySpec, k: int, samples: np.ndarray | None = None) -> dict:
    """The analyses of chunk ``k`` of ``spec`` on ``system``: ``{column: array}``, one row per sample.

    ``samples`` (all of the study's, from :meth:`StudySpec.samples`) saves drawing them again.
    Columns: ``sample`` (index), the sampled parameters (SI), then :data:`COLUMNS` (those of
    the requested analyses).
    """
    start, stop = spec.chunk_rows(k)
    if "freefall" in spec.analyses:
        return _freefall_chunk(system, spec, (spec.samples() if samples is None else samples)[start:stop], start, stop)
    system = system.with_values(dict(spec.values))  # the model at the --set values: what is written in them follows
    p = _plan(system, spec)
    h, f, base, names = p["hold"], p["force"], p["base"], spec.names
    S = (spec.samples() if samples is None else samples)[start:stop]
    m = len(S)
    X0 = np.tile(base, (m, 1))
    X0[:, p["cols"]] = S
    if not spec.hold and any(system.written_in(f"conditions.{c}.target") & set(names) for c in h):
        held = [system.index(n) for n in h]  # a hold written in sampled parameters: each sample's own
        for i in range(m):
            try:
                at, _ = downlock_condition(system.with_values(dict(zip(names, map(float, S[i])))), None, spec.force,
                                           condition=spec.condition)
            except InputError:  # a sample out of range: it fails below, with the reason
                continue
            X0[i, held] = [at[n] for n in h]
    status = np.full(m, _CONVERGED, dtype=object)
    reason = np.full(m, "", dtype=object)
    path = np.full(m, "batched", dtype=object)
    # values outside the model's ranges (its check and its declared limits) fail at once
    for i in range(m):
        why = _valid(system, {**p["fixed"], **{n: float(v) for n, v in zip(names, S[i])}})
        if not why:
            try:
                system.check_limits(X0[i])
            except InputError as exc:
                why = str(exc)
        if why:
            status[i], reason[i] = _FAILED, why
    ok = np.nonzero(status == _CONVERGED)[0]
    X = np.full_like(X0, np.nan)
    if len(ok):
        sol = newton_batch(system, X0[ok], p["unknowns"])
        # a row whose configuration moved far from the shared start may have reached another
        # assembly of the mechanism than the single-point path's own start would: it is a straggler
        geo = p["geometry"]
        moved = np.max(np.abs(sol.x[:, geo] - X0[ok][:, geo]) / p["scales"][geo], axis=1, initial=0.0)
        kept = sol.converged & (moved <= MAX_MOVE)
        X[ok[kept]] = sol.x[kept]
        for i in ok[~kept]:  # stragglers: the single-point path, from its own start
            path[i] = "single"
            values = {**p["fixed"], **{n: float(v) for n, v in zip(names, S[i])}}
            try:
                X[i] = downlock_point(system, values, hold=h, force=f)
            except (ConvergenceError, InputError) as exc:
                status[i], reason[i] = _FAILED, f"downlock solve: {exc}"
    F = X[:, system.index(f)]
    out = {"sample": np.arange(start, stop, dtype=np.int64), **{n: S[:, j] for j, n in enumerate(names)},
           "status": status, "reason": reason, "path": path, "downlock_force": F, "locks_unaided": F > 0}
    if "unlock" in spec.analyses or "branch" in spec.analyses:
        cols = _unlock_columns(system, X, F, status, reason, f, list(h), batched="branch" not in spec.analyses)
        out.update({k: cols[k] for k in result_columns(spec)[len(out):]})
    return out


_UNLOCK = ("unlock_force", "unlock_force_decreasing", "unlock_margin", "stable", "unlock_note", "unlock_path")
_BRANCH = ("branch_points", "branch_folds", "branch_unstable_points", "branch_force_low", "branch_force_high",
           "branch_status", "branch_note")


def _unlock_columns(system: Model, X: np.ndarray, F: np.ndarray, status: np.ndarray, reason: np.ndarray, f: str,
                    released: Sequence[str], batched: bool = True) -> dict:
    """The unlock columns of a chunk: the first converged row's release run, the others' folds polished all at
    once from it (:func:`fold_batch`), a row whose batched fold cannot be trusted run alone."""
    # longer than 60 lines: the chunk's thirteen result columns are filled in place by both paths (a
    # row run alone, the batch), which share them through the closure single()
    m = len(X)
    above, below = np.full(m, np.nan), np.full(m, np.nan)
    points, folds, unstable = (np.zeros(m, dtype=np.int64) for _ in range(3))
    f_low, f_high = np.full(m, np.nan), np.full(m, np.nan)
    how = np.full(m, "", dtype=object)
    stable = np.full(m, None, dtype=object)
    note = np.full(m, "", dtype=object)
    branch_note = np.full(m, "", dtype=object)
    path = np.full(m, "", dtype=object)

    def single(i: int) -> UnlockFolds | None:
        path[i] = "single"
        try:
            u = unlock_folds(system, X[i], f, released=released)
        except (ConvergenceError, InputError) as exc:  # unlock_folds reports failures itself; belt and braces
            status[i], reason[i], how[i] = _FAILED, f"unlock folds: {exc}", _FAILED
            return None
        if u.warnings:
            status[i], reason[i] = _FAILED, "unlock folds: " + "; ".join(u.warnings)
        lo, hi = u.locked_range
        above[i] = hi if np.isfinite(hi) else np.nan
        below[i] = lo if np.isfinite(lo) else np.nan
        stable[i] = u.stable
        note[i] = "; ".join(u.notes)
        b = u.branch
        if b is not None and len(b):
            points[i], folds[i] = len(b), len(b.special("LP"))
            unstable[i] = _unstable_points(b)
            (f_low[i], f_high[i]), branch_note[i] = _force_range(system, b, f, X[i])
            how[i] = (b.status if not u.warnings else Status.STOPPED_EARLY).value
        else:
            how[i] = _FAILED
        return u

    rows = np.nonzero(status == _CONVERGED)[0]
    if len(rows):
        ref = single(rows[0])
        rest = rows[1:]
        # the others from the reference's folds, all at once; a row whose fold is not found so,
        # or not on its side of the downlock force, or far from the reference, is run alone
        ok = np.ones(len(rest), dtype=bool)
        sides = [] if ref is None or ref.warnings else [
            (p, out, sign) for p, out, sign in ((ref.above, above, 1), (ref.below, below, -1)) if p is not None]
        # (a chunk of one converged sample has only its reference: nothing to batch)
        if ref is None or not len(rest) or not batched or not sides or any(not p.located for p, _, _ in sides):
            ok[:] = False
        else:
            missing = [n for n in ref.notes if n.startswith("no fold")]
            note[rest] = "; ".join(f"{n} (for the chunk's first sample; not searched for this one)" for n in missing)
            params = np.array([i for i, v in enumerate(system.variables) if v.kind == "parameter" and v.name != f])
            geo = np.array([i for i, v in enumerate(system.variables) if v.kind == "state" and v.unit in ("rad", "m")],
                           dtype=int)
            scales = system.scales()
            for p, out, sign in sides:
                assert p.null_vector is not None  # a located fold of a run carries its null vector
                G = np.tile(p.x, (len(rest), 1))
                G[:, params] = X[rest][:, params]
                fb = fold_batch(system, G, p.null_vector, list(system.state_names), f)
                moved = np.max(np.abs(fb.x[:, geo] - p.x[geo]) / scales[geo], axis=1, initial=0.0)
                Ff = fb.x[:, system.index(f)]
                good = fb.converged & (moved <= MAX_MOVE) & (sign * (Ff - F[rest]) > 0)
                out[rest[good]] = Ff[good]
                ok &= good
        for j, i in enumerate(rest):
            if ok[j]:
                path[i] = "batched"
                if system.mechanics is not None:
                    stable[i] = bool(system.mechanics.stability(X[i]).stable)
            else:
                above[i] = below[i] = np.nan
                single(i)
    return {"unlock_force": above, "unlock_force_decreasing": below, "unlock_margin": above - F, "stable": stable,
            "unlock_note": note, "unlock_path": path, "branch_points": points, "branch_folds": folds,
            "branch_unstable_points": unstable, "branch_force_low": f_low, "branch_force_high": f_high,
            "branch_status": how, "branch_note": branch_note}


def _unstable_points(b: Branch) -> int:
    """Points of the release run with an unstable direction; a fold point (its stability is
    ``fold``: a zero eigenvalue, neither stable nor unstable) is not one."""
    unstable = np.asarray(b.n_unstable) > 0
    unstable[[p.index for p in b.special("LP") if 0 <= p.index < len(unstable)]] = False
    return int(np.sum(unstable))


def _force_range(system: Model, b: Branch, f: str, x: np.ndarray) -> tuple[tuple[float, float], str]:
    """``((low, high), note)``: the force range of the release run ``b`` from the downlocked point ``x``;
    an end where the run stopped at its own bound on the force is no force of the mechanism: nan, and the note says so."""
    Fb = np.asarray(b[f], dtype=float)
    F0, sc = float(x[system.index(f)]), system.variable(f).scale
    reach = RELEASE_FORCE_SPAN * sc * (1 - 1e-9)
    low, high = float(np.min(Fb)), float(np.max(Fb))
    notes = []
    if low <= F0 - reach:
        low = float("nan")
        notes.append(f"decreasing: the release run ended at its bound {F0 - RELEASE_FORCE_SPAN * sc:.6g} N, no fold")
    if high >= F0 + reach:
        high = float("nan")
        notes.append(f"increasing: the release run ended at its bound {F0 + RELEASE_FORCE_SPAN * sc:.6g} N, no fold")
    return (low, high), "; ".join(notes)
