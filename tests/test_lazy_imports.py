"""Light paths import nothing heavy they do not use: ``import mechcont`` imports no SymPy,
SciPy or Matplotlib, and a continuation, fold or listing command imports no Matplotlib,
``scipy.integrate``/``scipy.optimize``, Exudyn, pandas, pyarrow or Dask (each costs a CLI
run 0.1-1 s). Checked in a fresh interpreter, the commands run in-process.

With a warm disk cache a command starts like a compiled tool: the built-in models and the
description files load their structure and compiled code from it, so no command imports
SymPy (0.5 s), the readers or generators of descriptions, or SciPy modules it does not call (a
``--set`` on a description included: what the description writes in parameters, a stop's limit or a
condition's target, comes from the model's compiled numeric form); and an edited description never
reuses the entry of its old text."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

HEAVY = ["matplotlib", "scipy.integrate", "scipy.optimize", "exudyn", "pandas", "pyarrow", "dask"]

SCRIPT = r"""
import contextlib, io, json, sys
heavy = json.loads(sys.argv[1])
found = {}
import mechcont
found["import mechcont"] = [m for m in [*heavy, "scipy", "sympy", "symengine", "numpy"] if m in sys.modules]
from mechcont.cli import main
for args in json.loads(sys.argv[2]):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(args)
        except SystemExit as exc:
            assert not exc.code, (args, exc.code)
    found[" ".join(args)] = [m for m in heavy if m in sys.modules]
print(json.dumps(found))
"""


def test_light_paths_import_nothing_heavy():
    commands = [
        ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
         "--bounds", "theta1=-1.2:1.2", "--quiet"],
        ["folds", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F", "--along", "LU",
         "--bounds", "LU=0.1:2", "--quiet"],
        ["models", "overcentre", "fourbar"],
    ]
    out = subprocess.run([sys.executable, "-c", SCRIPT, json.dumps(HEAVY), json.dumps(commands)],
                         capture_output=True, text=True, check=True, timeout=300).stdout
    found = json.loads(out)
    assert found == {"import mechcont": [], **{" ".join(c): [] for c in commands}}


def _blas_threads(env_value: str | None) -> str:
    import os

    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if env_value is not None:
        env["OPENBLAS_NUM_THREADS"] = env_value
    code = "import os, mechcont, numpy; print(os.environ.get('OPENBLAS_NUM_THREADS'))"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          check=True).stdout.strip()


def test_one_blas_thread_by_default_and_the_users_choice_kept():
    # small matrices on a shared machine: threads spin (a 63 x 64 SVD 96 ms instead of 0.5 ms)
    assert _blas_threads(None) == "1"
    assert _blas_threads("3") == "3"


EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SPRING_LOCK = Path(__file__).resolve().parent / "data" / "spring_lock.toml"
#: what a command with a warm cache must not import (unless it plots, which none of these does)
NOT_WARM = ["sympy", "matplotlib", "pandas", "scipy.integrate", "scipy.optimize", "scipy.interpolate", "scipy.sparse",
            "scipy.special", "mechcont.mechanism._description", "mechcont.mechanism._generate",
            "mechcont.mechanism.spatial", "mechcont.analysis.design"]
WARM_SCRIPT = r"""
import contextlib, io, json, sys
from mechcont.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        main(json.loads(sys.argv[2]))
    except SystemExit as exc:
        assert not exc.code, exc.code
print(json.dumps([m for m in json.loads(sys.argv[1]) if m in sys.modules]))
"""


FILL_SCRIPT = r"""
import contextlib, io, json, sys
from mechcont.cli import main
for args in json.loads(sys.argv[1]):
    with contextlib.redirect_stdout(io.StringIO()):
        try:
            main(args)
        except SystemExit as exc:
            assert not exc.code, (args, exc.code)
