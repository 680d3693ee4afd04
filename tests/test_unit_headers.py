"""A description written in other units says so in every header: the generated names (coordinates,
reactions, velocities, the energy audit) are labelled in the units their values are in.

Truth: the overcentre (src/mechcont/data/overcentre.toml) written in SI and again in mm and g (and in mm
and t, where a force is a newton) by tests/corpus/scaling.py, which declares the new units
(``[mechanism] units``). The same command on both files must write tables whose every column agrees
after each value is converted to SI by its own header's unit, read here by an independent parser (a
small table of prefixes and base units, not mechcont's). A header that named SI for a value in mm would
be off by 1e3 and fail. Tolerances: continuation and folds are solved to Newton's tolerance relative to
each variable's scale, which scales with the units (1e-9 of the largest magnitude of its kind: a reaction
that is zero in truth is the rounding of the other forces); a simulation (rtol 1e-8, its error growing
over its steps) is compared at the instants both histories have, its start and end, to 1e-6.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import csv_rows, make_runner
from corpus.scaling import write_scaled

from mechcont.units import dimension

ROOT = Path(__file__).parents[1]
OVERCENTRE = ROOT / "src" / "mechcont" / "data" / "overcentre.toml"
#: base symbols as (factor to SI, (length, mass, time, angle) exponents)
_BASE = {"m": (1.0, (1, 0, 0, 0)), "g": (1e-3, (0, 1, 0, 0)), "t": (1e3, (0, 1, 0, 0)), "s": (1.0, (0, 0, 1, 0)),
         "N": (1.0, (1, 1, -2, 0)), "J": (1.0, (2, 1, -2, 0)), "rad": (1.0, (0, 0, 0, 1)), "1": (1.0, (0, 0, 0, 0))}
_PREFIX = {"": 1.0, "k": 1e3, "c": 1e-2, "m": 1e-3, "u": 1e-6}


def _token(tok: str) -> tuple[float, list[int]]:
    name, _, power = tok.partition("^")
    n = int(power) if power else 1
    for pre, f in _PREFIX.items():
        if name.startswith(pre) and name[len(pre):] in _BASE:
            base, dim = _BASE[name[len(pre):]]
            return (f * base) ** n, [d * n for d in dim]
    raise AssertionError(f"unit symbol {tok!r} does not parse")


def si(unit: str) -> tuple[float, tuple[int, ...]]:
    """The factor to SI and the (length, mass, time, angle) exponents of a header's unit, e.g.
    ``"g mm^2/(s^2 rad)"`` -> (1e-9, (2, 1, -2, -1)): the factors before the first ``/`` outside
    parentheses over those after it, a parenthesised group read the same way. Fails on a unit it cannot read."""
    groups: list[str] = []

    def hide(m: re.Match) -> str:  # innermost groups first, each replaced by a placeholder
        groups.append(m.group(1))
        return f"@{len(groups) - 1}"

    text = unit
    while "(" in text:
        new = re.sub(r"\(([^()]*)\)", hide, text)
        assert new != text, f"{unit!r}: unbalanced parentheses"
        text = new
    assert ")" not in text, f"{unit!r}: unbalanced parentheses"

    def quotient(t: str) -> tuple[float, list[int]]:
        num, _, den = t.partition("/")
        factor, dim = 1.0, [0, 0, 0, 0]
        for part, sign in ((num, 1), (den, -1)):
            for tok in part.split():
                f, d = quotient(groups[int(tok[1:])]) if tok.startswith("@") else _token(tok)
                factor *= f ** sign
                dim = [a + sign * b for a, b in zip(dim, d)]
        return factor, dim

    factor, dim = quotient(text)
    return factor, tuple(dim)


def _columns(path: Path) -> dict[str, tuple[str, np.ndarray | list[str]]]:
    """``{name: (unit, values)}`` of a CSV table with ``name [unit]`` headers (text columns as text)."""
    rows = csv_rows(path)
    out: dict[str, tuple[str, np.ndarray | list[str]]] = {}
    for head in rows[0]:
        m = re.fullmatch(r"(\S+) \[(.+)\]", head)
        name, unit = (m.group(1), m.group(2)) if m else (head, "")
        texts = [r[head] for r in rows]
        try:
            out[name] = (unit, np.array([float(x) for x in texts]))
        except ValueError:
            out[name] = (unit, texts)
    return out


def assert_same_tables(si_path: Path, other_path: Path, rtol: float, rows: slice = slice(None)) -> None:
    """Every column of both tables (their ``rows``) agrees once converted to SI by its header's unit; the
    headers name the same physical dimension and parse as units."""
    a, b = _columns(si_path), _columns(other_path)
    assert list(a) == list(b)
    a = {k: (u, v[rows]) for k, (u, v) in a.items()}
    b = {k: (u, v[rows]) for k, (u, v) in b.items()}
    converted = {}
    for name, (ua, va) in a.items():
        ub, vb = b[name]
        if isinstance(va, list) or isinstance(vb, list):
            assert va == vb, name
            continue
        assert len(va) == len(vb), name
        fa, da = si(ua) if ua else (1.0, (0, 0, 0, 0))
        fb, db = si(ub) if ub else (1.0, (0, 0, 0, 0))
        assert da == db, f"{name}: [{ua}] and [{ub}] are different quantities"
        converted[name] = (da, va * fa, vb * fb, f"{name} [{ua}] vs [{ub}]")
    # a value is exact to the rounding of the largest of its kind (a reaction that is zero in truth is
    # rounding noise of the other forces)
    sizes: dict[tuple[int, ...], float] = {}
    for dim, x, _, _ in converted.values():
        sizes[dim] = max(sizes.get(dim, 0.0), float(np.max(np.abs(x), initial=0.0)))
    # at a fold the critical eigenvalue is zero: whether it counts as unstable there is rounding's choice
    exact = np.array([not str(label).startswith("LP") for label in a.get("label", ("", []))[1]] or [True] * len(x))
    for name, (dim, x, y, what) in converted.items():
        keep = exact if name == "n_unstable" else np.ones(len(x), bool)
        np.testing.assert_allclose(y[keep], x[keep], rtol=0, atol=rtol * sizes[dim] + 1e-300, err_msg=what)


def test_the_header_parser():
    """The test's own reader of units: a few labels and their SI factors by hand."""
    assert si("mm") == (1e-3, (1, 0, 0, 0))
    f, d = si("g mm^2/(s^2 rad)")
    assert math.isclose(f, 1e-9) and d == (2, 1, -2, -1)
    f, d = si("N mm/rad")
    assert math.isclose(f, 1e-3) and d == (2, 1, -2, -1)
    f, d = si("(g mm/s^2)/(g/s^2)")
    assert math.isclose(f, 1e-3) and d == (1, 0, 0, 0)
    assert si("N/(N/m)") == (1.0, (1, 0, 0, 0))
    with pytest.raises(AssertionError):
        si("N/(N/m")


