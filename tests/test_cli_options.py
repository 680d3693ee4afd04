"""One meaning per option name across the commands (issues 21, item 4, and 34, item 4), and the old spellings kept
for scripts.

``--free`` names a parameter solved for, ``--out`` a file, ``--quiet`` prints nothing but errors, ``--start`` a state
held at a value to find where a command starts (the first solution, the drawn equilibrium, the pose a simulation or
freefall starts from at rest), ``--hold`` a state held during the analysis, ``--vary`` the continuation parameter (of
the run, or of the branch read), ``--set`` a parameter's value, ``--point`` a row of a branch table, ``--branch`` a
branch table, in every command that has them; the spellings they replaced (``folds --free P2`` and ``--solve-for``,
``design --x/--y``, ``paper``/``study --out DIR``, ``freefall --from``, ``study --analysis freefall --hold``) still
work, hidden from the help. (``simulate``/``sweep``/``animate --quiet``, once a hidden ``--no-progress``, now print
nothing but errors as everywhere: tests/test_quiet_option.py.)
"""

import re

import click
import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.cli._app import _register, cli
from mechcont.continuation import read_branch_table


@pytest.fixture(scope="module")
def run():
    return make_runner()


def _visible_options() -> dict[str, list[tuple[str, click.Option]]]:
    """``{option: [(command, its click.Option), ...]}`` over every command, hidden options left out."""
    _register()
    found: dict[str, list[tuple[str, click.Option]]] = {}
    for name, command in cli.commands.items():
        for p in command.params:
            if isinstance(p, click.Option) and not p.hidden:
                for opt in p.opts:
                    found.setdefault(opt, []).append((name, p))
    return found


def test_each_shared_option_name_has_one_meaning():
    options = _visible_options()
    for command, p in options["--free"]:
        assert "solved for" in (p.help or ""), (command, p.help)
    for command, p in options["--out"]:
        text = f"{p.help or ''} {p.metavar or ''}".lower()
        assert "folder" not in text and "dir" not in text.split(), (command, p.help, p.metavar)
    for command, p in options["--quiet"]:
        assert (p.help or "").startswith("Print nothing but errors"), (command, p.help)
    assert {c for c, _ in options["--x"]} == {"continue"}  # a plot axis; design's parameters are --vary/--across
    assert {c for c, _ in options["--across"]} == {"design"}
    assert {c for c, _ in options["--dir"]} == {"paper", "study"}
    assert {c for c, _ in options["--no-progress"]} == {"simulate", "sweep", "animate", "freefall"}
    for command, p in options["--no-progress"]:
        assert (p.help or "").startswith("No progress bar"), (command, p.help)
    assert "--solve-for" not in options
    # --method names the numerical method a command computes with, its values listed: the integrator of the time
    # simulations (SciPy's names), the reliability method of study; --rtol/--atol are the integrator's tolerances
    assert {c for c, _ in options["--method"]} == {"simulate", "sweep", "freefall", "study"}
    for command, p in options["--method"]:
        assert "|" in (p.metavar or "") and ("Integrator method" in (p.help or "")) == (command != "study"), command
    for option in ("--rtol", "--atol"):
        assert {c for c, _ in options[option]} == {"simulate", "sweep", "freefall"}
        assert all((p.help or "").startswith("Integrator ") for _, p in options[option])


