"""``--quiet`` means one thing in every command: print nothing but errors (and warnings, on stderr), no progress bar,
files still written. ``simulate``, ``sweep`` and ``animate`` once took a hidden ``--quiet`` that only hid the
progress bar (the old spelling of ``--no-progress``) and printed their whole report: a fresh user asking for a quiet
long run got it all. ``--no-progress`` hides the bar alone and keeps the report.
"""

from __future__ import annotations

import pytest
from cli_helpers import csv_rows, make_runner, one_line_error

import mechcont._progress as progress_module
from mechcont.cli._app import _register, cli

BAR = "tests/data/bar_drop.toml"


@pytest.fixture
def bars(monkeypatch):
    """The ``quiet`` each progress bar a command opens is asked for (the bar itself draws only on a terminal)."""
    asked: list[bool] = []
    real = progress_module.Progress

    class Recording(real):
        def __init__(self, *args, quiet=False, **kwargs):
            asked.append(quiet)
            super().__init__(*args, quiet=quiet, **kwargs)

    monkeypatch.setattr(progress_module, "Progress", Recording)
    return asked


@pytest.fixture(scope="module")
def run():
    return make_runner()


@pytest.fixture(scope="module")
def branch(tmp_path_factory, run):
    out = tmp_path_factory.mktemp("branch") / "b.csv"
    r = run("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-0.5:0.5",
            "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    return out


def _commands(tmp_path, branch):
    return {
        "simulate": ("simulate", BAR, "--start", "theta_bar=0", "--until", 0.3, "--out", tmp_path / "s.csv"),
        "sweep": ("sweep", "overcentre", "--set", "LU=0.4", "--set", "c=50", "--start", "theta1=1.2",
                  "--ramp", "F=-65:-70:5", "--watch", "theta1", "--out", tmp_path / "s.csv"),
        "animate": ("animate", "overcentre", "--branch", branch, "--every", 50, "--out", tmp_path / "s.gif"),
    }


@pytest.mark.parametrize("command", ["simulate", "sweep", "animate"])
def test_quiet_prints_nothing_and_writes_the_file(command, run, tmp_path, branch, bars):
    args = _commands(tmp_path, branch)[command]
    out = args[-1]
    loud = run(*args, "--no-progress")
    assert loud.exit_code == 0, loud.output
    assert str(out) in loud.stdout and bars == [True]  # the report printed, the bar hidden
    out.unlink()
    bars.clear()
    quiet = run(*args, "--quiet")
    assert quiet.exit_code == 0, quiet.output
    assert quiet.stdout == "" and bars == [True]  # before: the whole report, as with --no-progress
    assert out.exists() and out.stat().st_size > 0
    if out.suffix == ".csv":
        assert len(csv_rows(out)) > 2
    bars.clear()
    plain = run(*args)  # on a terminal a long run shows its bar
    assert plain.exit_code == 0 and bars == [False], plain.output


def test_quiet_keeps_errors(run):
    one_line_error(run("simulate", BAR, "--start", "nope=0", "--until", 0.3, "--quiet"), "--start", "nope")


def test_no_command_hides_a_quiet_that_means_something_else():
    _register()
    for name, command in cli.commands.items():
        for p in command.params:
            if "--quiet" in getattr(p, "opts", []):
                assert not p.hidden and (p.help or "").startswith("Print nothing but errors"), (name, p.help)