@pytest.fixture(scope="module")
def overcentres(tmp_path_factory):
    """The overcentre in SI, in mm and g, and in mm and t: ``{name: (path, force factor from SI)}``."""
    d = tmp_path_factory.mktemp("units")
    return {"si": (write_scaled(OVERCENTRE, d / "si.toml", 1.0, 1.0), 1.0),
            "mm-g": (write_scaled(OVERCENTRE, d / "mmg.toml", 1e3, 1e3, labels=True), 1e6),
            "mm-t": (write_scaled(OVERCENTRE, d / "mmt.toml", 1e3, 1e-3, labels=True), 1.0)}


@pytest.fixture(scope="module")
def branches(overcentres, tmp_path_factory):
    """`continue` in F of each overcentre: ``{name: branch table}``."""
    d, run, out = tmp_path_factory.mktemp("branches"), make_runner(), {}
    for name, (path, force) in overcentres.items():
        out[name] = d / f"{name}.csv"
        r = run("continue", path, "--start", "theta1=0.3", "--vary", "F", "--bounds",
                f"F={-100 * force}:{120 * force}", "--out", out[name])
        assert r.exit_code == 0, r.output
    return out


@pytest.mark.parametrize("units", ["mm-g", "mm-t"])
def test_continue_tables_agree_by_their_headers(branches, units):
    """`continue` in F: every column (coordinates, reactions, parameters, arclength, labels) of the
    file in other units is the SI table's once read in its own headers' units."""
    out = branches
    assert_same_tables(out["si"], out[units], rtol=1e-9)
    heads = _columns(out[units])
    assert heads["R_pin_x"][0] == ("g mm/s^2" if units == "mm-g" else "N") and heads["x1"][0] == "mm"


