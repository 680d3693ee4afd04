"""Defects of the third fuzz campaign (issue 33), sizes decided before work: a description with 100,000
parameters, points or array values, or megabytes of text, is refused in one line at once (it took minutes
to build)."""

import time

import pytest
from cli_helpers import make_runner, one_line_error

from mechcont.mechanism import find_description

run = make_runner()
OVERCENTRE = find_description("overcentre").read_text()


def _many_parameters(n):
    return OVERCENTRE.replace("[parameters]\n", "[parameters]\n" + "".join(f"p{i} = 1.0\n" for i in range(n)), 1)


def _many_points(n):
    points = ", ".join(f"q{i} = [0.1, 0]" for i in range(n))
    return OVERCENTRE.replace('points = { spring = ["m", 0] }', f'points = {{ spring = ["m", 0], {points} }}', 1)


CASES = {
    "100,000 parameters": (_many_parameters(100_000), ("m.toml", "characters long", "at most 1048576")),
    "20,000 parameters": (_many_parameters(20_000), ("m.toml:13: parameters", "20011 entries", "at most 2000")),
    "20,000 points on a body": (_many_points(20_000), ("m.toml", "bodies.1.points", "20001 entries", "at most 500")),
    "an array of 100,000 values": (OVERCENTRE.replace('points = { spring = ["m", 0] }',
                                                      'points = { spring = [' + ", ".join(["0"] * 100_000) + '] }', 1),
                                   ("bodies.1.points.spring", "array of 100000 values", "at most 100")),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_huge_description_is_refused_before_any_work(tmp_path, case):
    text, words = CASES[case]
    path = tmp_path / "m.toml"
    path.write_text(text)
    t0 = time.perf_counter()
    r = run("check", path)
    one_line_error(r, *words)
    assert time.perf_counter() - t0 < 10


def test_limits_leave_the_shipped_descriptions_alone():
    from mechcont.mechanism._file import load_description

    for name in ("overcentre", "nose_gear", "lockstay", "fivebar"):
        load_description(name)



def test_a_scan_of_1000_values_is_refused_before_any_run(tmp_path):
    values = ",".join(str(1 + i / 1000) for i in range(1000))
    t0 = time.perf_counter()
    r = run("freefall", "nose_gear", "--start", "theta1=1", "--lock", "downlock", "--until", 1, "--critical", "U=0:100",
            "--scan", f"c={values}", "--out", tmp_path / "c.csv")
    one_line_error(r, "--scan", "1000 values", "at most 50", "--max-scan")
    assert time.perf_counter() - t0 < 10 and list(tmp_path.iterdir()) == []
    r = run("freefall", "nose_gear", "--start", "theta1=1", "--until", 1, "--scan", "c=1,2", "--max-scan", "0")
    assert r.exit_code == 2 and "--max-scan" in r.output
