"""benchmarks/bench_auto.py without AUTO (its one-line exit), its parser of AUTO's output, and
the Fortran it generates (double-precision literals that give back mechcont's start)."""

from __future__ import annotations

import importlib.util
import re
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_auto", ROOT / "benchmarks" / "bench_auto.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("auto_dir", [None, "/nonexistent/auto-07p"])
def test_without_auto_prints_one_line_and_exits_0(bench, monkeypatch, capsys, auto_dir):
    if auto_dir is None:
        monkeypatch.delenv("AUTO_DIR", raising=False)
    else:
        monkeypatch.setenv("AUTO_DIR", auto_dir)
    assert bench.main([]) == 0
    out = capsys.readouterr().out
    assert out.count("\n") == 1
    assert "AUTO_DIR" in out and "github.com/auto-07p/auto-07p" in out


# two runs as AUTO-07p prints them (column header, special points, its timer), then the script's lines
_OUTPUT = """\
gfortran -g -fopenmp -O -c oc.f90 -o oc.o
Starting oc ...

  BR    PT  TY  LAB    PAR(1)        L2-NORM         U(1)          U(2)          U(3)
   1     1  EP    1  -3.07723E+01   3.66014E+00   7.16502E-01   2.21640E-01   3.00000E-01
   1    50  LP    2   9.52007E+01   4.45578E+00   4.82745E-01  -5.73984E-01  -8.71526E-01
   1   126  UZ    3  -2.00000E+02   4.93059E+00   9.47748E-02  -7.43988E-01  -1.44409E+00

 Total Time    0.586E-02
oc ... done
Starting oc ...

  BR    PT  TY  LAB    PAR(1)        L2-NORM         U(1)          U(2)          U(3)
   1     1  EP    1  -3.07723E+01   3.66014E+00   7.16502E-01   2.21640E-01   3.00000E-01
   1   123  UZ    2   2.00000E+02   2.48490E+00   9.96363E-02   7.43352E-01   1.43755E+00

 Total Time    0.570E-02
oc ... done
RESULT LP 95.200667883 -0.87152579
"""


def test_parse_auto_output(bench):
    times, points, results = bench.parse_auto_output(_OUTPUT)
    assert times == pytest.approx([5.86e-3, 5.70e-3], rel=1e-12)
    assert points == [126, 123]
    assert results == [["LP", "95.200667883", "-0.87152579"]]


def test_fortran_start_is_double_precision_and_gives_back_the_start(bench, tmp_path):
    """Every literal of STPNT carries a D exponent (a bare 0.3 is single precision in Fortran)
    and reads back as the value mechcont solved for; F is divided by the variant's scale."""
    s, x0vec, _, _ = bench.mechcont_problem()
    x0 = dict(zip(s.names, map(float, x0vec)))
    bench.write_problem(tmp_path, x0, 127.0, 1.0, 1.0)
    source = (tmp_path / "oc.f90").read_text()
    start = source[source.index("SUBROUTINE STPNT"):source.index("END SUBROUTINE STPNT")]
    assigned = dict(re.findall(r"^\s+((?:PAR|U)\(\d+\)) = (\S+)$", start, flags=re.M))
    assert len(assigned) == 16
    assert all("D" in lit for lit in assigned.values())
    read = {k: float(v.replace("D", "e")) for k, v in assigned.items()}
    assert read["PAR(1)"] * 127.0 == pytest.approx(x0["F"], rel=1e-15)
    assert read["PAR(2)"] == x0["LU"]
    assert [read[f"U({i})"] for i in range(1, 7)] == [x0[n] for n in ("x1", "y1", "theta1", "x2", "y2", "theta2")]
    assert "UZSTOP={1: [-1.5748031496062993, 1.5748031496062993]}" in (tmp_path / "c.oc").read_text()