def test_fold_tables_agree_by_their_headers(overcentres, tmp_path):
    """`folds`: the overcentre's first fold continued in LU, in SI and in mm and g."""
    run = make_runner()
    out = {}
    for name in ("si", "mm-g"):
        path, force = overcentres[name]
        length = 1.0 if name == "si" else 1e3
        out[name] = tmp_path / f"{name}.csv"
        r = run("folds", path, "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
                "--bounds", f"LU={0.1 * length}:{2 * length}", "--bounds", f"F={-300 * force}:{300 * force}",
                "--out", out[name])
        assert r.exit_code == 0, r.output
    assert_same_tables(out["si"], out["mm-g"], rtol=1e-9)


def test_simulate_tables_agree_by_their_headers(overcentres, tmp_path):
    """`simulate`: the history (coordinates, reactions, velocities, the energy audit) of a fall from
    theta1 = 1.2 rad, in SI and in mm and g; the printed energy line names the file's unit."""
    run = make_runner()
    out, printed = {}, {}
    for name in ("si", "mm-g"):
        path, _ = overcentres[name]
        out[name] = tmp_path / f"{name}.csv"
        r = run("simulate", path, "--start", "theta1=1.2", "--until", "0.5", "--out", out[name], "--no-progress")
        assert r.exit_code == 0, r.output
        printed[name] = r.output
    # the integrator's steps depend on the numbers' sizes (its first step, an absolute tolerance): the rows
    # at the same instants are the first and the last (t = 0 and 0.5 s)
    assert_same_tables(out["si"], out["mm-g"], rtol=1e-6, rows=slice(0, 1))
    assert_same_tables(out["si"], out["mm-g"], rtol=1e-6, rows=slice(-1, None))
    heads = _columns(out["mm-g"])
    assert heads["E_kin"][0] == "g mm^2/s^2" and heads["x1_dot"][0] == "mm/s"
    assert "energy [g mm^2/s^2]:" in printed["mm-g"] and "energy [J]:" in printed["si"]


#: SI labels the generated names carry, with their (length, mass, time) dimension
SI_LABELS = {"m": (1, 0, 0), "N": (1, 1, -2), "N m": (2, 1, -2), "J": (2, 1, -2), "m/s": (1, 0, -1),
             "N/m": (0, 1, -2), "N m/rad": (2, 1, -2), "kg m^2": (2, 1, 0), "N s/m": (0, 1, -1), "kg": (0, 1, 0),
             "N m s/rad": (2, 1, -1), "m/s^2": (1, 0, -2), "1/m": (-1, 0, 0)}


@pytest.mark.parametrize(("length", "mass", "L", "M"), [("mm", "g", 1e-3, 1e-3), ("mm", "t", 1e-3, 1e3),
                                                         ("km", "kg", 1e3, 1.0), ("um", "mg", 1e-6, 1e-6)])
def test_a_label_in_other_units_is_worth_what_a_number_in_them_is(length, mass, L, M):
    """A quantity of dimension length^a mass^b time^c written in units of ``L`` metres and ``M`` kilograms is
    the SI number / (L^a M^b): its label's SI factor (read by this test's parser) must be L^a M^b, with the
    same dimension and the same power of rad."""
    from mechcont.units import UnitSystem

    units = UnitSystem(length, mass)
    for si_label, (a, b, c) in SI_LABELS.items():
        label = units.label(si_label)
        factor, dim = si(label)
        assert math.isclose(factor, L ** a * M ** b, rel_tol=1e-12), (si_label, label)
        assert dim == (a, b, c, si_label.count("rad") * -1), (si_label, label)
    assert units.label("rad") == "rad" and units.label("") == "" and units.label("rad/s") == "rad/s"


def test_newtons_where_the_units_make_them():
    """mm and t: a force is exactly a newton, so the labels say N, N mm, N/mm; a mass stays t."""
    from mechcont.units import UnitSystem

    units = UnitSystem("mm", "t")
    assert [units.label(u) for u in ("N", "N m", "N/m", "kg", "kg m^2", "N s/m")] == \
        ["N", "N mm", "N/mm", "t", "t mm^2", "N s/mm"]