"""


def _modules_after(args: list[str]) -> list[str]:
    """The modules of :data:`NOT_WARM` a fresh interpreter imported running ``mechcont args``."""
    env = {k: v for k, v in os.environ.items() if k != "MECHCONT_NO_CACHE"}
    out = subprocess.run([sys.executable, "-c", WARM_SCRIPT, json.dumps(NOT_WARM), json.dumps(args)], env=env,
                         capture_output=True, text=True, check=True, timeout=900).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_with_a_warm_cache_no_command_imports_sympy_or_what_it_does_not_call():
    commands = [
        ["continue", "overcentre", "--set", "LU=0.4", "--start", "theta1=0.3", "--vary", "F",
         "--bounds", "theta1=-1.2:1.2"],
        ["models"],
        ["downlock", "nose_gear", "--vary", "l_sp1", "--bounds", "l_sp1=-0.175:0.175"],
        ["check", str(EXAMPLES / "dual_sidestay.toml")],  # generated spatial gear
        ["check", "nose_gear.toml"],  # a planar description
        ["continue", "fourbar.toml", "--vary", "T", "--bounds", "T=-5:5", "--quiet"],
        ["continue", "dual_sidestay_kinematics", "--vary", "theta", "--bounds", "theta=0:1.5", "--quiet"],
        # a time simulation (its redundant-row choice is the statics' own, which lived in the spatial package, whose
        # description imports SymPy); it integrates, so SciPy's integrator and what it imports are its own
        ["freefall", str(EXAMPLES / "freefall_leg.toml"), "--start", "angle=3.0", "--lock", "downlock", "--until", "2"],
        # --set on a description with a stop, a condition's target and a damper written in parameters: the values
        # those fields take at the --set values (Model.fields_at) and their derivatives (a held target's, for the
        # sensitivity) come from the model's compiled numeric form, not from the description's SymPy expressions
        ["continue", str(SPRING_LOCK), "--set", "c_max=0.25", "--set", "k=25", "--vary", "F", "--stops", "--start",
         "angle=0.2", "--bounds", "F=0:20", "--bounds", "theta_bar=-1:1", "--quiet"],
        ["sensitivity", str(SPRING_LOCK), "--downlock", "--params", "c_max,h", "--set", "c_max=0.25"],
    ]
    integrates = {"scipy.integrate", "scipy.optimize", "scipy.interpolate", "scipy.sparse", "scipy.special"}
    # one process runs them all first and fills the cache (the session's cache: warm after one run; a fresh
    # interpreter for each command's fill was as many interpreter start-ups more, each ~0.4 s)
    env = {k: v for k, v in os.environ.items() if k != "MECHCONT_NO_CACHE"}
    subprocess.run([sys.executable, "-c", FILL_SCRIPT, json.dumps(commands)], env=env, capture_output=True, text=True,
                   check=True, timeout=900)
    for args in commands:
        assert [m for m in _modules_after(args) if not (args[0] == "freefall" and m in integrates)] == [], args


def test_an_edited_description_never_reuses_a_stale_entry(tmp_path, monkeypatch):
    """One number edited in a description file: the next load builds the edited mechanism (the same
    as a build without any cache), and the original text still finds its own entry."""
    from mechcont.equations import _cache
    from mechcont.mechanism import check_report
    from mechcont.mechanism._paths import DATA_DIR
    from mechcont.models import describe_model, load_model

    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MECHCONT_NO_CACHE", raising=False)
    text = (DATA_DIR / "fourbar.toml").read_text()
    assert text.count('D = ["d", 0]') == 1 and text.count("k = { value = 200.0,") == 1
    path = tmp_path / "linkage.toml"
    path.write_text(text)
    before = load_model(path)
    assert load_model(path).variable("k").value == 200.0  # the same text: from the disk cache
    hits = _cache.STATS["hits"]
    for old, new in (('D = ["d", 0]', 'D = ["d", 0.05]'), ("k = { value = 200.0,", "k = { value = 260.0,")):
        edited = text.replace(old, new)
        path.write_text(edited)
        os.utime(path, ns=(0, 0))  # the same modification time as before: only the text tells
        model = load_model(path)
        monkeypatch.setenv("MECHCONT_NO_CACHE", "1")
        truth = load_model(path)
        monkeypatch.delenv("MECHCONT_NO_CACHE")
        x = before.defaults()
        np.testing.assert_allclose(model.defaults(), truth.defaults(), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(model.residual(x), truth.residual(x), rtol=1e-12, atol=1e-12)
        # the edit shows: in the equations (the anchor) or in the values (the stiffness)
        assert not (np.allclose(model.residual(x), before.residual(x), rtol=1e-9, atol=1e-12)
                    and np.allclose(model.defaults(), x, rtol=1e-9, atol=1e-12)), new
        assert describe_model(str(path)).parameters == tuple((v.name, v.value, v.unit, v.description)
                                                             for v in truth.variables if v.kind == "parameter")
        assert check_report(str(path)).system.variable("k").value == truth.variable("k").value
    path.write_text(text)
    again = load_model(path)
    assert _cache.STATS["hits"] > hits and again.variable("k").value == 200.0
    np.testing.assert_array_equal(again.residual(before.defaults()), before.residual(before.defaults()))


def test_every_command_is_found_where_the_lazy_group_looks_for_it():
    """``mechcont CMD`` imports only CMD's module (``_app.COMMAND_MODULES``): every module of the
    CLI package imported, the commands registered are exactly the map's, each defined in its module."""
    import importlib
    import pkgutil

    import mechcont.cli as package
    from mechcont.cli._app import COMMAND_MODULES, cli

    for info in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"mechcont.cli.{info.name}")
    assert set(cli.commands) == set(COMMAND_MODULES)
    for name, command in cli.commands.items():
        assert command.callback.__module__ == f"mechcont.cli.{COMMAND_MODULES[name]}", name


