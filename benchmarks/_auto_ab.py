"""The periodic orbits of AUTO-07p's demo ``ab`` in AUTO and in mechcont: the problem, the check, the timed work.

``ab`` (the A -> B reaction) at B = 14, beta = 3 has two Hopf points on its equilibria in D
(D = 0.16504 and 0.33655, closed forms from the trace of the Jacobian: see :func:`hopf_values`). The
family of periodic orbits from the first, with NTST = 50 and NCOL = 4 in both programs, is continued
in D to D = 0.3 (AUTO: ``UZSTOP``; mechcont: a bound), passing its fold of cycles near D = 0.1617.
AUTO runs its own way (IPS = 1 then IPS = 2 from the HB label, ICP = [1, 11], IAD = 3, ISP = 2,
its demo's tolerances EPSL = EPSU = 1e-7, THL(11) = 0, the equations typed again in Fortran with
AUTO's finite-difference Jacobian as in its demo); mechcont through :func:`mechcont.continuation.cycles_from_hopf`.
Before timing, the Hopf points, the fold of cycles (D and period) and the period at D = 0.3 are checked
to agree.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

B, BETA = 14.0, 3.0
D_END = 0.3
NTST, NCOL = 50, 4
#: AUTO's periodic family from the first HB is checked against mechcont's to this (AUTO converges to 1e-7)
REL_TOL = 1e-5

FORTRAN = """\
! AUTO-07p's demo ab (the A -> B reaction), typed again: u1' = -u1 + D (1 - u1) e^u2,
! u2' = -u2 + D B (1 - u1) e^u2 - beta u2; PAR(1) = D, PAR(2) = B, PAR(3) = beta.
SUBROUTINE FUNC(NDIM, U, ICP, PAR, IJAC, F, DFDU, DFDP)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM, ICP(*), IJAC
  DOUBLE PRECISION, INTENT(IN) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(OUT) :: F(NDIM)
  DOUBLE PRECISION, INTENT(INOUT) :: DFDU(NDIM, NDIM), DFDP(NDIM, *)
  DOUBLE PRECISION E
  E = EXP(U(2))
  F(1) = -U(1) + PAR(1) * (1 - U(1)) * E
  F(2) = -U(2) + PAR(1) * PAR(2) * (1 - U(1)) * E - PAR(3) * U(2)
END SUBROUTINE FUNC

SUBROUTINE STPNT(NDIM, U, PAR, T)
  IMPLICIT NONE
  INTEGER, INTENT(IN) :: NDIM
  DOUBLE PRECISION, INTENT(INOUT) :: U(NDIM), PAR(*)
  DOUBLE PRECISION, INTENT(IN) :: T
  PAR(1) = 0.0D0
  PAR(2) = {b}
  PAR(3) = {beta}
  U(1) = 0.0D0
  U(2) = 0.0D0
END SUBROUTINE STPNT

SUBROUTINE BCND
END SUBROUTINE BCND
SUBROUTINE ICND
END SUBROUTINE ICND
SUBROUTINE FOPT
END SUBROUTINE FOPT
SUBROUTINE PVLS
END SUBROUTINE PVLS
"""

EQUILIBRIA = """\
NDIM=2, IPS=1, IRS=0, ILP=1
ICP=[1]
NTST=50, NCOL=4, IAD=3, ISP=1, ISW=1, IPLT=0, NBC=0, NINT=0
NMX=500, NPR=500, MXBF=0, IID=2, ITMX=8, ITNW=5, NWTN=3, JAC=0
EPSL=1e-07, EPSU=1e-07, EPSS=1e-05
DS=0.01, DSMIN=0.0001, DSMAX=0.05, IADS=1
THL={{11: 0.0}}, THU={{}}
UZSTOP={{1: 0.5}}
"""

CYCLES = """\
NDIM=2, IPS=2, IRS=0, ILP=1
ICP=[1, 11]
NTST={ntst}, NCOL={ncol}, IAD=3, ISP=2, ISW=1, IPLT=0, NBC=0, NINT=0
NMX=500, NPR=500, MXBF=0, IID=2, ITMX=8, ITNW=5, NWTN=3, JAC=0
EPSL=1e-07, EPSU=1e-07, EPSS=1e-05
DS=0.01, DSMIN=0.0001, DSMAX=0.5, IADS=1
THL={{11: 0.0}}, THU={{}}
UZSTOP={{1: {d_end!r}}}
"""

SCRIPT = """\
import resource


