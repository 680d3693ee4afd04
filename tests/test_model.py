"""The typed model: declared fields only, compiled once per structure, listed without compiling.

A model (:class:`mechcont.equations.Model`) is an equation system with declared fields; nothing
is attached after construction. Its equations are generated and compiled once per structure:
a build at other parameter values compiles nothing (counted with ``MECHCONT_NO_CACHE=1``, so
the disk cache cannot hide a rebuild) and gives the same results as a fresh build at those
values. ``mechcont models`` lists every model without compiling anything.
"""

import dataclasses
import json
import os
import pickle
import subprocess
import sys

import numpy as np
import pytest
from cli_helpers import make_runner

from mechcont.analysis.downlock import downlock_point
from mechcont.continuation import ContinuationOptions, continuation, find_equilibrium
from mechcont.equations import EquationSystem, Model, _cache, _codegen
from mechcont.mechanism import load_description
from mechcont.models import build_overcentre, describe_model, load_model, model_names
from mechcont.models.dual_sidestay import build_dual_sidestay_kinematics
from mechcont.models.nose_gear import build_nose_gear

DECLARED = {f.name for f in dataclasses.fields(Model)}

BUILDS = {
    "overcentre": lambda: build_overcentre(LU=0.5),
    "nose_gear": lambda: build_nose_gear(LU=1.31),
    "dual_sidestay": build_dual_sidestay_kinematics,
    "fourbar": lambda: load_model("fourbar", k=250.0),
    "lockstay": lambda: load_model("lockstay.toml"),
    "fivebar_reduced": lambda: load_description("fivebar").build_reduced(),
}


def _counts() -> tuple[int, int, int]:
    """Functions compiled in this process, and disk-cache look-ups (hits, misses)."""
    return _codegen.COUNTS["compiled"], _cache.STATS["hits"], _cache.STATS["misses"]


def _use_everything(system, x=None) -> None:
    """Evaluate every compiled part once (residual, Jacobian, second derivatives, mechanics, drawing)."""
    x = system.defaults() if x is None else x
    system.residual_and_jacobian(x)
    system.jacobian_derivative(x, np.ones(len(x)))
    system.limit_values(x)
    if system.mechanics is not None:
        system.mechanics.stability(x)
        system.mechanics.mass(x)
    system.scene(x)
    if system.coordinates_of is not None:
        system.coordinates_of(x)
        system.dropped_residual(x)


def _fields(model) -> set[str]:
    """The attributes of ``model`` once its symbolic parts are read (a model loaded from a pickle or
    the disk cache unpickles them on first use, see mechcont.equations._deferred)."""
    model.equations, model.symbols  # noqa: B018 - read for their side effect
    return set(vars(model))


@pytest.mark.parametrize("name", list(BUILDS))
def test_a_built_model_has_its_declared_fields_only(name):
    model = BUILDS[name]()
    assert isinstance(model, Model)
    assert _fields(model) == DECLARED
    with pytest.raises(AttributeError, match="no field 'downlock_angle'"):
        model.downlock_angle = 0.0  # nothing can be bolted on
    # copies keep exactly the declared fields, and the fields themselves
    for copy in (model.with_values({model.parameter_names[0]: model.defaults()[model.index(model.parameter_names[0])]}),
                 pickle.loads(pickle.dumps(model)), Model.from_compiled_state(pickle.loads(pickle.dumps(
                     model.compiled_state())))):
        assert type(copy) is Model and _fields(copy) == DECLARED and copy.unpickled_without == ()
        assert copy.reaction_names == model.reaction_names and copy.conditions == model.conditions
        assert copy.downlock == model.downlock
        x = model.defaults()
        assert [b.tobytes() for _, b in copy.scene(x).bars] == [b.tobytes() for _, b in model.scene(x).bars]


def test_no_getattr_probing_is_left_in_the_readers():
    """Analyses, outputs, dynamics and the CLI read a model's declared fields, never probe for attributes
    (the spatial generator included)."""
    import re
    from pathlib import Path

    import mechcont

    root = Path(mechcont.__file__).parent
    facts = DECLARED - {f.name for f in dataclasses.fields(EquationSystem)} | {"scene", "check_values", "mechanics"}
    probe = re.compile(r"(?:getattr|hasattr)\([^,()]+, \"(" + "|".join(sorted(facts)) + r")\"")
    found = [(str(f.relative_to(root)), m.group(1)) for f in root.rglob("*.py")
             for m in probe.finditer(f.read_text())]
    assert found == []


@pytest.fixture
def no_disk_cache(monkeypatch):
    monkeypatch.setenv("MECHCONT_NO_CACHE", "1")


def _lockstay():
    return load_description("lockstay").build, {"k": 26000.0, "LU": 0.61, "Ax": -1.48}


def _fivebar_reduced():
    return load_description("fivebar").build_reduced, {"k1": 310.0}


STRUCTURES = {  # name -> (a build function over one structure, values that change)
    "lockstay": _lockstay,
    "fivebar_reduced": _fivebar_reduced,
    "nose_gear": lambda: (build_nose_gear, {"LU": 1.31, "l_sp1": 0.05}),
    "overcentre": lambda: (build_overcentre, {"LU": 0.7, "L1": 1.4}),
}


@pytest.mark.parametrize("name", list(STRUCTURES))
def test_a_parameter_change_compiles_nothing(no_disk_cache, name):
    build, changed = STRUCTURES[name]()
    first = build()
    _use_everything(first)
    before = _counts()
    other = build(**changed)
    _use_everything(other)
    assert _counts() == before  # nothing generated, compiled or even looked up
    assert other._code is first._code and other.mechanics is first.mechanics
    for k, v in changed.items():
        assert other.defaults()[other.index(k)] == v


