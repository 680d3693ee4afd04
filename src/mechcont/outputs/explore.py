"""A branch explorer: one self-contained HTML page with the bifurcation diagram and the mechanism beside it.

:func:`explore_page` reads branch, fold-curve or time-history tables (or :class:`Branch`
objects), draws every row of the mechanism with its model's scene (:mod:`mechcont.mechanism`
or the hand-formulated model's ``scene``), and embeds the poses as JSON in a page
(:mod:`._explore_page`) whose small script draws them in SVG: the diagram with any two
columns on the axes, the mechanism at the point hovered, clicked or chosen with the slider
(planar: one view; spatial: the front, side and top views of :mod:`.drawing3d`), the loads
and the point's values, and the special points as buttons. The page needs no server and no
network: no external script, style or font.

Poses (JSON ``branches[k].poses[row]``) are in metres; forces in N, moments in N m; body
colours are those of the PNG drawings (:func:`.drawing.body_colours`).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
import numpy.typing as npt

from .._io import atomic_write
from ..equations import EquationSystem, Model, Scene
from ..errors import InputError
from . import _drawing_parts as _d
from ._explore_points import default_axes, special_points

if TYPE_CHECKING:
    from ..continuation import Branch, CycleBranch

    #: A table the page shows: a branch, fold-curve, time-history or cycles CSV path, a Branch or a CycleBranch.
    _Source: TypeAlias = Branch | CycleBranch | str | os.PathLike[str]

__all__ = ["explore_page", "write_explore", "pose_json", "MAX_ROWS", "PAGE_BUDGET", "EXPLORE_SUFFIXES"]

EXPLORE_SUFFIXES = (".html",)
#: Rows per branch embedded at most; a longer table is thinned (its special points always kept) and the page says so.
MAX_ROWS = 3000
#: Bytes of embedded data (columns and poses) a page holds at most: longer tables of a large mechanism (a spatial
#: gear's time history, 10 kB a row) are thinned further to fit, every special point and event kept.
PAGE_BUDGET = 4_000_000
_EXTRA = ("s", "stability", "n_unstable", "label", "vary")
#: The scene names a tyre's contact point ``"tyre NAME"`` (:meth:`mechcont.mechanism.elements.tyre.Tyre.draw`).
_TYRE = "tyre "


def _xy(p: npt.ArrayLike) -> list[float]:
    return [float(v) for v in np.asarray(p, float).ravel()]


def pose_json(scene: Scene, bodies: Mapping[str, int]) -> dict[str, list[Any]]:
    """One pose as JSON-ready lists (metres, N, N m): ``bars`` ``[[body index, [[x, y(, z)], ...]], ...]``,
    ``pins``/``grounds``/``anchors`` ``[[x, y], ...]``, ``sliders`` ``[[point, direction]]``, ``springs``/
    ``dampers`` ``[[name, a, b]]``, ``slots`` (pin-in-slot joints) ``[[name, start, end]]``,
    ``actuators`` ``[[name, a, b, tension N]]``, ``forces`` ``[[name, point,
    vector N]]``, ``moments`` ``[[name, point, value N m (a 3-vector in 3-D)]]``, ``axes`` ``[[name, point,
    unit axis]]``, ``coils`` (torsion springs and rotary dampers) ``[[name, centre, "spring" | "damper"]]``,
    ``contacts`` (tyres' contact points) ``[[name, point]]``. ``bodies`` maps a body name to its index in the page's
    body list."""
    return {
        "bars": [[bodies[n], [_xy(p) for p in np.atleast_2d(np.asarray(pts, float))]] for n, pts in scene.bars],
        "pins": [_xy(p) for p in scene.pins], "grounds": [_xy(p) for p in scene.grounds],
        "anchors": [_xy(p) for p in scene.anchors],
        "sliders": [[_xy(p), _xy(d)] for p, d in scene.sliders],
        "springs": [[n, _xy(a), _xy(b)] for n, a, b in scene.springs],
        "dampers": [[n, _xy(a), _xy(b)] for n, a, b in scene.dampers],
        "slots": [[n, _xy(a), _xy(b)] for n, a, b in scene.slots],
        "actuators": [[n, _xy(a), _xy(b), float(t)] for n, a, b, t in scene.actuators],
        "forces": [[n, _xy(p), _xy(f)] for n, p, f in scene.forces],
        "moments": [[n, _xy(p), _xy(m) if np.ndim(m) else float(m)] for n, p, m in scene.moments],
        "axes": [[n, _xy(p), _xy(u)] for n, p, u in scene.joint_axes],
        "coils": [[n, _xy(p), str(kind)] for n, p, kind in scene.coils],
        "contacts": [[n[len(_TYRE):], _xy(p)] for n, p in scene.points if n.startswith(_TYRE)],
    }


def _model(model: EquationSystem | str | Path | None) -> EquationSystem | None:
    if model is None or isinstance(model, EquationSystem):
        return model
    from ..models import load_model

    return load_model(model)


def _branch(source: object, index: int) -> tuple[Branch, str]:
    from ..continuation import Branch

    if isinstance(source, Branch):
        return source, source.model or f"branch {index + 1}"
    if isinstance(source, (str, os.PathLike)):
        return Branch.read_csv(source), Path(source).name
    raise InputError("branch", f"expected a branch CSV path or a Branch, not {type(source).__name__}")


def _full_rows(system: EquationSystem, branch: Branch, name: str, values: Mapping[str, float]) -> np.ndarray:
    """The model's full variable vectors at every row of ``branch`` (SI; ``values`` on every row)."""
    X = np.empty((len(branch), len(system.names)))
    missing = []
    for c, var in enumerate(system.variables):
        if var.name in values:
            X[:, c] = values[var.name]
        elif var.name in branch.names:
            unit, want = branch.units.get(var.name, ""), var.unit
            factor = 1.0
            if unit == "deg" and want == "rad":
                factor = math.pi / 180.0
            elif unit and unit != want:
                raise InputError("branch", f"'{name}' column {var.name}: the model's unit is '{want or 'none'}', "
                                           f"not '{unit}'")
            X[:, c] = branch.column(var.name) * factor
        else:
            missing.append(var.name)
    if missing:
        listed = ", ".join(missing[:6]) + (f" and {len(missing) - 6} more" if len(missing) > 6 else "")
        raise InputError("branch", f"'{name}' lacks the column(s) {listed} of model '{system.name}' (a table of "
                                   "another model?); give a missing one with --set NAME=VALUE")
    if not np.all(np.isfinite(X)):
        raise InputError("branch", f"'{name}' row {int(np.where(~np.isfinite(X).all(axis=1))[0][0])} has a "
                                   "non-finite value")
    return X


def _rows(branch: Branch, max_rows: int) -> np.ndarray:
    """Rows embedded: all, or every k-th, the last and every special row when more than ``max_rows``."""
    n = len(branch)
    if n <= max_rows:
        return np.arange(n)
    step = math.ceil(n / max_rows)
    keep = set(range(0, n, step)) | {n - 1} | {p.index for p in branch.special_points}
    return np.array(sorted(keep))


def _row_bytes(branch: Branch, system: EquationSystem | None, X: np.ndarray | None, index: Mapping[str, int],
               samples: int = 5) -> float:
    """Bytes one embedded row of ``branch`` takes in the page, its columns and, with a model, its pose: the most
    of ``samples`` rows spread along it (a row at rest prints shorter numbers than one in motion)."""
    most = 0
    for r in np.unique(np.linspace(0, len(branch) - 1, samples).round().astype(int)):
        size = len(json.dumps([float(v) for v in branch.values[r]], separators=(",", ":")))
        if system is not None and system.scene is not None and X is not None:
            size += len(json.dumps(pose_json(system.scene(X[r]), index), separators=(",", ":")))
        most = max(most, size)
    return most + 8.0  # the row's n_unstable, label and index


def _within_budget(counts: Sequence[int], row_bytes: Sequence[float], budget: float) -> list[int]:
    """Rows per branch (at least 2 each) so that ``sum(rows * row_bytes) <= budget`` where it can be, each branch
    thinned by one factor; ``counts`` are the rows each has."""
    total = sum(n * b for n, b in zip(counts, row_bytes))
    if total <= budget:
        return list(counts)
    f = budget / total
    return [min(n, max(2, int(n * f))) for n in counts]


def _document(branch: Branch, name: str, rows: np.ndarray) -> dict[str, Any]:
    """The page's document of ``rows`` of ``branch`` (see :func:`page_data`; its ``note`` empty, its poses to come);
    InputError naming the row and column of a value that is not finite."""
    doc: dict[str, Any] = {"name": name, "vary": branch.vary, "units": {n: branch.units.get(n, "") for n in branch.names},
           "columns": {n: [float(v) for v in branch.column(n)[rows]] for n in branch.names},
           "n_unstable": [int(v) for v in branch.n_unstable[rows]], "labels": [branch.labels[i] for i in rows],
           "rows": [int(i) for i in rows], "special": special_points(branch, rows), "note": ""}
    for col, vals in doc["columns"].items():
        bad = [i for i, v in enumerate(vals) if not math.isfinite(v)]
        if bad:
            raise InputError("branch", f"'{name}' row {doc['rows'][bad[0]]}, column {col}: {vals[bad[0]]} is "
                                       "not a finite number")
    return doc


def _limits(scenes: Sequence[Scene], dim: int) -> tuple[float, dict[str, tuple[float, float, float, float]]]:
    """(force scale m/N, {view: (xmin, xmax, ymin, ymax)}) fixed over all ``scenes``."""
    if dim == 3:
        from . import drawing3d as _d3

        scale = _d3._force_scale(scenes)
        return scale, {v: _d3._view_limits(scenes, v, scale, True) for v in _d3.VIEWS}
    scale = _d._default_force_scale(scenes)
    return scale, {"plane": _d._limits(_d._union(_d._bounds(s, scale, True) for s in scenes))}


def page_data(model: EquationSystem | str | Path | None, branches: Sequence[_Source], *,
              values: Mapping[str, float] | None = None, max_rows: int = MAX_ROWS, title: str | None = None,
              budget: float = PAGE_BUDGET, orbits: Sequence[str | os.PathLike[str]] = ()) -> dict[str, Any]:
    """The JSON document the page embeds (see :func:`explore_page` for the arguments).

    ``branches[k]``: ``name``, ``columns`` (``{name: [values]}``, SI, the table's own columns),
    ``units``, ``n_unstable`` (-1: not evaluated), ``labels``, ``special`` (``name``, ``tag``, ``short``,
    ``label``, ``row``: see :func:`._explore_points.special_points`), ``rows`` (the table rows embedded), ``note``
    and, with a model, ``poses``
    (:func:`pose_json` per embedded row). A family of cycles also has ``cycle`` (``states``: those with
    ``min_X``/``max_X`` columns) and, with its orbits, per embedded row one period as
    :data:`._explore_cycles.PAGE_FRAMES` instants: ``poses`` (a list of poses per row) when the model is drawn,
    else ``orbits`` (per row, per instant the states' values, SI). Top level: ``bodies`` (``[{name, colour}]``),
    ``dim`` (2 or 3), ``views`` (``{view: [xmin, xmax, ymin, ymax]}`` m; spatial views
    name the axes in ``view_axes``), ``force_scale`` (m/N), ``symbol`` (m), ``load_units`` (the units of the
    poses' lengths, forces and moments: ``["m", "N", "N m"]``, or the description's, ``["mm", "g mm/s^2", ...]``).
    """
    from ._explore_cycles import ORBIT_POINTS, PAGE_FRAMES, CycleTable, cycle_table, has_orbits
    from ._explore_page import VIEW_AXES

    if int(max_rows) < 2:
        raise InputError("--max-rows", f"must be at least 2, not {max_rows}")
    if not budget > 0:
        raise InputError("budget", f"must be a positive number of bytes, not {budget}")
    system = _model(model)
    kinds = {v.name: v.kind for v in system.variables} if system is not None else None
    values = dict(values or {})
    if system is not None:
        for n in values:
            system.index(n)
        if system.scene is None and not (isinstance(system, Model) and system.ode is not None):  # an ODE: no drawing
            raise InputError("model", f"'{system.name}' has no drawing (its EquationSystem has no scene)")
    scene_fn = system.scene if system is not None else None
    drawn = scene_fn is not None  # an ODE model has no drawing
    states = list(system.ode.states) if isinstance(system, Model) and system.ode is not None else []
    tables: list[tuple[Any, str, np.ndarray | None, np.ndarray]] = []
    cycles: list[CycleTable | None] = []
    paired = list(orbits)
    for k, source in enumerate(branches):
        cyc = cycle_table(source, k, None, system, values, _full_rows)
        if cyc is not None and cyc.orbit is None and paired and not has_orbits(source):
            cyc = cycle_table(source, k, paired.pop(0), system, values, _full_rows)
        if cyc is not None:
            tables.append((cyc.branch, cyc.name, None, _rows(cyc.branch, int(max_rows))))
            cycles.append(cyc)
            continue
        branch, name = _branch(source, k)
        X = _full_rows(system, branch, name, values) if system is not None else None
        tables.append((branch, name, X, _rows(branch, int(max_rows))))
        cycles.append(None)
    if paired:
        raise InputError("orbits", f"{len(paired)} orbit table(s) beyond the cycles tables (mechcont cycles --out) "
                                   "without orbits to pair with")

    def frame(k: int, row: int) -> list[Any]:  # one period of a cycle row: its scenes (drawn) or its states' values
        cyc = cycles[k]
        assert cyc is not None and cyc.orbit is not None and system is not None
        X = cyc.orbit(row, PAGE_FRAMES if drawn else ORBIT_POINTS)
        if scene_fn is not None:   # drawn
            return [scene_fn(x) for x in X]
        return [[float(v) for v in x[[system.index(s) for s in states]]] for x in X]

    def sample(k: int) -> np.ndarray | None:  # a full vector of table k, for the size of a pose
        cyc, X = cycles[k], tables[k][2]
        if cyc is None:
            return None if X is None else X[0]
        return cyc.orbit(0, 1)[0] if cyc.orbit is not None else None

    probe: dict[str, int] = {}  # any body index: a pose's size does not depend on it
    first = next((x for x in (sample(k) for k in range(len(tables))) if x is not None), None) if system else None
    if scene_fn is not None and first is not None:   # drawn
        probe = {n: 0 for n, _ in scene_fn(first).bars}

    def cycle_bytes(k: int) -> float:  # one row's period in the page
        cyc = cycles[k]
        if cyc is None or cyc.orbit is None or system is None:
            return 0.0
        f = frame(k, len(tables[k][0]) // 2)
        return float(sum(len(json.dumps(pose_json(s, probe) if drawn else s, separators=(",", ":"))) + 1 for s in f))

    sizes = [_row_bytes(branch, system if X is not None else None, X, probe) + cycle_bytes(k)
             for k, (branch, _, X, _) in enumerate(tables)]
    caps = _within_budget([len(rows) for *_, rows in tables], sizes, float(budget))
    for _ in range(8):  # the estimate per row, checked on the page's data and corrected if it was short
        out: list[dict[str, Any]] = []
        all_scenes: list[list[Scene]] = []
        periods: list[list[list[Any]]] = []
        for k, ((branch, name, X, rows), cap) in enumerate(zip(tables, caps)):
            out.append(_document(branch, name, _rows(branch, cap) if cap < len(rows) else rows))
            per: list[list[Any]] = []
            cyc = cycles[k]
            if cyc is not None and cyc.orbit is not None and system is not None:
                per = [frame(k, r) for r in out[-1]["rows"]]
            periods.append(per)
            if scene_fn is not None and X is not None:   # drawn
                all_scenes.append([scene_fn(x) for x in X[out[-1]["rows"]]])
            elif drawn:
                all_scenes.append([s for f in per for s in f])
        used = len(json.dumps(out, separators=(",", ":"))) + 160 * len(out) + sum(  # 160: the note to come
            len(json.dumps(pose_json(s, probe), separators=(",", ":"))) + 1 for scenes in all_scenes for s in scenes)
        if not drawn:
            used += sum(len(json.dumps(per, separators=(",", ":"))) for per in periods)
        if used <= budget or all(len(d["rows"]) <= len(d["special"]) + 2 for d in out):
            break
        shrink = min(0.97 * budget / used, 0.98)  # fewer rows each pass: rows come by whole steps
        caps = [max(2, min(cap - 1, int(min(cap, len(d["rows"])) * shrink))) for cap, d in zip(caps, out)]
    for (branch, _, _, rows), doc in zip(tables, out):
        kept = len(doc["rows"])
        if kept < len(branch):
            step = math.ceil(len(branch) / max(kept - len(branch.special_points), 1))
            why = f"; the page holds at most {budget / 1e6:.3g} MB" if kept < len(rows) else ""
            doc["note"] = f"{kept} of {len(branch)} rows shown (one in {step}, every special point and event{why})"
    for cyc, doc, per in zip(cycles, out, periods):
        if cyc is None:
            continue
        doc["cycle"] = {"states": cyc.states, "frames": len(per[0]) if per else 0}
        doc["units"].update({s: doc["units"].get("max_" + s, "") for s in cyc.states})
        if not per:
            doc["note"] = "; ".join(filter(None, [doc["note"], "the orbits are not in this table (write them with "
                                                  "mechcont cycles --orbits FILE.csv and give it with --orbits)"]))
        elif not drawn:
            doc["orbits"], doc["cycle"]["orbit_states"] = per, states
    data: dict[str, Any] = {"title": title or (system.name if system is not None else ""), "branches": out, "bodies": [],
                  "axes": default_axes(out[0], kinds, cycles[0]) if out else ["", ""],
                  "dim": 2, "views": {}, "force_scale": 0.0, "symbol": 0.0, "view_axes": VIEW_AXES,
                  "load_units": ["m", "N", "N m"]}
    flat = [s for scenes in all_scenes for s in scenes] if drawn else []
    if flat:
        assert system is not None
        colours = _d.body_colours(flat)
        index = {n: i for i, n in enumerate(colours)}
        dim = flat[0].dimension
        scale, views = _limits(flat, dim)
        size = max(max(v[1] - v[0], v[3] - v[2]) for v in views.values())
        data.update(bodies=[{"name": n, "colour": c} for n, c in colours.items()], dim=dim, force_scale=scale,
                    views={v: [float(t) for t in lim] for v, lim in views.items()}, symbol=_d._SYMBOL * size,
                    model=system.name, load_units=[flat[0].units.label(u) for u in ("m", "N", "N m")])
        for doc, scenes, per in zip(out, all_scenes, periods):
            if per:
                doc["poses"] = [[pose_json(s, index) for s in f] for f in per]
            elif "cycle" not in doc:
                doc["poses"] = [pose_json(s, index) for s in scenes]
    return data


def explore_page(model: EquationSystem | str | Path | None, branches: Sequence[_Source], *,
                 values: Mapping[str, float] | None = None, max_rows: int = MAX_ROWS, title: str | None = None,
                 compact: bool = False, budget: float = PAGE_BUDGET,
                 orbits: Sequence[str | os.PathLike[str]] = ()) -> str:
    """The explorer page (HTML text) of ``branches`` of ``model``.

    Parameters
    ----------
    model:
        The model (an :class:`~mechcont.equations.EquationSystem` with a scene), a built-in
        name or description path (see :func:`mechcont.models.load_model`), or None for the
        diagram alone.
    branches:
        Branch, fold-curve or time-history CSV paths (``mechcont continue``/``folds``/
        ``downlock``/``sweep``/``simulate --out``) or :class:`~mechcont.continuation.Branch` objects.
        Each table must hold every variable of the model (or get it from ``values``). A family of
        cycles: a :class:`~mechcont.continuation.CycleBranch` (with its orbits) or a cycles table
        (``mechcont cycles --out``), drawn as its amplitude; a row of it plays one period of the orbit.
    orbits:
        Orbit tables (``mechcont cycles --orbits``), one per cycles CSV in ``branches``, in their order.
    values:
        ``{name: value}`` (SI) set on every row before drawing: variables a table lacks.
    max_rows:
        Rows per branch embedded at most (more are thinned, special points kept; the page says so).
    budget:
        Bytes of embedded data (columns and poses) at most [:data:`PAGE_BUDGET`]: the branches are thinned
        further, by one factor, to fit it (every special point and event kept; the page says so).
    title:
        Page heading [the model's name].
    compact:
        A smaller page (for a notebook's output cell).

    Raises
    ------
    InputError
        Unreadable table, a model variable missing from a table, a unit that is not the model's.
    """
    from ._explore_page import render

    data = page_data(model, branches, values=values, max_rows=max_rows, title=title, budget=budget, orbits=orbits)
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    token = "mcx" + hashlib.sha1(text.encode()).hexdigest()[:10]
    return render(text, token, title=str(data["title"]), compact=compact)


def write_explore(path: str | os.PathLike[str], model: EquationSystem | str | Path | None, branches: Sequence[_Source],
                  **options: Any) -> Path:
    """Write :func:`explore_page` to ``path`` (``.html``) atomically; returns the path. ``options``
    as :func:`explore_page` takes them."""
    from .._io import check_output_path

    out = check_output_path(path, "out", EXPLORE_SUFFIXES)
    assert out is not None
    page = explore_page(model, branches, **options)

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(page)

    return atomic_write(out, write)


def branch_html(branch: Branch) -> str:
    """Jupyter's view of a :class:`~mechcont.continuation.Branch`: the explorer page (compact, at most 600
    rows) in an ``iframe``, with the mechanism drawn when the branch's ``model`` loads as a model of
    its variables (else the diagram alone). ``import mechcont`` registers it with IPython's HTML
    formatter (:func:`mechcont._register_notebook_view`)."""
    import html

    model = None
    try:
        from ..models import load_model

        system = load_model(branch.model) if branch.model else None
        model = system if system is not None and tuple(system.names) == branch.names else None
    except Exception:  # noqa: BLE001 - an unknown or unbuildable model: show the diagram alone
        model = None
    page = explore_page(model, [branch], max_rows=600, compact=True)
    return (f'<iframe srcdoc="{html.escape(page, quote=True)}" style="width:100%;height:760px;border:0" '
            f'title="{html.escape(repr(branch))}"></iframe>')