def cpu():
    # the CPU time of the finished child processes: AUTO's compiled program, run once per run()
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


eq = run(e='ab', c='ab.eq')
for p in eq('HB'):
    print('RESULT HB', repr(float(p['PAR(1)'])))
hb = [p for p in eq('HB') if abs(p['PAR(1)'] - {d_hb!r}) < 1e-3][0]
c0 = cpu()
po = run(hb, e='ab', c='ab.po')
print('RESULT CPU', repr(cpu() - c0))
for p in po('LP'):
    print('RESULT LPC', repr(float(p['PAR(1)'])), repr(float(p['PAR(11)'])))
for p in po('UZ'):
    print('RESULT UZ', repr(float(p['PAR(1)'])), repr(float(p['PAR(11)'])))
"""


def hopf_values(b: float = B, beta: float = BETA) -> list[tuple[float, float, float]]:
    """``(D, u1, u2)`` of ab's Hopf points: on the equilibria u1 = (1 + beta) u2 / b, D = u1 e^(-u2) / (1 - u1),
    the trace of the Jacobian, -1/(1 - u1) - 1 - beta + b u1, vanishes (its determinant is positive there)."""
    a2, a1, a0 = -b, b + 1 + beta, -(2 + beta)
    disc = math.sqrt(a1 * a1 - 4 * a2 * a0)
    out = []
    for u1 in sorted(((-a1 + disc) / (2 * a2), (-a1 - disc) / (2 * a2))):
        u2 = b * u1 / (1 + beta)
        out.append((u1 * math.exp(-u2) / (1 - u1), u1, u2))
    return out


def write_problem(folder: Path) -> None:
    """``ab.f90``, ``c.ab.eq``, ``c.ab.po`` and the script ``cycles.auto`` in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "ab.f90").write_text(FORTRAN.format(b=f"{B!r}D0", beta=f"{BETA!r}D0"))
    (folder / "c.ab.eq").write_text(EQUILIBRIA.format())
    (folder / "c.ab.po").write_text(CYCLES.format(ntst=NTST, ncol=NCOL, d_end=D_END))
    (folder / "cycles.auto").write_text(SCRIPT.format(d_hb=hopf_values()[0][0]))


#: mechcont's settings compared with AUTO, by label: its defaults (``newton_tol`` 1e-10, the largest Newton correction
#: relative to the largest unknown) and AUTO's demo's tolerance (EPSL = EPSU = 1e-7 on the relative corrections of
#: the parameter and the orbit); mechcont's Jacobian stays exact (AUTO's demo differences its own, JAC = 0)
SETTINGS: dict[str, float | None] = {"mechcont, its defaults (Newton to 1e-10)": None,
                                     "mechcont, AUTO's tolerance (Newton to 1e-7)": 1e-7}


def mechcont_family(newton_tol: float | None = None):
    """The model and the timed function (the family from the first Hopf point to D = 0.3); ``newton_tol``: the
    corrector's tolerance (None: mechcont's default)."""
    import sympy as sp

    from mechcont.continuation import ContinuationOptions, EngineSettings, cycles_from_hopf
    from mechcont.equations import ode_model

    u1, u2, D, Bs, beta = sp.symbols("u1 u2 D B beta", real=True)
    e = sp.exp(u2)
    m = ode_model("ab", {"u1": 0.0, "u2": 0.0}, {"D": 0.0, "B": B, "beta": BETA},
                  {"u1": -u1 + D * (1 - u1) * e, "u2": -u2 + D * Bs * (1 - u1) * e - beta * u2})
    d, a, b = hopf_values()[0]
    x = m.vector({"D": d, "u1": a, "u2": b})
    engine = EngineSettings() if newton_tol is None else EngineSettings(newton_tol=newton_tol)
    opts = ContinuationOptions(ds=0.01, dsmax=0.5, bounds={"D": (0.0, D_END)}, engine=engine)

    def family():
        return cycles_from_hopf(m, x, "D", ntst=NTST, ncol=NCOL, options=opts)

    return m, family