def _fold_curve(run, tmp_path, name, *spelling):
    out = tmp_path / f"{name}.csv"
    r = run("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", *spelling,
            "--bounds", "LU=0.1:2", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    return r, read_branch_table(out)[0]


def test_folds_old_spelling_of_the_second_parameter_still_works_with_a_note(run, tmp_path):
    new, rows = _fold_curve(run, tmp_path, "new", "--along", "LU")
    old, rows_old = _fold_curve(run, tmp_path, "old", "--free", "LU")
    assert new.stderr == "" and "--along LU" in old.stderr and len(old.stderr.splitlines()) == 1
    assert rows_old == rows  # the same run, the same table


def test_folds_free_is_a_parameter_solved_for(run, tmp_path):
    # without --along nothing names the second parameter ...
    one_line_error(run("folds", "overcentre", "--set", "LU=0.4", "--vary", "F", "--bounds", "LU=0.1:2"), "--along")
    # ... and --free with --hold is read as a parameter solved for, as in continue (not as P2)
    r = run("folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--hold", "theta1",
            "--free", "LU", "--bounds", "LU=0.1:2")
    one_line_error(r, "--along")


def test_study_folder_old_and_new_spelling(run, tmp_path):
    args = ("study", "nose_gear", "--grid", "LU=1.29:1.31:2", "--scheduler", "serial", "--quiet")
    assert run(*args, "--dir", tmp_path / "a").exit_code == 0
    assert run(*args, "--out", tmp_path / "b").exit_code == 0
    assert (tmp_path / "a" / "results.parquet").exists() and (tmp_path / "b" / "results.parquet").exists()
    one_line_error(run(*args, "--dir", tmp_path / "a"), "--dir", "--resume")  # the error names the spelling given
    one_line_error(run(*args, "--out", tmp_path / "b"), "--out", "--resume")
    one_line_error(run(*args, "--dir", tmp_path / "c", "--out", tmp_path / "d"), "--dir", "not both")
    one_line_error(run(*args), "--dir")


def test_design_parameters_old_and_new_spelling(run):
    args = ("design", "lockstay.toml", "--bounds", "k=5000:40000", "--bounds", "Sy=-0.1:0.1", "--levels", "2")
    new = run(*args, "--vary", "k", "--across", "Sy")
    old = run(*args, "--x", "k", "--y", "Sy")
    assert new.exit_code == 0 and old.exit_code == 0, new.output
    assert new.output == old.output
    one_line_error(run(*args, "--vary", "k", "--across", "k"), "--across", "must differ from --vary")
    one_line_error(run(*args, "--x", "k", "--y", "k"), "--y", "must differ from --x")
    one_line_error(run(*args, "--vary", "k", "--x", "k"), "--vary", "not both")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def test_continue_hold_takes_a_value_as_downlock_does(run, tmp_path):
    """``--hold NAME=VALUE`` holds the state at VALUE (as in downlock/design/study); ``--hold NAME`` at its
    value in the start solve. Checked against the library run with the same state held and F solved for."""
    import numpy as np

    from mechcont.continuation import continuation, find_equilibrium, run_options
    from mechcont.models import load_model

    args = ("continue", "nose_gear", "--free", "F", "--vary", "LU", "--bounds", "LU=1.25:1.35", "--quiet")
    assert run(*args, "--hold", "theta4=0.01", "--out", tmp_path / "v.csv").exit_code == 0
    assert run(*args, "--hold", "theta4=0", "--out", tmp_path / "z.csv").exit_code == 0
    assert run(*args, "--hold", "theta4", "--out", tmp_path / "n.csv").exit_code == 0  # the default, 0
    def table(k):
        rows, _ = read_branch_table(tmp_path / f"{k}.csv")
        names = [n for n in rows[0] if all(_is_number(r[n]) for r in rows)]  # the numeric columns
        return {n: np.array([float(r[n]) for r in rows]) for n in names}

    held, zero, named = table("v"), table("z"), table("n")
    assert np.allclose(held["theta4"], 0.01, rtol=0, atol=1e-12)
    assert zero.keys() == named.keys() and all(np.allclose(zero[n], named[n], rtol=1e-12, atol=1e-12) for n in zero)
    system = load_model("nose_gear")
    x0 = find_equilibrium(system, hold={"theta4": 0.01}, free=["F"])
    lib = continuation(system, x0, "LU", hold=["theta4"], free=["F"], options=run_options({"LU": (1.25, 1.35)}))
    for lu in (1.27, 1.3, 1.33):  # the force that holds theta4 = 0.01 rad, at the same LU
        assert np.interp(lu, held["LU"], held["F"]) == pytest.approx(np.interp(lu, lib["LU"], lib["F"]), rel=1e-6)
    one_line_error(run(*args, "--start", "theta4=0", "--hold", "theta4=0"), "--hold", "once")
    one_line_error(run(*args, "--hold", "theta4=abc"), "--hold theta4", "not a number")


def test_set_moves_what_the_description_writes_in_parameters(run, tmp_path):
    """``--set`` changes the model, not only the start: a stop's limit written in a parameter follows it.

    The bar of pendulum_stop_3d.toml rests on its stop (tip at least d_min from P); by virtual work
    the contact force is m g d_min / (2 L). ``continue --stops --set d_min=0.5`` kept the file's
    0.72 m as the limit while the table said d_min = 0.5 (a gap of 0.72 and a force for 0.72)."""
    out = tmp_path / "b.csv"
    r = run("continue", "tests/data/spatial/pendulum_stop_3d.toml", "--stops", "--set", "d_min=0.5", "--vary", "g",
            "--bounds", "g=5:15", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    rows, _ = read_branch_table(out)
    assert len(rows) > 5
    for row in rows:
        d, gap, R, m, g, L = (float(row[k]) for k in ("d_min", "gap", "R_floor", "m", "g", "L"))
        assert d == 0.5 and gap == pytest.approx(0.5, abs=1e-12)
        assert R == pytest.approx(m * g * 0.5 / (2 * L), rel=1e-10)
    one_line_error(run("continue", "tests/data/spatial/pendulum_stop_3d.toml", "--stops", "--set", "d_mni=0.5",
                       "--vary", "g", "--bounds", "g=5:15"), "d_mni")


#: option name -> what its help and metavar say in every command that shows it: one meaning each
MEANINGS = {
    "--start": ("a state held at a value to find where the command starts",
                lambda p: p.multiple and p.metavar == "NAME=VALUE" and re.search(r"\bheld\b|\bhold\b", p.help, re.I)),
    "--hold": ("a state held during the analysis",
               lambda p: p.multiple and p.metavar.startswith("NAME") and re.search(r"\bheld\b", p.help)),
    "--vary": ("the continuation parameter (of the run, or of the branch read)",
               lambda p: not p.multiple and re.search(r"continu", p.help, re.I)),
    "--set": ("a parameter's value, in SI units",
              lambda p: p.multiple and p.metavar == "NAME=VALUE" and "SI units" in p.help),
    "--point": ("a row of a branch table", lambda p: (p.metavar or "").startswith("BRANCH.csv:") and "branch" in p.help),
    "--bounds": ("a variable's range NAME=LO:HI",
                 lambda p: p.multiple and p.metavar == "NAME=LO:HI"),
    "--branch": ("a branch table (CSV)",
                 lambda p: (p.metavar or "").endswith(".csv") and re.search(r"\bbranch\b", p.help, re.I)),
}


@pytest.mark.parametrize("option", sorted(MEANINGS))
def test_start_hold_vary_set_point_branch_mean_one_thing(option):
    meaning, check = MEANINGS[option]
    shown = _visible_options()[option]
    assert len(shown) >= 3, option  # shared by several commands: a name worth one meaning
    wrong = [(command, p.metavar, p.help) for command, p in shown if not check(p)]
    assert not wrong, f"{option} should be {meaning} in every command: {wrong}"


def test_every_command_with_a_start_calls_it_start_and_from_is_hidden():
    options = _visible_options()
    assert {c for c, _ in options["--start"]} >= {"continue", "folds", "draw", "simulate", "sweep", "freefall", "study"}
    assert "--from" not in options
    _register()
    hidden = {o for p in cli.commands["freefall"].params if isinstance(p, click.Option) and p.hidden for o in p.opts}
    assert "--from" in hidden


def test_the_meanings_tell_a_wrong_help_apart():
    """The checks themselves: an option whose help says another thing fails its meaning."""
    def option(name, help, metavar="NAME=VALUE", multiple=True):
        return click.Option([name], multiple=multiple, metavar=metavar, help=help)

    assert not MEANINGS["--start"][1](option("--start", "First value of the parameter sweep.", "VALUE", False))
    assert not MEANINGS["--hold"][1](option("--hold", "Seconds to pause on each special point.", "SECONDS", False))
    assert not MEANINGS["--vary"][1](option("--vary", "Parameter in which the fold is a turning point.", "P1", False))
    assert not MEANINGS["--set"][1](option("--set", "Study folder.", "DIR", False))
    assert not MEANINGS["--branch"][1](option("--branch", "Time history table.", "FILE.csv", False))


PENDULUM = "tests/data/freefall_pendulum.toml"


def test_freefall_start_and_its_old_spelling_from(run, tmp_path):
    """``freefall --start`` is the retracted pose (as ``simulate --start``); ``--from``, its old spelling, gives the
    same run; the two together, or an unknown name, are one line naming the spelling given."""
    args = ("freefall", PENDULUM, "--lock", "downlock", "--until", 5, "--set", "U=15", "--set", "c=5")
    new = run(*args, "--start", "angle=1", "--out", tmp_path / "new.csv")
    old = run(*args, "--from", "angle=1", "--out", tmp_path / "old.csv")
    assert new.exit_code == 0 and old.exit_code == 0, new.output + old.output
    assert new.output.replace("new.csv", "old.csv") == old.output and "outcome: locked" in new.output and old.stderr == ""
    assert (tmp_path / "new.csv").read_text() == (tmp_path / "old.csv").read_text()
    one_line_error(run(*args, "--start", "angle=1", "--from", "angle=1"), "--start", "--from", "not both")
    one_line_error(run(*args, "--start", "phi=1"), "--start", "phi is not")
    one_line_error(run(*args, "--from", "phi=1"), "--from", "phi is not")
    one_line_error(run(*args), "--start", "retracted pose")


def test_study_freefall_start_and_its_old_spelling_hold(run, tmp_path):
    """A freefall study's released pose is ``--start`` (``--hold``, a downlock condition elsewhere, its old spelling):
    both give the same samples and outcomes; ``--start`` is refused where nothing is released."""
    import pandas as pd

    args = ("study", PENDULUM, "--analysis", "freefall", "--dist", "m=normal:6:0.4", "--n", 2, "--lock", "downlock",
            "--until", 5, "--set", "U=15", "--set", "c=5", "--scheduler", "serial", "--quiet")
    assert run(*args, "--start", "angle=1", "--dir", tmp_path / "new").exit_code == 0
    assert run(*args, "--hold", "angle=1", "--dir", tmp_path / "old").exit_code == 0
    new, old = (pd.read_parquet(tmp_path / k / "results.parquet") for k in ("new", "old"))
    assert list(new["outcome"]) == list(old["outcome"]) and new["m"].tolist() == old["m"].tolist()
    assert set(new["outcome"]) == {"locked"}
    one_line_error(run(*args, "--start", "angle=1", "--hold", "angle=1", "--dir", tmp_path / "a"), "--start", "not both")
    one_line_error(run(*args, "--start", "phi=1", "--dir", tmp_path / "b"), "--start", "phi is not")
    one_line_error(run("study", PENDULUM, "--dist", "m=normal:6:0.4", "--n", 2, "--start", "angle=1", "--dir",
                       tmp_path / "c"), "--start", "--analysis freefall")


def test_at_is_one_repeatable_option_in_continue_and_cycles(run, tmp_path):
    """``--at P=V1,V2,...`` means the same in both commands (one parser, ``cli/_parse.at_values``): repeatable, the
    values of the --vary parameter; given twice it adds the values of both (it kept only the last)."""
    shown = _visible_options()["--at"]
    assert {c for c, _ in shown} == {"continue", "cycles"}
    assert all(p.multiple and p.metavar == "P=V1,V2,..." for _, p in shown)
    args = ("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds",
            "F=-100:100", "--quiet")
    twice, once = tmp_path / "twice.csv", tmp_path / "once.csv"
    assert run(*args, "--at", "F=-20", "--at", "F=30", "--out", twice).exit_code == 0
    assert run(*args, "--at", "F=-20,30", "--out", once).exit_code == 0

    def uz(path):
        rows, _ = read_branch_table(path)
        return sorted(float(r["F"]) for r in rows if r["label"] == "UZ")

    assert uz(twice) == uz(once) and len(uz(once)) >= 2  # the branch may pass a value more than once (folds)
    assert {round(v, 9) for v in uz(once)} == {-20.0, 30.0}
    one_line_error(run(*args, "--at", "F=1", "--at", "LU=1"), "--at", "the values are of the --vary parameter, F")


def test_draw_and_animate_errors_name_their_option(run, tmp_path):
    """A bad --point, --vary, --every or --diagram is one line naming the option typed (they named a bare field)."""
    png = tmp_path / "p.png"
    one_line_error(run("draw", "overcentre", "--point", "nocolon", "--out", png), "--point", "BRANCH.csv:ROW")
    one_line_error(run("draw", "overcentre", "--point", "b.csv:LP1", "--set", "LU=0.4", "--out", png), "--point")
    one_line_error(run("draw", "overcentre", "--vary", "F", "--out", png), "--vary", "with --point")
    branch = tmp_path / "b.csv"
    assert run("continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--bounds",
               "F=-50:50", "--max-steps", "20", "--out", branch, "--quiet").exit_code == 0
    gif = tmp_path / "a.gif"
    one_line_error(run("animate", "overcentre", "--branch", branch, "--every", "0", "--out", gif), "--every")
    one_line_error(run("animate", "overcentre", "--branch", branch, "--diagram", "F", "--out", gif), "--diagram")
    assert not png.exists() and not gif.exists()


def test_sensitivity_hold_takes_the_value_continue_held_it_at(run, tmp_path):
    """``--hold NAME=VALUE`` means in sensitivity what it means in continue: the state held on the branch at VALUE
    (it took only NAME); the derivatives are those of ``--hold NAME``, and a VALUE the row does not have is refused."""
    import json

    branch = tmp_path / "b.csv"
    assert run("continue", "nose_gear", "--free", "F", "--vary", "LU", "--bounds", "LU=1.25:1.35", "--hold",
               "theta4=0.01", "--out", branch, "--quiet").exit_code == 0
    args = ("sensitivity", "nose_gear", "--point", f"{branch}:3", "--free", "F", "--params", "k", "--of", "F")
    for hold, name in (("theta4=0.01", "v"), ("theta4", "n")):
        r = run(*args, "--hold", hold, "--out", tmp_path / f"{name}.json")
        assert r.exit_code == 0, r.output
    v, n = (json.loads((tmp_path / f"{k}.json").read_text()) for k in ("v", "n"))
    assert v["k"] == pytest.approx(n["k"], rel=1e-12) and v["k"] != 0
    one_line_error(run(*args, "--hold", "theta4=0.02"), "--hold", "theta4 is 0.01")
