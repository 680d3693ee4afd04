"""tests/doc_runs.py runs a documented command forked from a server as a process started afresh runs it."""

from __future__ import annotations

from doc_runs import run_fresh, server


def test_a_forked_command_prints_and_exits_as_one_started_afresh(tmp_path):
    """The same output and exit status, forked or started afresh: a command that succeeds, and one that fails with
    its one-line error (status 2); each forked command in the folder it is given, its figures reviewed there."""
    for args in (("models",), ("continue", "no_such_model", "--vary", "F")):
        fresh, forked = run_fresh(" ".join(args), args, tmp_path), server().run(" ".join(args), args, tmp_path)
        assert (forked.returncode, forked.stdout, forked.stderr) == (fresh.returncode, fresh.stdout, fresh.stderr)
        assert forked.fresh is False and fresh.fresh is True
    assert fresh.returncode == 2 and fresh.stderr.startswith("error: ") and len(fresh.stderr.splitlines()) == 1
    args = ("check", "fourbar.toml", "--plot", "fourbar.png")
    drawn = server().run(" ".join(args), args, tmp_path)
    assert drawn.returncode == 0 and (tmp_path / "fourbar.png").exists()
    assert drawn.figures == {"fourbar.png": []}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fourbar.png"]   # the streams' files removed
