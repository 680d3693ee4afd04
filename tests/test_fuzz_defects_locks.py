"""Defects of the third fuzz campaign (issue 33), locks and signals: the build lock of the compiled-code
cache cannot block a run forever (a stopped or dead holder, a holder that takes too long, a FIFO in
its place), and SIGHUP/SIGTERM/SIGKILL leave no temporary file behind. Real subprocesses, each with a
timeout: a test of a hang fails in seconds instead of hanging."""

import os
import signal
import subprocess
import sys
import time

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