def test_load_model_with_overrides_compiles_nothing(no_disk_cache):
    for name, change in (("nose_gear.toml", {"LU": 1.31}), ("fourbar", {"k": 260.0}), ("nose_gear", {"LU": 1.29}),
                         ("overcentre", {"LU": 0.9}), ("dual_sidestay_kinematics", {"delta": 0.05})):
        _use_everything(load_model(name))
        before = _counts()
        _use_everything(load_model(name, **change))
        assert _counts() == before, name


def _assert_same(a, b, tol=1e-12):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape
    assert np.all(np.abs(a - b) <= tol * np.maximum(1.0, np.abs(b))), np.max(np.abs(a - b))


def test_new_values_give_what_a_fresh_build_gives():
    """A build at new values (the first build's code, the start assembled again) equals a fresh build."""
    values = {"k": 26000.0, "LU": 0.61, "Ax": -1.48, "L_up": 1.06}
    mech = load_description("lockstay")
    default = mech.build()
    reused = mech.build(**values)
    fresh = load_description("lockstay").build(**values)
    assert reused._code is default._code and fresh._code is not default._code
    # the start is assembled again at the new values (the links' angles move with L_up and Ax)
    assert np.max(np.abs(reused.defaults()[:9] - default.defaults()[:9])) > 1e-3
    _assert_same(reused.defaults(), fresh.defaults())
    _assert_same(reused.scales(), fresh.scales())
    assert reused.conditions == fresh.conditions and reused.downlock == fresh.downlock
    x = fresh.defaults() + 1e-3
    _assert_same(reused.residual(x), fresh.residual(x))
    _assert_same(reused.jacobian(x), fresh.jacobian(x))
    # and so do the analyses: a downlocked equilibrium and a continuation branch from it
    xr, xf = downlock_point(reused), downlock_point(fresh)
    _assert_same(xr, xf)
    opts = ContinuationOptions(bounds={"k": (15000.0, 40000.0)}, max_steps=40)
    br = continuation(reused, xr, "k", hold=list(reused.downlock.hold), free=[reused.downlock.force], options=opts)
    bf = continuation(fresh, xf, "k", hold=list(fresh.downlock.hold), free=[fresh.downlock.force], options=opts)
    _assert_same(br.values, bf.values)


def test_nose_gear_at_new_values_equals_a_fresh_structure(monkeypatch):
    from mechcont.models import nose_gear

    build_nose_gear()
    reused = build_nose_gear(LU=1.31, l_sp1=0.05)
    monkeypatch.setattr(nose_gear, "_STRUCTURE", {})
    fresh = build_nose_gear(LU=1.31, l_sp1=0.05)
    assert fresh._code is not reused._code
    _assert_same(reused.downlock.pose, fresh.downlock.pose)
    _assert_same(reused.downlock.assemble({"LU": 1.3}), fresh.downlock.assemble({"LU": 1.3}))
    x = find_equilibrium(reused, values={"F": 150.0}, guess=reused.downlock.pose)
    _assert_same(x, find_equilibrium(fresh, values={"F": 150.0}, guess=fresh.downlock.pose))


def test_models_lists_without_compiling_and_says_what_a_build_says():
    code = """
import contextlib, io, json, sys
from mechcont.cli import main
from mechcont.equations import _cache, _codegen
from mechcont.models import _registry
sys.argv = ["mechcont", "models", "--json"]
out = io.StringIO()
with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
    main()
print(json.dumps({"listed": len(json.loads(out.getvalue())), "compiled": _codegen.COUNTS["compiled"],
                  "cache": _cache.STATS, "descriptions_read": len(_registry._DESCRIPTIONS)}))
"""
    env = {**os.environ, "MECHCONT_NO_CACHE": "1"}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout.strip().splitlines()[-1])
    assert got == {"listed": len(model_names()), "compiled": 0, "cache": {"hits": 0, "misses": 0, "writes": 0},
                   "descriptions_read": 0}
    assert make_runner()("models", "lockstay.toml").exit_code == 0
    for name in model_names():
        s, m = describe_model(name), load_model(name)
        assert s.description == m.description and s.n_equations == len(m.equations)
        assert s.states == tuple((v.name, v.unit, v.description) for v in m.variables if v.kind == "state")
        assert s.parameters == tuple((v.name, v.value, v.unit, v.description) for v in m.variables
                                     if v.kind == "parameter")


def test_model_from_text_shares_the_disk_cache_entry_of_a_file_with_that_text(tmp_path, monkeypatch):
    """model_from_text(text, "name.toml") and load_model of a file name.toml holding that text are one
    entry of the disk cache; another text is another entry (never a stale model)."""
    from mechcont.equations import _cache
    from mechcont.mechanism._paths import find_description
    from mechcont.models import load_model, model_from_text

    monkeypatch.setenv("MECHCONT_CACHE_DIR", str(tmp_path / "cache"))
    text = find_description("fourbar").read_text()
    a = model_from_text(text, "fourbar.toml")
    (tmp_path / "fourbar.toml").write_text(text)
    writes = _cache.STATS["writes"]
    b = load_model(tmp_path / "fourbar.toml")
    assert _cache.STATS["writes"] == writes and b.names == a.names
    np.testing.assert_array_equal(b.defaults(), a.defaults())
    other = model_from_text(text.replace("k = { value = ", "k = { value = 1", 1), "fourbar.toml")
    assert _cache.STATS["writes"] == writes + 1 and other.names == a.names