@pytest.mark.skipif(shutil.which("gfortran") is None, reason="needs gfortran")
def test_generated_fortran_compiles(bench, tmp_path):
    """The generated equations file is valid Fortran (compiled alone; AUTO's library not needed)."""
    import subprocess

    s, x0vec, _, _ = bench.mechcont_problem()
    bench.write_problem(tmp_path, dict(zip(s.names, map(float, x0vec))), 1.0, 2.0, 2.0)
    proc = subprocess.run(["gfortran", "-c", "oc.f90", "-o", "oc.o"], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_periodic_run_counts_unstable_points_and_the_ab_problem_is_written(bench, tmp_path):
    # AUTO prints an unstable periodic orbit's point number negative; the family's last row counts
    out = _OUTPUT.replace("   1   123  UZ    2", "   1  -123  UZ    2")
    assert bench.parse_auto_output(out)[1] == [126, 123]
    ab = bench._auto_ab
    ab.write_problem(tmp_path)
    assert "NTST=50, NCOL=4" in (tmp_path / "c.ab.po").read_text()
    assert "UZSTOP={1: 0.3}" in (tmp_path / "c.ab.po").read_text()
    assert "PAR(2) = 14.0D0" in (tmp_path / "ab.f90").read_text()
    # the Hopf points the script picks from are those of the closed form, and mechcont locates them there
    import numpy as np

    from mechcont.continuation import hopf_point
    from mechcont.equations import dynamics_of

    m, _ = ab.mechcont_family()
    for d, u1, u2 in ab.hopf_values():
        h = hopf_point(m, dynamics_of(m), m.vector({"D": d * 1.001, "u1": u1, "u2": u2}), "D")
        assert h.x[m.index("D")] == pytest.approx(d, rel=1e-12)
        assert np.max(np.abs(np.linalg.eigvals(dynamics_of(m).rates_jacobian(h.z, h.x)).real)) < 1e-10


# a stretch of AUTO-07p's diagnostics file (fort.9, IID = 2) of ab's periodic run: an orbit, then the location of
# the fold of cycles (its secant iterations, each with its Newton iterations), then the located orbit's summary
_DIAGNOSTICS = """\
  BR    PT  IT         PAR           L2-NORM
   2    61   0        1.61694E-01   2.00370E+00
   2    61   1        1.61697E-01   2.00293E+00
   2    61   2        1.61697E-01   2.00293E+00
   2    61   3        1.61697E-01   2.00293E+00
   2    61         Multipliers:     Stable:   1
   2    61         Multiplier  1    1.00000E+00   0.00000E+00  Abs. Val.   1.00000E+00

  BR    PT  TY  LAB    PAR(1)        L2-NORM       MAX U(1)      MAX U(2)       PERIOD
  -2    61        0   1.61697E-01   2.00293E+00   9.44429E-01   4.84104E+00   7.15029E+00

   2    61         Iterations   :   3
   2    61         Next Step    :   2.25000E-02
===============================================

  BR    PT  IT         PAR           L2-NORM
   2    62   0        1.61693E-01   2.00656E+00
   2    62   1        1.61696E-01   2.00592E+00
   2    62   2        1.61696E-01   2.00591E+00
   2    62         Fold Function    2.66254E-05
 ==> Location of special point :  Iteration   0  Step size =  -4.94435E-03
===============================================

  BR    PT  IT         PAR           L2-NORM
   2    62   0        1.61696E-01   2.00524E+00
   2    62   1        1.61696E-01   2.00529E+00
 ==> Location of special point :  Convergence.   Step size =  -5.93400E-08

  BR    PT  TY  LAB    PAR(1)        L2-NORM       MAX U(1)      MAX U(2)       PERIOD
  -2    62  LP    5   1.61696E-01   2.00528E+00   9.49792E-01   4.95064E+00   7.11375E+00

   2    62         Iterations   :   2
"""


def test_auto_iterations_counts_newton_rows_and_orbits(bench):
    # 3 + 2 + 1 rows with IT >= 1 (the IT 0 rows are the predicted orbits; summaries and multipliers are no
    # iterations); two accepted orbits
    assert bench._auto_ab.auto_iterations(_DIAGNOSTICS) == (6, 2)


def test_ab_script_measures_autos_cpu_time_and_both_settings_agree_with_auto(bench, tmp_path):
    """The script prints the periodic run's CPU time (its program's, from the children's resource usage), and
    mechcont's family at its defaults and at AUTO's tolerance both agree with AUTO-07p's printed results (its run of
    2026-11-29: Hopf points, fold of cycles, period at D = 0.3; AUTO converges to 1e-7, hence REL_TOL 1e-5)."""
    ab = bench._auto_ab
    ab.write_problem(tmp_path)
    script = (tmp_path / "cycles.auto").read_text()
    assert "RUSAGE_CHILDREN" in script and script.index("c0 = cpu()") < script.index("po = run(") < \
        script.index("RESULT CPU")
    auto = [["HB", "0.16504204529"], ["HB", "0.33655036532"], ["CPU", "0.059889"],
            ["LPC", "0.1616961289", "7.1137548044"], ["UZ", "0.30000000192", "1.6092335179"]]
    assert ab.auto_cpu(auto) == pytest.approx(0.059889, rel=1e-12)
    assert sorted(ab.SETTINGS.values(), key=lambda v: v or 0.0) == [None, 1e-7]
    lines: list[str] = []
    for name, tol in ab.SETTINGS.items():
        _, family = ab.mechcont_family(tol)
        fam, iterations, solves = ab.mechcont_iterations(family)
        assert ab.agree(auto, fam, lines.append, name), lines
        assert solves >= len(fam) - 1 and iterations >= 2 * solves  # every orbit but the start corrected
    wrong = [r if r[0] != "UZ" else ["UZ", "0.3", "1.6093"] for r in auto]
    assert not ab.agree(wrong, fam, lines.append)  # a period 6e-5 off is no agreement
