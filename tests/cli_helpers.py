"""Shared by the CLI tests: invoking mechcont, checking its one-line errors, reading the tables it writes."""

import csv
from pathlib import Path

from click.testing import CliRunner

from mechcont.cli._app import _register, cli


def make_runner():
    """``run(*args)`` -> click Result of ``mechcont args...`` (arguments str()-ed)."""
    _register()
    runner = CliRunner()
    return lambda *args: runner.invoke(cli, [str(a) for a in args])


def one_line_error(result, *words):
    """Exit status 2, exactly one line on stderr starting 'error: ', containing ``words``, no traceback."""
    assert result.exit_code == 2, result.output
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    for w in words:
        assert w in lines[0], lines[0]


def csv_rows(path: str | Path) -> list[dict[str, str]]:
    """The rows of the CSV table at ``path`` as ``{column: text}``."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))
