"""One meaning per option name across the commands (issue 21, item 4), and the old spellings kept for scripts.

``--free`` names a parameter solved for, ``--out`` a file, ``--quiet`` prints nothing but errors, in
every command that has them; the spellings they replaced (``folds --free P2`` and ``--solve-for``,
``design --x/--y``, ``paper``/``study --out DIR``, ``simulate``/``sweep``/``animate --quiet``) still work, hidden from the help.
"""

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
    assert {c for c, _ in options["--no-progress"]} == {"simulate", "sweep", "animate"}
    assert "--solve-for" not in options


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