def auto_cpu(results: list[list[str]]) -> float:
    """The CPU time (s, user + system) of AUTO's program in the periodic run, from the script's ``RESULT CPU`` line."""
    return next(float(r[1]) for r in results if r[0] == "CPU")


def auto_iterations(diagnostics: str) -> tuple[int, int]:
    """``(Newton iterations, orbits)`` of an AUTO run from its diagnostics file (``fort.9``, IID = 2): the rows of its
    iteration tables with IT >= 1 (IT 0 is the predicted orbit; the iterations of locating a special point count
    too), and its ``Iterations :`` lines (one per accepted orbit)."""
    iterations = len(re.findall(r"^\s+-?\d+\s+-?\d+\s+([1-9]\d*)\s+\S+\s+\S+\s*$", diagnostics, flags=re.M))
    return iterations, len(re.findall(r"Iterations\s+:", diagnostics))


def mechcont_iterations(family) -> tuple[object, int, int]:
    """``(family(), Newton iterations, solves)``: one call of ``family`` with the collocation corrector's iterations
    counted (every Newton solve of the call: the steps, the rejected ones and the located special points)."""
    from mechcont.continuation import _cycle_system

    newton = _cycle_system.CycleSystem.newton
    counts = [0, 0]

    def counted(self, *args, **kwargs):
        out = newton(self, *args, **kwargs)
        counts[0] += out[2]
        counts[1] += 1
        return out

    _cycle_system.CycleSystem.newton = counted
    try:
        fam = family()
    finally:
        _cycle_system.CycleSystem.newton = newton
    return fam, counts[0], counts[1]


def agree(results: list[list[str]], fam, say, name: str = "mechcont") -> bool:
    """Check AUTO's ``RESULT`` lines against mechcont's family ``fam`` (from the settings ``name``, for the printed
    lines): the Hopf points (AUTO's against the closed form; the family starts at the first), the fold of cycles
    (D, period) and the period at D = 0.3, to REL_TOL; ``say(line)`` prints. True when they agree."""
    ok = True
    theirs = sorted(float(r[1]) for r in results if r[0] == "HB")
    ours = sorted(h[0] for h in hopf_values())
    same = len(theirs) == len(ours) and all(abs(a - b) <= 1e-6 * b for a, b in zip(theirs, ours))
    say(f"  ab HB (D): closed form {', '.join(f'{v:.10g}' for v in ours)} | AUTO {', '.join(f'{v:.10g}' for v in theirs)}"
        f"  {'agree' if same else 'DISAGREE'}")
    ok &= same
    start = float(fam.p[0])
    same = fam.labels[0] == "HB" and abs(start - ours[0]) <= 1e-6 * ours[0]
    say(f"  ab first orbit ({name}): {fam.labels[0]} at D = {start:.10g}  {'agree' if same else 'DISAGREE'}")
    ok &= same
    for kind, label in (("LPC", "LPC"), ("UZ", "EP")):
        rows = [(float(r[1]), float(r[2])) for r in results if r[0] == kind]
        mine = [(float(fam.p[i]), float(fam.period[i])) for n, i in fam.point_names() if fam.labels[i] == label]
        same = len(rows) == len(mine) and all(abs(a - c) <= REL_TOL * abs(c) and abs(b - d) <= REL_TOL * abs(d)
                                              for (a, b), (c, d) in zip(rows, mine))
        say(f"  ab {kind} (D, period): {name} {mine} | AUTO {rows}  {'agree' if same else 'DISAGREE'}")
        ok &= same
    return ok
