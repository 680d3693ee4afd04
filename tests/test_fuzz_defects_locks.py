"""Defects of the third fuzz campaign (issue 33), locks and signals: the build lock of the compiled-code
cache cannot block a run forever (a stopped or dead holder, a holder that takes too long, a FIFO in
its place), and SIGHUP/SIGTERM/SIGKILL leave no temporary file behind. Real subprocesses, each with a
timeout: a test of a hang fails in seconds instead of hanging."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc, flock and signals of Linux")

KEY = "ab" + "0" * 62

HOLDER = """
import os, sys, time
from mechcont.equations import _cache
fork = sys.argv[1] == "fork"
with _cache._build_lock(sys.argv[2]):
    if fork:
        child = os.fork()
        if child:  # the parent leaves; its child keeps the lock's file open (and so the lock)
            print(child, flush=True)
            os._exit(0)
    else:
        print(os.getpid(), flush=True)
    time.sleep(60)
"""

WAITER = """
import sys, time
from mechcont.equations import _cache
t0 = time.monotonic()
print(_cache.load_or_build(sys.argv[1], lambda: 42), round(time.monotonic() - t0, 2), flush=True)
"""


def _env(cache, **extra):
    env = dict(os.environ, MECHCONT_CACHE_DIR=str(cache), MECHCONT_NO_CACHE="")
    env.update(extra)
    return env


@pytest.fixture
def holder(tmp_path):
    """Start a process holding the build lock of KEY (``mode``: "plain", or "fork": held by a child
    whose parent, the recorded holder, has ended); yields the holding process's id; kills it after."""
    procs = []

    def start(mode="plain"):
        p = subprocess.Popen([sys.executable, "-c", HOLDER, mode, KEY], env=_env(tmp_path / "cache"),
                             stdout=subprocess.PIPE, text=True)
        procs.append(p)
        pid = int(p.stdout.readline())
        procs.append(pid)
        return pid

    yield start
    for p in procs:
        pid = p if isinstance(p, int) else p.pid
        for sig in (signal.SIGKILL, signal.SIGCONT):
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        if not isinstance(p, int):
            p.wait(10)


def _wait(tmp_path, timeout=30, **env):
    return subprocess.run([sys.executable, "-c", WAITER, KEY], env=_env(tmp_path / "cache", **env),
                          capture_output=True, text=True, timeout=timeout)


