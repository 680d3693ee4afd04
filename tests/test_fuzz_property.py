"""Property-based fuzzing of the CLI contract (issue 20).

For any command line or study spec drawn here, mechcont either exits 0 with finite results,
or exits 2 with exactly one line ``error: ...`` on stderr, no traceback, and nothing written.
Few examples per strategy (the whole file runs in well under 30 s); the strategies mix ordinary
values with the fuzz campaign's kinds of trouble (non-finite and huge numbers, digits beyond the
integer conversion limit, keywords, empty items, control characters).
"""

import csv
import math
import tempfile
from pathlib import Path

import pytest
from cli_helpers import make_runner
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

run = make_runner()
FEW = settings(max_examples=10, deadline=None, derandomize=True,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

NUMBER_TEXT = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(-2.0, 2.0).map(repr),
    st.sampled_from(["1e308", "-1e308", "1e-320", "nan", "inf", "", "abc", "1" + "0" * 4400, "0x10", "1_000"]),
)


def _contract(result, folder: Path, made=()) -> bool:
    """The CLI contract; True when the command succeeded (exit 0)."""
    text = result.output + (result.stderr or "")
    event(f"exit {result.exit_code}")  # --hypothesis-show-statistics: both outcomes are exercised
    assert "Traceback" not in text and "RuntimeWarning" not in text, text[-2000:]
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    if result.exit_code == 0:
        return True
    assert result.exit_code == 2, (result.exit_code, text[-2000:])
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    left = sorted(p.name for p in folder.iterdir())
    assert left == sorted(made), left  # nothing half-written
    return False


def _finite_csv(path: Path) -> None:
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows
    for row in rows:
        for key, cell in row.items():
            if key not in ("stability", "label", "vary"):
                assert math.isfinite(float(cell)), (key, cell)


@FEW
@given(
    sets=st.lists(st.tuples(st.sampled_from(["L1", "k", "LU", "m1", "c", "theta2", "lambda", "nope"]), NUMBER_TEXT),
                  max_size=2),
    start=st.one_of(st.floats(-1.5, 1.5).map(repr), NUMBER_TEXT),
    max_steps=st.one_of(st.integers(-2, 60), st.sampled_from([10**5 + 1, 999999999999])),
    ds=st.one_of(st.none(), st.sampled_from(["0.01", "0", "-1", "nan", "1e300"])),
)
def test_continue_contract(sets, start, max_steps, ds):
    with tempfile.TemporaryDirectory() as d:
        folder = Path(d)
        out = folder / "b.csv"
        args = ["continue", "overcentre", "--start", f"theta1={start}", "--vary", "F", "--bounds", "theta1=-1.2:1.2",
                "--max-steps", str(max_steps), "--out", out, "--quiet"]
        for name, value in sets:
            args += ["--set", f"{name}={value}"]
        if ds is not None:
            args += ["--ds", ds]
        if _contract(run(*args), folder):
            _finite_csv(out)


DIST = st.one_of(
    st.sampled_from(["normal:1.3:0.01", "uniform:1.25:1.35", "truncnormal:1.3:0.01:1.28:1.32"]),
    st.sampled_from(["normal:1.3:0", "uniform:2:1", "gauss:1:2", "normal:nan:1", "normal:1.3", "", ":", "normal:1e400:1"]),
)


@FEW
@given(
    n=st.one_of(st.integers(1, 12), st.sampled_from([0, -3, 10**7 + 1, 10**30, 1.5, "7", True, float("inf")])),
    chunk=st.one_of(st.none(), st.integers(1, 8), st.sampled_from([0, -1, 2**40, 10**6])),
    seed=st.one_of(st.integers(0, 2**32), st.sampled_from([-1, 2**64])),
    dist=DIST,
    extra=st.sampled_from(["", 'analyses = ["downlock"]\n', 'analyses = "downlock"\n', 'analyses = ["nope"]\n',
                           "unknown = 1\n", "[set]\nU = 10.0\n", "[set]\nLU = 1.3\n", "[hold]\nlambda = 1\n"]),
)
def test_study_spec_contract(n, chunk, seed, dist, extra):
    pytest.importorskip("pyarrow")

    def toml(v):
        return "inf" if v == float("inf") else ("true" if v is True else (f'"{v}"' if isinstance(v, str) else repr(v)))

    with tempfile.TemporaryDirectory() as d:
        folder = Path(d)
        spec = folder / "spec.toml"
        body = f'sampling = "mc"\nn = {toml(n)}\nseed = {seed}\n'
        if chunk is not None:
            body += f"chunk = {chunk}\n"
        top, _, table = extra.partition("[")
        body += top + f'[parameters]\nLU = "{dist}"\n' + (f"[{table}" if table else "")
        spec.write_text(body)
        out = folder / "s"
        r = run("study", "nose_gear", "--spec", spec, "--out", out, "--scheduler", "serial", "--quiet")
        if _contract(r, folder, made=["spec.toml"]):
            import pyarrow.parquet as pq

            t = pq.read_table(out / "results.parquet").to_pandas()
            assert len(t) == n and list(t["sample"]) == list(range(n))
            ok = t["status"] == "converged"
            assert t.loc[ok, "downlock_force"].map(math.isfinite).all() and t["LU"].map(math.isfinite).all()


@FEW
@given(value=NUMBER_TEXT, key=st.sampled_from(["k = { value = 127.0", 'mass = "m1"', "LU = { value = 0.4"]))
def test_description_number_contract(value, key):
    from mechcont.mechanism import find_description

    text = find_description("overcentre").read_text()
    if key.startswith("mass"):
        new = f'mass = "{value}"' if value and not value[0].isdigit() else f"mass = {value or 1}"
    else:
        new = key.split("=")[0] + f"= {{ value = {value or 'nan'}"
    with tempfile.TemporaryDirectory() as d:
        folder = Path(d)
        path = folder / "m.toml"
        path.write_text(text.replace(key, new, 1))
        _contract(run("equations", path), folder, made=["m.toml"])