@pytest.mark.parametrize(("units", "words"), [
    ('{ length = "inch" }', ["mechanism.units.length", "'mm'"]),
    ('{ mass = 3 }', ["mechanism.units.mass", "'kg'"]),
    ('{ time = "ms" }', ["mechanism.units.time", "unknown key", "length, mass"]),
    ('"mm"', ["mechanism.units", "must be a table"]),
])
def test_bad_units_are_one_line(tmp_path, units, words):
    """A declaration of units mechcont does not know is refused in one line naming the key, exit 2."""
    from cli_helpers import one_line_error

    text = OVERCENTRE.read_text().replace("[mechanism]\n", f"[mechanism]\nunits = {units}\n", 1)
    assert text != OVERCENTRE.read_text()
    path = tmp_path / "bad.toml"
    path.write_text(text)
    one_line_error(make_runner()("check", path), *words)


def test_sensitivities_agree_by_their_units(overcentres, branches, tmp_path):
    """`sensitivity` at the fold LP1: each derivative (printed and in the JSON) names a unit that parses, and
    converted by it to SI is the SI file's (the derivatives are exact: to 1e-8)."""
    import json

    run, found = make_runner(), {}
    for name in ("si", "mm-g"):
        out = tmp_path / f"{name}.json"
        r = run("sensitivity", overcentres[name][0], "--point", f"{branches[name]}:LP1", "--params", "LU,k,m1",
                "--out", out)
        assert r.exit_code == 0, r.output
        found[name] = json.loads(out.read_text())
    for p in ("LU", "k", "m1"):
        (fa, da), (fb, db) = si(found["si"]["units"][p]), si(found["mm-g"]["units"][p])
        assert da == db, p
        assert dimension(found["mm-g"]["units"][p]) == db[:3], p  # mechcont's own reader agrees
        assert found["mm-g"][p] * fb == pytest.approx(found["si"][p] * fa, rel=1e-8), p
    assert found["mm-g"]["units"]["LU"] == "mm g/(s^2 mm)"


def test_drawings_and_the_explorer_say_the_units(overcentres, branches):
    """The drawing's axes and load labels, and the explorer's, in the file's units: mm, g mm/s^2."""
    from mechcont.mechanism import load
    from mechcont.outputs.drawing import draw_scene
    from mechcont.outputs.explore import page_data

    path, force = overcentres["mm-g"]
    model = load(path, F=5.0 * force)
    ax = draw_scene(model.scene(model.defaults()))
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (mm)", "y (mm)")
    texts = [t.get_text() for t in ax.texts]
    assert "F = 5e+06 g mm/s^2" in texts, texts  # 5 N in g mm/s^2, no SI prefix on grams
    data = page_data(model, [branches["mm-g"]])
    assert data["load_units"] == ["mm", "g mm/s^2", "g mm^2/s^2"]
    assert data["branches"][0]["units"]["x1"] == "mm"


def test_check_warns_of_parameters_labelled_in_undeclared_units(overcentres, tmp_path):
    """A file whose parameters say mm but that declares no units gets one warning naming the parameter and
    the declaration; declared, or in SI, it gets none."""
    run = make_runner()
    path, _ = overcentres["mm-g"]
    undeclared = tmp_path / "undeclared.toml"
    undeclared.write_text(re.sub(r"^units = .*\n", "", path.read_text(), flags=re.M))
    assert "units" not in undeclared.read_text().split("[parameters]")[0]
    r = run("check", undeclared)
    assert r.exit_code == 0, r.output
    (line,) = [ln for ln in r.output.splitlines() if "labelled" in ln]
    assert "parameters.L1 is labelled 'mm'" in line and "units = { length" in line
    for good in (path, overcentres["si"][0]):
        r = run("check", good)
        assert r.exit_code == 0 and "labelled" not in r.output, r.output