LAZY_COMMANDS_SCRIPT = r"""
import contextlib, io, json, sys
from mechcont.cli import main
out = io.StringIO()
with contextlib.redirect_stdout(out):
    try:
        main(json.loads(sys.argv[1]))
    except SystemExit as exc:
        assert not exc.code, exc.code
print(json.dumps([sorted(m for m in sys.modules if m.startswith("mechcont.cli.")), out.getvalue()]))
"""


def _cli_modules_and_output(args: list[str]) -> tuple[list[str], str]:
    out = subprocess.run([sys.executable, "-c", LAZY_COMMANDS_SCRIPT, json.dumps(args)], capture_output=True, text=True,
                         check=True, timeout=300).stdout
    modules, text = json.loads(out.strip().splitlines()[-1])
    return modules, text


def test_a_command_imports_no_other_commands_module_and_help_lists_them_all():
    from mechcont.cli._app import COMMAND_MODULES

    modules, _ = _cli_modules_and_output(["models"])
    assert [m for m in modules if m.removeprefix("mechcont.cli.") in COMMAND_MODULES.values()] == ["mechcont.cli.models"]
    modules, text = _cli_modules_and_output(["--help"])
    listed = {line.split()[0] for line in text.split("Commands:")[1].splitlines() if line.strip()}
    assert listed == set(COMMAND_MODULES)


def test_the_stored_objects_key_follows_every_source_files_size_and_time(tmp_path):
    """Built models are keyed by the (size, modification time) of each of mechcont's modules, as
    Python keys its bytecode: a touched module or one edited to another size gives another key."""
    from mechcont.equations._stored import _sources

    (tmp_path / "sub").mkdir()
    (tmp_path / "__pycache__").mkdir()
    for name, text in (("a.py", "x = 1\n"), ("sub/b.py", "y = 2\n"), ("__pycache__/c.py", ""), ("notes.txt", "")):
        (tmp_path / name).write_text(text)
    before = _sources(str(tmp_path))
    assert [(rel, size) for rel, size, _ in before] == [("a.py", 6), ("sub/b.py", 6)]
    t = before[1][2]
    os.utime(tmp_path / "sub" / "b.py", ns=(t + 1000, t + 1000))  # the same text, saved again
    touched = _sources(str(tmp_path))
    assert touched[0] == before[0] and touched[1] == ("sub/b.py", 6, t + 1000)
    (tmp_path / "a.py").write_text("x = 10\n")
    os.utime(tmp_path / "a.py", ns=(before[0][2], before[0][2]))  # the old time: the size tells
    assert _sources(str(tmp_path))[0] == ("a.py", 7, before[0][2])


GC_SCRIPT = r"""
import contextlib, gc, io, json, sys, time
from mechcont.cli import main
from mechcont.cli._app import GC_PAUSE
if sys.argv[1] == "off":
    gc.disable()
t0 = time.monotonic()
with contextlib.redirect_stdout(io.StringIO()):
    try:
        main(["models"])
    except SystemExit as exc:
        assert not exc.code, exc.code
took, paused = time.monotonic() - t0, not gc.isenabled()
limit = GC_PAUSE + (60 if sys.argv[1] == "on" else 1)  # on: until the timer fires; off: past its time
while not gc.isenabled() and time.monotonic() - t0 < limit:
    time.sleep(0.01)
print(json.dumps([took < 0.5 * GC_PAUSE, paused, gc.isenabled(), GC_PAUSE]))
"""


def test_the_garbage_collector_is_paused_for_the_start_up_only():
    """main() pauses the cyclic collector (the start-up's 40,000 long-lived objects scanned for nothing)
    and a timer turns it back on GC_PAUSE s later; a caller's own choice to keep it off stands."""
    # both interpreters at once: each spends most of its time waiting for (or past) the timer
    procs = {state: subprocess.Popen([sys.executable, "-c", GC_SCRIPT, state], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True) for state in ("on", "off")}
    results = {}
    for state, proc in procs.items():
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err
        results[state] = json.loads(out.strip().splitlines()[-1])

    quick, paused, enabled, pause = results["on"]
    assert enabled and 0 < pause <= 2
    assert paused or not quick  # (a run slower than half the pause may see the timer fire first)
    assert results["off"][1:3] == [True, False]  # still off GC_PAUSE + 1 s after the start
