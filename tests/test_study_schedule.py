"""Where a study runs: ``--scheduler auto`` (the default) times its first chunk in this process and starts a local
cluster only when the work left pays for the cluster's start; the same table whichever way it went.

The choice is checked on given timings (no measured time in an assertion): the threshold against the cost model
it stands for, and :func:`run_parts` sending the parts where the choice says. The tables are checked against an
explicit serial run in test_study_cli.py (beside the explicit local cluster, sharing its serial run)."""

import contextlib
import math
import os

import pytest
from cli_helpers import make_runner, one_line_error
from numeric_text import assert_frames_close

from mechcont.analysis.study import (
    CLUSTER_START_SECONDS,
    Distribution,
    StudySpec,
    check_scheduler,
    choose,
    cluster_threshold,
    read_results,
    run_parts,
)

pytest.importorskip("pyarrow")
run = make_runner()


# -- the choice, on given timings ---------------------------------------------------------------
@pytest.mark.parametrize("workers", [2, 3, 8, 64])
@pytest.mark.parametrize("start", [1.0, CLUSTER_START_SECONDS, 37.0])
def test_threshold_is_where_the_cluster_saves_its_start_again(workers, start):
    """At the threshold W the cost model's cluster, ``start + W/n``, takes exactly ``start`` less than ``W`` here;
    above it it saves more, below less."""
    W = cluster_threshold(workers, start)
    saving = lambda w: w - (start + w / workers)
    assert saving(W) == pytest.approx(start, rel=1e-12)
    assert saving(1.01 * W) > start > saving(0.99 * W)


def test_one_worker_never_pays_off():
    assert math.isinf(cluster_threshold(1))
    c = choose(1e6, 1, 10**7, workers=1)  # 10^13 s of computing left
    assert not c.cluster and "one worker" in c.describe()


def test_choice_estimates_the_work_left_from_the_first_chunk():
    """Mean time per sample of the first chunk times the samples left, against 2 S n/(n-1) (40 s on 2 workers)."""
    c = choose(0.25, 1000, 9000, workers=2, start=10.0)   # the nose gear's 10,000 samples: 2.25 s left
    assert (c.cluster, c.seconds_left, c.samples_left, c.workers, c.threshold) == (False, pytest.approx(2.25), 9000, 2, 40.0)
    assert "9000 samples left" in c.describe() and "2.25 s of computing" in c.describe() and "above 40 s" in c.describe()
    assert not choose(1.0, 1000, 39_000, workers=2, start=10.0).cluster    # 39 s left
    assert choose(1.0, 1000, 41_000, workers=2, start=10.0).cluster        # 41 s left
    assert choose(1.0, 1000, 23_000, workers=8, start=10.0).cluster        # 8 workers: above 22.9 s
    assert not choose(1.0, 1000, 22_000, workers=8, start=10.0).cluster
    assert choose(1.0, 1000, 0, workers=2).seconds_left == 0.0
    assert choose(1.0, 1, 1, workers=None).workers == (os.cpu_count() or 1)


class _Parts:
    """Fake work: ``here`` records the part and returns the given seconds of computing, ``there`` records the parts
    sent to the (fake) client."""

    def __init__(self, seconds: float):
        self.seconds, self.here_done, self.there_done, self.opened, self.clients = seconds, [], [], 0, []

    def here(self, k):
        self.here_done.append(k)
        return self.seconds

    def there(self, client, ks):
        self.there_done += list(ks)

    def before(self):
        assert not self.here_done and not self.there_done
        self.opened += 1


@pytest.fixture
def fake_cluster(monkeypatch):
    """Replaces the Dask client by a record of the clusters asked for."""
    from mechcont.analysis.study import _schedule

    asked = []

    @contextlib.contextmanager
    def client(scheduler, workers):
        asked.append((scheduler, workers))
        yield f"client of {scheduler}"

    monkeypatch.setattr(_schedule, "dask_client", client)
    return asked


@pytest.mark.parametrize("first_seconds, cluster", [(0.25, False), (4.0, False), (5.0, True)])
def test_auto_runs_the_first_part_here_then_chooses(fake_cluster, first_seconds, cluster):
    """Ten parts of 1000 samples, the first taking ``first_seconds``: 9000 left take 9 x that, against 40 s."""
    parts = _Parts(first_seconds)
    ran_on = run_parts(dict.fromkeys(range(10), 1000), parts.here, parts.there, "auto", 2, parts.before)
    assert parts.opened == 1
    if cluster:
        assert parts.here_done == [0] and parts.there_done == list(range(1, 10)) and fake_cluster == [("local", 2)]
        assert ran_on.startswith("this process, then a local cluster of 2 worker processes (auto: 9000 samples left")
    else:
        assert parts.here_done == list(range(10)) and not parts.there_done and not fake_cluster
        assert ran_on.startswith("this process (auto: 9000 samples left")


