"""One path from a value to a model (issue 32, items 1 and 6; issue 33, item 5).

Every command that takes ``--set`` is run on tests/data/spring_lock.toml with ``--set`` of a
geometric value (the spring anchor's height ``h``), a stop's limit (``c_max``) and an element value
(the spring's stiffness ``k``), and on the same file edited to those values: the outputs (printed
numbers, tables, JSON, figures) are the same to rounding, and differ from the unedited file's (so the
values matter to each output compared). The analyses that take values of their own (``optimize
--design``, ``study --grid``, ``sensitivity``) are checked against the closed form of the lock: the
bar rests on its max stop at ``theta = c``, where the stop's reaction is
``R = M0 - F - m g L/2 cos c + k (d - l0) L h cos c / d`` with ``d = |tip - A|`` (the spring's
moment about the pin is ``k (d - l0) L h cos(theta) / d``).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import make_runner, one_line_error

DATA = Path(__file__).parent / "data"
MODEL = DATA / "spring_lock.toml"
#: The values given by --set and written into the edited file: geometry, a stop's limit, an element value.
EDIT = {"h": 0.85, "c_max": 0.25, "k": 25.0}
DEFAULTS = {"h": 0.8, "c_max": 0.3, "k": 20.0}
run = make_runner()

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def stop_reaction(c=0.3, k=20.0, h=0.8, M0=15.0, F=0.0, m=2.0, L=1.0, g=9.81, l0=0.6):
    """The closed form of R_top at rest on the stop (N m)."""
    d = math.hypot(L * math.cos(c), h - L * math.sin(c))
    return M0 - F - m * g * L / 2 * math.cos(c) + k * (d - l0) * L * h * math.cos(c) / d


def edited(folder: Path) -> Path:
    """tests/data/spring_lock.toml with EDIT written into its parameter table."""
    text = MODEL.read_text()
    for name, value in EDIT.items():
        old = f"{name} = {{ value = {DEFAULTS[name]},"
        assert text.count(old) == 1, old
        text = text.replace(old, f"{name} = {{ value = {value},")
    out = folder / "spring_lock_edited.toml"
    out.write_text(text)
    return out


def same_text(a: str, b: str, rtol: float = 1e-6, atol: float = 1e-9) -> bool:
    """Whether ``a`` and ``b`` are the same text with the same numbers (to ``rtol``/``atol``)."""
    if _NUMBER.split(a) != _NUMBER.split(b):
        return False
    x = np.array([float(v) for v in _NUMBER.findall(a)])
    y = np.array([float(v) for v in _NUMBER.findall(b)])
    return len(x) == len(y) and bool(np.allclose(x, y, rtol=rtol, atol=atol))


def sets() -> list[str]:
    return [a for n, v in EDIT.items() for a in ("--set", f"{n}={v}")]


#: Each command with options that make it short; "{out}" is its output file in the run's folder.
COMMANDS = {
    "check": (["check", "{model}"], None),
    "equations": (["equations", "{model}"], None),
    "continue": (["continue", "{model}", "--vary", "F", "--stops", "--start", "angle=0.2", "--bounds", "F=0:20",
                  "--bounds", "theta_bar=-1:1", "--out", "{out}"], "b.csv"),
    "folds": (["folds", "{model}", "--vary", "F", "--along", "M0", "--start", "angle=0.2", "--bounds", "F=0:20",
               "--bounds", "theta_bar=-1.5:1", "--bounds", "M0=14:16", "--out", "{out}"], "f.csv"),
    "downlock": (["downlock", "{model}", "--force", "F", "--vary", "M0", "--bounds", "M0=12:20", "--out", "{out}"],
                 "d.csv"),
    "design": (["design", "{model}", "--vary", "M0", "--across", "m", "--bounds", "M0=5:20", "--bounds", "m=1.5:2.5",
                "--levels", "2", "--out", "{out}"], "g.csv"),
    "sensitivity": (["sensitivity", "{model}", "--downlock", "--params", "c_max,k,h,M0", "--out", "{out}"], "s.json"),
    "optimize": (["optimize", "{model}", "--minimize", "M0", "--design", "M0=5:20", "--constraint", "R_top >= 13",
                  "--out", "{out}"], "o.json"),
    "study": (["study", "{model}", "--grid", "M0=12:16:2", "--dir", "{out}"], "st"),
    "simulate": (["simulate", "{model}", "--start", "theta_bar=0.1", "--until", "0.3", "--stops", "--out", "{out}"],
                 "sim.csv"),
    "sweep": (["sweep", "{model}", "--start", "theta_bar=0.2", "--ramp", "F=0:20:40", "--watch", "theta_bar",
               "--stops", "--out", "{out}"], "sw.csv"),
    "freefall": (["freefall", "{model}", "--start", "angle=-0.3", "--lock", "top", "--until", "1", "--out", "{out}"],
                 "ff.csv"),
    "draw": (["draw", "{model}", "--start", "theta_bar=0.2", "--free", "F", "--out", "{out}"], "w.png"),
}


def _run(command: str, model: Path, folder: Path, extra=()) -> tuple[str, object]:
    """``(stdout with the paths named MODEL and DIR, the output file's contents)``."""
    args, out = COMMANDS[command]
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / out if out else None
    r = run(*[a.format(model=model, out=target) for a in args], *extra)
    assert r.exit_code == 0, r.output
    text = r.stdout.replace(str(model), "MODEL").replace(str(folder), "DIR").replace(model.name, "MODEL")
    text = re.sub(r"; \S+ s$", "", text, flags=re.M)  # a study's time taken
    return text, _read(target)


def _read(target: Path | None):
    if target is None:
        return None
    if target.suffix == ".png":
        import matplotlib.image as mpimg

        return mpimg.imread(target)
    if target.is_dir():
        import pandas as pd

        frame = pd.read_parquet(target / "results.parquet")
        return frame[["M0", "downlock_force"]].to_numpy(dtype=float)
    return target.read_text()


def _same(a, b) -> bool:
    if a is None:
        return b is None
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and bool(np.allclose(a, b, rtol=1e-6, atol=1e-6))
    return same_text(a, b)


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    folder = tmp_path_factory.mktemp("set_everywhere")
    return folder, edited(folder)


@pytest.mark.parametrize("command", list(COMMANDS))
def test_set_equals_the_edited_file(models, command):
    """--set h, c_max, k gives what the file edited to those values gives, and not what the unedited file gives."""
    folder, edited_file = models
    by_set = _run(command, MODEL, folder / command / "set", sets())
    by_file = _run(command, edited_file, folder / command / "file")
    assert _same(by_set[0], by_file[0]), f"stdout:\n{by_set[0]}\n---\n{by_file[0]}"
    assert _same(by_set[1], by_file[1]), f"output:\n{by_set[1]}\n---\n{by_file[1]}"
    unedited = _run(command, MODEL, folder / command / "default")
    assert not (_same(unedited[0], by_file[0]) and _same(unedited[1], by_file[1])), "the edit changes nothing here"


def test_explore_takes_set_values_into_the_rows(models, tmp_path):
    """explore --set fills the columns a table lacks: a table without h, c_max, k with --set draws what the full
    table of the edited file draws."""
    folder, edited_file = models
    full = tmp_path / "full.csv"
    r = run(*[a.format(model=edited_file, out=full) for a in COMMANDS["continue"][0]])
    assert r.exit_code == 0, r.output
    import csv

    with open(full, newline="") as f:
        rows = list(csv.reader(f))
    drop = {i for i, name in enumerate(rows[0]) if name.split(" ")[0] in EDIT}
    assert len(drop) == 3, rows[0]
    lacking = tmp_path / "lacking.csv"
    with open(lacking, "w", newline="") as f:
        csv.writer(f).writerows([[v for i, v in enumerate(row) if i not in drop] for row in rows])
    pages = []
    for model, table, extra in ((MODEL, lacking, sets()), (edited_file, full, [])):
        out = tmp_path / f"{table.stem}.html"
        r = run("explore", model, "--branch", table, "--out", out, *extra)
        assert r.exit_code == 0, r.output
        text = out.read_text()
        data = text[text.index('"poses"'):]
        pages.append(data[:data.index("</script>")].replace(table.name, "TABLE"))  # the page's data
    assert same_text(pages[0], pages[1])


def test_optimize_and_sensitivity_follow_the_stop_limit():
    """optimize --set c_max and --design c_max, sensitivity by c_max: the closed form of the lock."""
    r = run("optimize", MODEL, "--minimize", "M0", "--design", "M0=5:20", "--constraint", "R_top >= 13",
            "--set", "c_max=0.25")
    assert r.exit_code == 0, r.output
    # R_top = M0 + (R at M0 = 15) - 15 >= 13: the least M0
    truth = 13 - (stop_reaction(c=0.25) - 15)
    got = float(re.search(r"^M0 = (\S+)", r.output, re.M).group(1))
    assert got == pytest.approx(truth, rel=1e-8)
    # the stop's limit as a design parameter: R falls as c rises, so the optimum is at the upper bound
    r = run("optimize", MODEL, "--minimize", "k", "--design", "k=5:40", "--design", "c_max=0.1:0.3",
            "--constraint", "R_top >= 13")
    assert r.exit_code == 0, r.output
    c = 0.1
    k_truth = (13 - stop_reaction(c=c, k=0.0)) / (stop_reaction(c=c, k=1.0) - stop_reaction(c=c, k=0.0))
    assert float(re.search(r"^k = (\S+)", r.output, re.M).group(1)) == pytest.approx(k_truth, rel=1e-7)
    assert float(re.search(r"c_max = (\S+)", r.output).group(1)) == pytest.approx(c, abs=1e-9)
    # sensitivity of the downlock force (held at the condition's target c_max) at c_max = 0.25
    r = run("sensitivity", MODEL, "--downlock", "--params", "c_max,h", "--set", "c_max=0.25")
    assert r.exit_code == 0, r.output
    value = float(re.search(r"at F = (\S+)", r.output).group(1))
    assert value == pytest.approx(stop_reaction(c=0.25), rel=1e-9)
    d_c = float(re.search(r"c_max\s+(\S+)", r.output).group(1))
    eps = 1e-5
    fd = (stop_reaction(c=0.25 + eps) - stop_reaction(c=0.25 - eps)) / (2 * eps)
    assert d_c == pytest.approx(fd, rel=1e-7)
    assert abs(d_c) > 1.0


def test_release_sensitivity_by_the_stop_limit():
    """The release load of the lock (F where R_top = 0) at c_max = 0.25, and its derivative by c_max and k, from
    the model at the values: the closed form (a stop's limit is a parameter like any other)."""
    from mechcont.analysis.sensitivity import release_sensitivity
    from mechcont.analysis.stop_lock import locked_on_stops
    from mechcont.models import model_at

    system = model_at(str(MODEL), {"c_max": 0.25})
    x, contact = locked_on_stops(system)
    assert contact == ["top"]
    s = release_sensitivity(system, x, "top", "F", ["c_max", "k"])
    assert s.value == pytest.approx(stop_reaction(c=0.25), rel=1e-9)
    eps = 1e-5
    for name, f in (("c_max", lambda e: stop_reaction(c=0.25 + e)), ("k", lambda e: stop_reaction(c=0.25, k=20 + e))):
        assert s[name] == pytest.approx((f(eps) - f(-eps)) / (2 * eps), rel=1e-7)


def test_study_follows_the_stop_limit(tmp_path):
    """study --grid c_max: each sample's downlock hold (the condition's target c_max) is its own."""
    import pandas as pd

    r = run("study", MODEL, "--grid", "c_max=0.2:0.3:3", "--dir", tmp_path / "st", "--set", "k=25")
    assert r.exit_code == 0, r.output
    df = pd.read_parquet(tmp_path / "st" / "results.parquet")
    for c, F in zip(df["c_max"], df["downlock_force"]):
        assert F == pytest.approx(stop_reaction(c=c, k=25.0), rel=1e-9)


@pytest.mark.parametrize("args, words", [
    (["freefall", "examples/freefall_leg.toml", "--start", "angle=3.0", "--lock", "downlock", "--until", "1",
      "--critical", "U=0:100", "--scan", "c_ret=-1,2"], ["--scan", "damping", "non-negative"]),
    (["freefall", "examples/freefall_leg.toml", "--start", "angle=3.0", "--lock", "downlock", "--until", "1",
      "--critical", "U=0:100", "--scan", "U=1,2"], ["--scan", "U", "bisects"]),
    (["equations", "dual_sidestay_kinematics", "--set", "fwd_L1=-1.15"], ["--set", "fwd_L1", "positive"]),
    (["optimize", str(MODEL), "--minimize", "M0", "--design", "c_d=-1:2"], ["--design", "damping"]),
    (["optimize", str(MODEL), "--maximize", "M0", "--design", "M0=5:20", "--dist", "c_d=normal:-1:0.1",
      "--constraint", "P(not locking) <= 0.01"], ["--dist", "damping"]),
    (["study", str(MODEL), "--dist", "c_d=normal:-1:0.1", "--n", "4", "--dir", "{tmp}/st"], ["--dist", "damping"]),
    (["draw", str(MODEL), "--set", "c_d=-1", "--out", "{tmp}/w.png"], ["--set", "damping"]),
    (["sensitivity", str(MODEL), "--downlock", "--params", "k", "--set", "c_d=-1"], ["--set", "damping"]),
])
def test_values_are_checked_the_same_everywhere(tmp_path, args, words):
    """A value --set refuses is refused in --scan, --design, --dist too; the bisected parameter is not scanned."""
    root = Path(__file__).parent.parent
    r = run(*[a.format(tmp=tmp_path).replace("examples/", f"{root}/examples/") for a in args])
    one_line_error(r, *words)
    assert not (tmp_path / "w.png").exists() and not (tmp_path / "st" / "results.parquet").exists()


def test_model_at_names_and_states():
    """model_at: unknown names refused naming the option; a state's value is a guess (as continue accepted)."""
    from mechcont.errors import InputError
    from mechcont.models import model_at

    with pytest.raises(InputError, match="--set"):
        model_at(str(MODEL), {"c_d": -1.0})
    with pytest.raises(InputError, match="nope"):
        model_at(str(MODEL), {"nope": 1.0})
    m = model_at(str(MODEL), {"theta_bar": 0.1, "c_max": 0.25})
    assert m.variable("theta_bar").value == 0.1 and m.stops[0].limit == 0.25
    assert m.conditions["angle"] == 0.25 and m.downlock.hold == {"angle": 0.25}
    # a zero stiffness: refused by the file's own check, valid for an analysis (continue accepted it)
    assert model_at(str(MODEL), {"k": 0.0}).variable("k").value == 0.0


def free_fold(**kw) -> float:
    """The closed-form fold of the free branch: the largest F that holds the bar off the stop (N m)."""
    from scipy.optimize import minimize_scalar

    found = minimize_scalar(lambda t: -stop_reaction(c=t, **kw), bounds=(-1.5, 0.3), method="bounded",
                            options={"xatol": 1e-12})
    return -float(found.fun)


def test_downlock_prints_the_force_in_its_unit_and_bounds_its_release_run():
    """downlock --force F (a moment): 'F = 0 N m', not 'N'; the release run's reach is an option, and a run that
    stops short says where it stopped and how to go further."""
    r = run("downlock", MODEL, "--force", "F", "--vary", "M0", "--bounds", "M0=14:16")
    assert r.exit_code == 0, r.output
    assert "F = 0 N m, stable" in r.output and "F = 0 N," not in r.output
    lp = float(re.search(r"a fold \(LP\) at F = (\S+) N m", r.output).group(1))
    assert lp == pytest.approx(free_fold(), rel=5e-6)  # printed to 6 digits
    short = run("downlock", MODEL, "--force", "F", "--vary", "M0", "--bounds", "M0=14:16", "--release-span", "0.5")
    assert short.exit_code == 0, short.output
    # F's scale is 20 N m: half of it reaches 10 N m, short of the release at 12.42 N m
    assert "no fold increasing F within the release run (F moved by 0.5 of its scales, to 10 N m; a larger " \
           "--release-span searches further)" in short.output
    one_line_error(run("downlock", MODEL, "--force", "F", "--vary", "M0", "--bounds", "M0=14:16", "--release-span",
                       "0"), "--release-span")


def test_sweep_starts_on_the_stops_and_compares_only_held_parameters(tmp_path):
    """sweep --stops starts from the equilibrium on the stops (its free equilibrium solve put the start past the
    limit: 'past the limit' for a start the user gave on the stop); --branch does not take a stop's reaction,
    solved along the branch, for a value the branch was continued at, and still names a parameter set otherwise."""
    branch = tmp_path / "b.csv"
    r = run(*[a.format(model=MODEL, out=branch) for a in COMMANDS["continue"][0]])
    assert r.exit_code == 0, r.output
    sweep = ["sweep", MODEL, "--start", "theta_bar=0.2", "--ramp", "F=0:20:80", "--watch", "theta_bar", "--stops",
             "--branch", branch]
    r = run(*sweep)
    assert r.exit_code == 0, r.output
    assert "continued at other parameter values" not in r.output
    release = float(re.search(r"release  top  at F = (\S+) N m", r.output).group(1))
    assert release == pytest.approx(stop_reaction(), rel=2e-3)  # a ramp of 80 N m/s lags the quasi-static release
    r = run(*sweep, "--no-equilibrium")  # at rest at theta = 0.2, below the stop: no reaction on the branch compared
    assert r.exit_code == 0 and "continued at other parameter values" not in r.output, r.output
    r = run(*sweep, "--set", "k=25")
    assert "continued at other parameter values: k = 20 N/m (sweep 25 N/m)" in r.output
    one_line_error(run("sweep", MODEL, "--start", "theta_bar=0.35", "--ramp", "F=0:20:80", "--watch", "theta_bar",
                       "--stops", "--no-equilibrium"), "--start", "past the limit")


def test_design_levels_of_the_stop_limit():
    """design --across c_max: each level's downlock hold (the condition's target c_max) is its own (the closed form)."""
    r = run("design", MODEL, "--vary", "M0", "--across", "c_max", "--bounds", "M0=5:20", "--bounds", "c_max=0.2:0.3",
            "--levels", "2")
    assert r.exit_code == 0, r.output
    rows = [ln.split("|") for ln in r.output.splitlines() if re.match(r"\| 0\.[23] \|", ln)]
    assert [float(row[1]) for row in rows] == [0.2, 0.3]
    for row in rows:
        assert float(row[2]) == pytest.approx(stop_reaction(c=float(row[1])), rel=5e-6)  # printed to 6 digits