def test_design_tables_agree_by_their_headers(tmp_path):
    """`design` on the pendulum downlock (tests/data/pendulum_downlock.toml: F = M0 - m g L/2 cos 0.3, a
    moment) in SI and in mm and g: every number of every column, read in its header's unit, is the SI
    table's (the lengths where F > 0 are printed to 4 digits, the rest to 1e-9); and an interval that
    ends at its bound ends there in both (its end at the rounding of the bound is no F = 0 crossing)."""
    run = make_runner()
    src = ROOT / "tests" / "data" / "pendulum_downlock.toml"
    tables = {}
    for name, L, M in (("si", 1.0, 1.0), ("mm-g", 1e3, 1e3)):
        path = write_scaled(src, tmp_path / f"{name}.toml", L, M, labels=True)
        moment = L * L * M
        out = tmp_path / f"{name}.csv"
        r = run("design", path, "--bounds", f"L={0.5 * L}:{1.5 * L}", "--bounds", f"M0={10 * moment}:{20 * moment}",
                "--levels", "3", "--out", out)
        assert r.exit_code == 0, r.output
        tables[name] = csv_rows(out)
    a, b = tables["si"], tables["mm-g"]
    assert len(a) == len(b) == 3
    for ha, hb in zip(a[0], b[0]):
        ua, ub = (re.search(r"\(([^()]*(?:\([^()]*\)[^()]*)*)\)$", h) for h in (ha, hb))
        (fa, da), (fb, db) = (si(u.group(1)) if u else (1.0, (0, 0, 0, 0)) for u in (ua, ub))
        assert da == db, (ha, hb)
        for ra, rb in zip(a, b):
            na = [float(v) for v in re.findall(r"[-+]?\d[\d.]*(?:e[-+]?\d+)?", ra[ha].replace("..", " "))]
            nb = [float(v) for v in re.findall(r"[-+]?\d[\d.]*(?:e[-+]?\d+)?", rb[hb].replace("..", " "))]
            assert len(na) == len(nb), (ha, ra[ha], rb[hb])
            rel = 5e-4 if ".." in ra[ha] else 1e-9
            for x, y in zip(na, nb):
                assert y * fb == pytest.approx(x * fa, rel=rel, abs=1e-12), (ha, ra[ha], rb[hb])


def test_a_study_labels_its_force_in_the_force_parameters_unit(tmp_path):
    """`study` of the pendulum downlock (a moment, F = M0 - m g L/2 cos 0.3) in mm and g: its downlock_force
    column is labelled as F is (g mm^2/s^2, which the old table called N) and is the SI answer in it."""
    pytest.importorskip("pyarrow")
    from mechcont.analysis.study import read_results

    src = ROOT / "tests" / "data" / "pendulum_downlock.toml"
    path = write_scaled(src, tmp_path / "mmg.toml", 1e3, 1e3, labels=True)
    r = make_runner()("study", path, "--grid", "M0=1e10:2e10:2", "--dir", tmp_path / "st")
    assert r.exit_code == 0, r.output
    df = read_results(tmp_path / "st" / "results.parquet")
    unit = df.attrs["units"]["downlock_force"]
    factor, dim = si(unit)
    assert dim == (2, 1, -2, 0), unit
    truth = np.array([10.0, 20.0]) - 2.0 * 9.81 * 0.5 * math.cos(0.3)  # N m, in SI
    np.testing.assert_allclose(df["downlock_force"].to_numpy() * factor, truth, rtol=1e-9)


def test_a_loop_that_cannot_close_says_its_gap_in_the_files_length(tmp_path):
    """The fourbar with its ground link d = 2.0 m (a + b + c = 1.7 m) misses by 0.3 m; written in mm and g
    the message says 300 mm."""
    from mechcont.errors import InputError
    from mechcont.mechanism import find_description, load_description

    src = tmp_path / "bad.toml"
    src.write_text(find_description("fourbar").read_text().replace("d = { value = 0.7", "d = { value = 2.0")
                   .replace("[assembly]\nhold = { theta_crank = 1.2 }", ""))
    path = write_scaled(src, tmp_path / "mmg.toml", 1e3, 1e3, labels=True)
    with pytest.raises(InputError) as info:
        load_description(path).build()
    gap = float(re.search(r"misses by ([0-9.eE+-]+) mm at best", str(info.value)).group(1))
    assert gap == pytest.approx(300.0, rel=1e-6)