@pytest.mark.parametrize("scheduler, parts, here, there, clients", [
    (None, {3: 10, 5: 10}, [3, 5], [], []),
    ("serial", {3: 10, 5: 10}, [3, 5], [], []),
    ("auto", {7: 10}, [7], [], []),                     # one part: nothing to choose
    ("local", {7: 10}, [7], [], []),                    # one part: no cluster (as before)
    ("local", {3: 10, 5: 10}, [], [3, 5], [("local", 2)]),
    ("tcp://127.0.0.1:8786", {7: 10}, [], [7], [("tcp://127.0.0.1:8786", 2)]),
    ("tcp://127.0.0.1:8786", {}, [], [], []),           # nothing to do: no connection
])
def test_explicit_schedulers_are_kept(fake_cluster, scheduler, parts, here, there, clients):
    work = _Parts(1e6)  # an hour per sample would start any cluster auto could
    ran_on = run_parts(parts, work.here, work.there, scheduler, 2, work.before)
    assert (work.here_done, work.there_done, fake_cluster, work.opened) == (here, there, clients, 1)
    assert "auto" not in ran_on


@pytest.mark.parametrize("bad", ["lcoal", "Auto", "", "tcp://host", "cluster 2", "http://x/y"])
def test_an_unknown_scheduler_is_refused_before_any_work(fake_cluster, bad):
    work = _Parts(1.0)
    with pytest.raises(Exception, match="--scheduler: unknown scheduler") as info:
        run_parts({0: 1, 1: 1}, work.here, work.there, bad, 2, work.before)
    assert "valid: auto" in str(info.value) and not work.opened and not fake_cluster


def test_known_schedulers_and_addresses_pass():
    for ok in (None, "auto", "local", "serial", "tcp://127.0.0.1:8786", "127.0.0.1:8786", "tcp://[::1]:8786",
               "tls://host:1"):  # tls: refused by the connection's own check, which says why
        check_scheduler(ok)


# -- the command ----------------------------------------------------------------------------------
STUDY = ("study", "nose_gear", "--dist", "LU=normal:1.3:0.01", "--n", "60", "--chunk", "20", "--seed", "3")


def test_default_says_its_choice_and_quiet_says_nothing(tmp_path):
    r = run(*STUDY, "--dir", tmp_path / "a")
    assert r.exit_code == 0, r.output
    first = r.stdout.splitlines()[0]
    assert "3 chunk(s) computed in this process (auto: 40 samples left, about " in first, first
    assert "a local cluster of" in first and "pays off above" in first
    q = run(*STUDY, "--dir", tmp_path / "b", "--quiet")
    assert q.exit_code == 0 and q.stdout == "" and q.stderr == ""
    assert_frames_close(read_results(tmp_path / "b" / "results.parquet"), read_results(tmp_path / "a" / "results.parquet"),
                        rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("extra", [(), ("--method", "form", "--n", "0")])
@pytest.mark.parametrize("bad", ["lcoal", "Auto", "tcp://host"])
def test_bad_scheduler_is_one_line(tmp_path, bad, extra):
    """Refused at once in one line naming the valid values, nothing written; also where no chunk would reach a
    scheduler (FORM without importance samples ran and exited 0 with any --scheduler)."""
    args = [*STUDY[:4], *(extra or STUDY[4:])]
    one_line_error(run(*args, "--scheduler", bad, "--dir", tmp_path / "s"), "--scheduler", "unknown scheduler",
                   "valid: auto", "local, serial")
    assert not (tmp_path / "s").exists()


def test_form_importance_samples_with_auto_equal_serial():
    """``downlock_reliability(scheduler="auto")``: two chunks of importance samples, the second run where auto chose
    (here: too little work for a cluster), the same probability as in this process."""
    from dataclasses import replace

    from mechcont.analysis.reliability import downlock_reliability

    spec = replace(StudySpec("nose_gear", "mc", (("LU", Distribution("normal", (1.2696, 0.01))),), n=600, seed=4), chunk=300)
    here = downlock_reliability(spec, scheduler=None)
    auto = downlock_reliability(spec, scheduler="auto", workers=2)
    assert here.sampling.ran_on == "this process" and auto.sampling.ran_on.startswith("this process (auto: 300 samples")
    assert auto.sampling.probability == pytest.approx(here.sampling.probability, rel=1e-9)
    assert auto.sampling.cov == pytest.approx(here.sampling.cov, rel=1e-9)