def test_a_holder_stopped_with_ctrl_z_does_not_block_the_next_run(tmp_path, holder):
    pid = holder()
    os.kill(pid, signal.SIGSTOP)
    r = _wait(tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[0] == "42" and float(r.stdout.split()[1]) < 5
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and f"process {pid}" in lines[0] and "is stopped" in lines[0], r.stderr
    assert "kill -CONT" in lines[0] and "building" in lines[0]


def test_a_lock_whose_recorded_holder_has_ended(tmp_path, holder):
    holder("fork")  # the lock file records the parent, which has gone; its child still holds the flock
    r = _wait(tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[0] == "42" and float(r.stdout.split()[1]) < 5
    assert "has ended without releasing it" in r.stderr and len(r.stderr.splitlines()) == 1, r.stderr


def test_a_running_holder_is_waited_for_up_to_the_timeout_then_one_line(tmp_path, holder):
    pid = holder()
    r = _wait(tmp_path, MECHCONT_LOCK_TIMEOUT="1.5")
    assert r.returncode == 0, r.stderr
    seconds = float(r.stdout.split()[1])
    assert r.stdout.split()[0] == "42" and 1.4 < seconds < 6
    lines = r.stderr.splitlines()  # not a terminal: no waiting lines, only the one that ends the wait
    assert len(lines) == 1 and "waited 1.5 s" in lines[0] and f"process {pid}" in lines[0], r.stderr


def test_on_a_terminal_the_wait_is_told_every_few_seconds(tmp_path, holder):
    """stderr a terminal: a line naming the holder and the lock while waiting (here every 0.3 s)."""
    import pty

    pid = holder()
    leader, follower = pty.openpty()
    p = subprocess.Popen([sys.executable, "-c", WAITER, KEY], stdout=subprocess.PIPE, stderr=follower,
                         env=_env(tmp_path / "cache", MECHCONT_LOCK_TIMEOUT="1.5", MECHCONT_LOCK_NOTICE="0.3"))
    os.close(follower)
    out, _ = p.communicate(timeout=30)
    text = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:
            break
        if not chunk:
            break
        text += chunk
    os.close(leader)
    lines = [ln for ln in text.decode().splitlines() if ln.strip()]
    waiting = [ln for ln in lines if ln.startswith(f"mechcont: waiting for process {pid} to build")]
    assert 2 <= len(waiting) <= 6 and all(f"{KEY}.lock" in ln for ln in waiting), lines
    assert "waited 1.5 s" in lines[-1] and out.split()[0] == b"42"


def test_a_lock_released_in_time_is_waited_for_and_the_entry_loaded(tmp_path):
    """The lock still does its job: a waiter loads what the holder built, without building it again."""
    script = WAITER.replace("lambda: 42", "lambda: (time.sleep(1.5), 7)[1]")
    first = subprocess.Popen([sys.executable, "-c", script, KEY], env=_env(tmp_path / "cache"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(0.7)
    second = _wait(tmp_path)  # builds 42 only if it did not wait
    out, err = first.communicate(timeout=30)
    if not (tmp_path / "cache" / KEY[:2] / f"{KEY}.pkl").exists():
        pytest.skip("the cache stores nothing with this SymEngine backend")
    assert out.split()[0] == "7" and second.stdout.split()[0] == "7", (out, second.stdout, second.stderr)
    assert second.stderr == "" and err == ""


def test_a_fifo_for_the_lock_file_is_one_line(tmp_path):
    shard = tmp_path / "cache" / KEY[:2]
    _wait(tmp_path)  # makes the cache folder, its key and the shard
    (shard / f"{KEY}.pkl").unlink(missing_ok=True)
    (shard / f"{KEY}.lock").unlink()
    os.mkfifo(shard / f"{KEY}.lock")
    script = ("from mechcont.equations import _cache\nfrom mechcont.errors import InputError\n"
              f"try:\n    _cache.load_or_build('{KEY}', lambda: 42)\n"
              "except InputError as e:\n    print('error:', e)\n")
    r = subprocess.run([sys.executable, "-c", script], env=_env(tmp_path / "cache"), capture_output=True, text=True,
                       timeout=30)
    lines = r.stdout.splitlines()
    assert len(lines) == 1 and f"{KEY}.lock" in lines[0] and "is a FIFO" in lines[0] and "delete it" in lines[0], r


def test_holder_state_reads_proc():
    from mechcont.equations._lock import holder_state

    p = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        assert holder_state(p.pid) is None
        os.kill(p.pid, signal.SIGSTOP)
        deadline = time.monotonic() + 5
        while holder_state(p.pid) != "stopped" and time.monotonic() < deadline:
            time.sleep(0.02)
        assert holder_state(p.pid) == "stopped"
    finally:
        p.kill()
        p.wait(10)
    assert holder_state(p.pid) == "gone"



# -- signals and temporary files ------------------------------------------------------------------
MAIN = "from mechcont.cli._app import main; main()"


@pytest.fixture(scope="module")
def branch_csv(tmp_path_factory):
    from cli_helpers import make_runner

    out = tmp_path_factory.mktemp("branch") / "b.csv"
    r = make_runner()("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--bounds", "theta1=-1.2:1.2",
                      "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    return out


def _mechcont(*args, cwd):
    return subprocess.Popen([sys.executable, "-c", MAIN, *map(str, args)], cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ, MPLBACKEND="Agg"))


def _when_a_temporary_appears(folder: Path, proc, stem: str, timeout=60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if any(p.name.startswith(f".{stem}") for p in folder.iterdir()):
            return
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    raise AssertionError("no temporary file appeared")


@pytest.mark.parametrize("sig, status, words", [(signal.SIGHUP, 129, "hung up"), (signal.SIGTERM, 143, "terminated")])
def test_a_signal_while_an_animation_is_written_leaves_no_temporary_file(tmp_path, branch_csv, sig, status, words):
    """The GIF's temporary file exists (empty) while the frames are drawn; SIGHUP left it there."""
    out = tmp_path / "out"
    out.mkdir()
    p = _mechcont("animate", "overcentre", "--branch", branch_csv, "--out", out / "a.gif", "--no-progress", cwd=tmp_path)
    try:
        _when_a_temporary_appears(out, p, "a")
        p.send_signal(sig)
        _, err = p.communicate(timeout=60)
    finally:
        p.kill()
    assert p.returncode == status and err.strip() == f"error: {words}", (p.returncode, err)
    assert list(out.iterdir()) == []


def test_a_temporary_file_of_a_killed_writer_is_removed_by_the_next_write(tmp_path, branch_csv):
    """SIGKILL runs no handler: the temporary file stays, named after its writer; the next write into the
    folder removes it once that process is gone (and leaves a live writer's alone)."""
    from mechcont._io import atomic_write

    out = tmp_path / "out"
    out.mkdir()
    p = _mechcont("animate", "overcentre", "--branch", branch_csv, "--out", out / "a.gif", "--no-progress", cwd=tmp_path)
    try:
        _when_a_temporary_appears(out, p, "a")
        p.kill()
        p.communicate(timeout=30)
    finally:
        p.kill()
    left = [q.name for q in out.iterdir()]
    assert len(left) == 1 and f".mechcont-{p.pid}-" in left[0], left
    live = out / f".b.mechcont-{os.getpid()}-abcdefgh.csv"  # this process's own: alive
    live.write_text("")
    atomic_write(out / "c.csv", lambda tmp: Path(tmp).write_text("x\n"))
    assert sorted(q.name for q in out.iterdir()) == sorted([live.name, "c.csv"])


def test_sigterm_during_a_long_continuation_writes_the_branch_so_far(tmp_path):
    """`continue` of 100,000 steps each way: SIGTERM ends the continuation where it is, the branch so far is
    written (table and figure), and the exit status is 143. (The compiled corrector makes about 100,000 steps
    a second here: the signal comes half a second after start-up, far from the end on any machine.)"""
    warm = _mechcont("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--max-steps", "5", "--quiet",
                     cwd=tmp_path)
    t0 = time.monotonic()
    warm.communicate(timeout=120)
    start_up = time.monotonic() - t0
    p = _mechcont("continue", "overcentre", "--start", "theta1=0.3", "--vary", "F", "--max-steps", "100000", "--ds",
                  "1e-4", "--dsmax", "1e-4", "--out", "b.csv", "--plot", "b.png", cwd=tmp_path)
    try:
        time.sleep(start_up + 0.5)
        assert p.poll() is None
        p.send_signal(signal.SIGTERM)
        out, err = p.communicate(timeout=60)
    finally:
        p.kill()
    assert p.returncode == 143 and err.strip() == "error: terminated", (p.returncode, err)
    assert "stopped by SIGTERM" in out and "wrote b.csv" in out and "wrote b.png" in out
    rows = (tmp_path / "b.csv").read_text().splitlines()
    assert 100 < len(rows) < 200_000  # some of the branch, not all 200,000 steps
    assert sorted(q.name for q in tmp_path.iterdir()) == ["b.csv", "b.png"]


def test_a_cache_entry_half_written_by_a_killed_process_is_removed_by_the_next_store(tmp_path):
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait(10)  # a process id that is gone
    dead, alive = p.pid, os.getpid()
    code = ("import os, sys\nfrom mechcont.equations import _cache\n"
            f"shard = os.path.join(sys.argv[1], '{KEY[:2]}')\n"
            "print(_cache.store(sys.argv[2], 1), sorted(os.listdir(shard)))\n")
    cache = tmp_path / "cache"
    _wait(tmp_path)  # makes the cache, its key and the shard
    shard = cache / KEY[:2]
    (shard / f".tmp-{dead}-{'0' * 16}.pkl").write_bytes(b"half")
    (shard / f".tmp-{alive}-{'1' * 16}.pkl").write_bytes(b"being written")
    other = KEY[:2] + "1" * 62
    r = subprocess.run([sys.executable, "-c", code, str(cache), other], env=_env(cache), capture_output=True,
                       text=True, timeout=60)
    if r.stdout.startswith("False"):
        pytest.skip("the cache stores nothing here")
    names = sorted(q.name for q in shard.iterdir())
    assert f".tmp-{dead}-{'0' * 16}.pkl" not in names and f".tmp-{alive}-{'1' * 16}.pkl" in names, names
    assert f"{other}.pkl" in names
