"""The mypy ratchet (issue 34): the modules checked with ``disallow_untyped_defs`` may only grow.

A module leaves the list only by someone deleting it from pyproject.toml (mypy then stops checking it and
its functions can lose their annotations unnoticed): the list here is the floor, and every module whose
functions are all annotated must be on the list, so that annotating one makes it join."""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"

#: The floor: each of these is checked with disallow_untyped_defs (add, never remove; a module that is split or
#: renamed is replaced by its successors).
FLOOR = {
    "mechcont",
    "mechcont.__main__",
    "mechcont._dense",
    "mechcont._io",
    "mechcont._lazy",
    "mechcont._progress",
    "mechcont._roots",
    "mechcont._signals",
    "mechcont._status",
    "mechcont._version",
    "mechcont.analysis",
    "mechcont.analysis._cusp",
    "mechcont.analysis._downlock_point",
    "mechcont.analysis._optimum_map",
    "mechcont.analysis._reliability_checks",
    "mechcont.analysis._runs",
    "mechcont.analysis._slsqp",
    "mechcont.analysis._special_points",
    "mechcont.analysis._stop_events",
    "mechcont.analysis._stop_quantities",
    "mechcont.analysis._stop_search",
    "mechcont.analysis.design",
    "mechcont.analysis.design_sensitivity",
    "mechcont.analysis.downlock",
    "mechcont.analysis.dynamic_stability",
    "mechcont.analysis.ode_check",
    "mechcont.analysis.optimize",
    "mechcont.analysis.redundancy",
    "mechcont.analysis.reliability",
    "mechcont.analysis.rest_on_stops",
    "mechcont.analysis.retraction",
    "mechcont.analysis.sensitivity",
    "mechcont.analysis.stops",
    "mechcont.analysis.study",
    "mechcont.analysis.study._estimate",
    "mechcont.analysis.study._execute",
    "mechcont.analysis.study._kernels",
    "mechcont.analysis.study._results",
    "mechcont.analysis.study._spec",
    "mechcont.analysis.study._store",
    "mechcont.analysis.surface",
    "mechcont.analysis.unlock",
    "mechcont.cli",
    "mechcont.cli._app",
    "mechcont.cli._commands",
    "mechcont.cli._parse",
    "mechcont.cli._run",
    "mechcont.cli.check",
    "mechcont.cli.continue_",
    "mechcont.cli.cycles",
    "mechcont.cli.design",
    "mechcont.cli.downlock",
    "mechcont.cli.draw",
    "mechcont.cli.equations",
    "mechcont.cli.explore",
    "mechcont.cli.folds",
    "mechcont.cli.freefall",
    "mechcont.cli.models",
    "mechcont.cli.optimize",
    "mechcont.cli.paper",
    "mechcont.cli.sensitivity",
    "mechcont.cli.simulate",
    "mechcont.cli.study",
    "mechcont.cli.sweep",
    "mechcont.continuation",
    "mechcont.continuation._api",
    "mechcont.continuation._batch",
    "mechcont.continuation._branch",
    "mechcont.continuation._collocation",
    "mechcont.continuation._condensation",
    "mechcont.continuation._corrector",
    "mechcont.continuation._cycle_system",
    "mechcont.continuation._cycle_tests",
    "mechcont.continuation._events",
    "mechcont.continuation._fold_point",
    "mechcont.continuation._folds",
    "mechcont.continuation._hopf_plane",
    "mechcont.continuation._hopf_point",
    "mechcont.continuation._kernel",
    "mechcont.continuation._linalg",
    "mechcont.continuation._lyapunov",
    "mechcont.continuation._move",
    "mechcont.continuation._newton",
    "mechcont.continuation._options",
    "mechcont.continuation._palc",
    "mechcont.continuation._problem",
    "mechcont.continuation._scaling",
    "mechcont.continuation._sensitivity",
    "mechcont.continuation._special_point",
    "mechcont.continuation._start",
    "mechcont.continuation._table",
    "mechcont.continuation._variants",
    "mechcont.continuation.branch_rows",
    "mechcont.dynamics",
    "mechcont.dynamics._assembly",
    "mechcont.dynamics._budget",
    "mechcont.dynamics._checks",
    "mechcont.dynamics._compare",
    "mechcont.dynamics._compliant",
    "mechcont.dynamics._contact",
    "mechcont.dynamics._critical",
    "mechcont.dynamics._critical_scan",
    "mechcont.dynamics._dampers",
    "mechcont.dynamics._energy",
    "mechcont.dynamics._events",
    "mechcont.dynamics._exudyn",
    "mechcont.dynamics._freefall",
    "mechcont.dynamics._held_differences",
    "mechcont.dynamics._jumps",
    "mechcont.dynamics._mass",
    "mechcont.dynamics._ode",
    "mechcont.dynamics._peaks",
    "mechcont.dynamics._poses",
    "mechcont.dynamics._reactions",
    "mechcont.dynamics._redundant",
    "mechcont.dynamics._result",
    "mechcont.dynamics._settle",
    "mechcont.dynamics._simulate",
    "mechcont.dynamics._stall",
    "mechcont.dynamics._sweep",
    "mechcont.dynamics._udwadia_kalaba",
    "mechcont.dynamics.freefall",
    "mechcont.equations",
    "mechcont.equations._backend",
    "mechcont.equations._cache",
    "mechcont.equations._cache_key",
    "mechcont.equations._codegen",
    "mechcont.equations._compiled",
    "mechcont.equations._deferred",
    "mechcont.equations._dynamics",
    "mechcont.equations._layout",
    "mechcont.equations._linear_dynamics",
    "mechcont.equations._lock",
    "mechcont.equations._mechanics",
    "mechcont.equations._mechanism_dynamics",
    "mechcont.equations._model",
    "mechcont.equations._ode_text",
    "mechcont.equations._protocols",
    "mechcont.equations._rates",
    "mechcont.equations._scene",
    "mechcont.equations._stability",
    "mechcont.equations._stored",
    "mechcont.equations._system",
    "mechcont.equations._variables",
    "mechcont.errors",
    "mechcont.mechanism",
    "mechcont.mechanism._assembly",
    "mechcont.mechanism._bar_points",
    "mechcont.mechanism._bodies",
    "mechcont.mechanism._check",
    "mechcont.mechanism._compiled",
    "mechcont.mechanism._compliant",
    "mechcont.mechanism._condition_kinds",
    "mechcont.mechanism._conditions",
    "mechcont.mechanism._description",
    "mechcont.mechanism._diagnose",
    "mechcont.mechanism._element_states",
    "mechcont.mechanism._elements",
    "mechcont.mechanism._equilibrium",
    "mechcont.mechanism._expr",
    "mechcont.mechanism._file",
    "mechcont.mechanism._forces",
    "mechcont.mechanism._generate",
    "mechcont.mechanism._kinematics",
    "mechcont.mechanism._locate",
    "mechcont.mechanism._ode_file",
    "mechcont.mechanism._paths",
    "mechcont.mechanism._plugin",
    "mechcont.mechanism._reduce",
    "mechcont.mechanism._scene",
    "mechcont.mechanism._stops",
    "mechcont.mechanism._tables",
    "mechcont.mechanism._values",
    "mechcont.mechanism.elements",
    "mechcont.mechanism.elements._base",
    "mechcont.mechanism.elements._rotary",
    "mechcont.mechanism.elements.actuator",
    "mechcont.mechanism.elements.damper",
    "mechcont.mechanism.elements.spring",
    "mechcont.mechanism.elements.stop",
    "mechcont.mechanism.elements.torsion_damper",
    "mechcont.mechanism.elements.torsion_spring",
    "mechcont.mechanism.elements.tyre",
    "mechcont.mechanism.joints",
    "mechcont.mechanism.joints._base",
    "mechcont.mechanism.joints.pin_in_slot",
    "mechcont.mechanism.joints.prismatic",
    "mechcont.mechanism.joints.revolute",
    "mechcont.mechanism.joints.slider",
    "mechcont.mechanism.joints.weld",
    "mechcont.mechanism.loads",
    "mechcont.mechanism.loads._base",
    "mechcont.mechanism.loads.custom",
    "mechcont.mechanism.loads.drag",
    "mechcont.mechanism.loads.force",
    "mechcont.mechanism.loads.gravity",
    "mechcont.mechanism.loads.moment",
    "mechcont.mechanism.spatial",
    "mechcont.mechanism.spatial._description",
    "mechcont.mechanism.spatial._dropped",
    "mechcont.mechanism.spatial._file",
    "mechcont.mechanism.spatial._generate",
    "mechcont.mechanism.spatial._kinematics",
    "mechcont.mechanism.spatial._rotation",
    "mechcont.mechanism.spatial._scene",
    "mechcont.mechanism.spatial.joints",
    "mechcont.mechanism.spatial.joints._base",
    "mechcont.mechanism.spatial.joints.cylindrical",
    "mechcont.mechanism.spatial.joints.inline",
    "mechcont.mechanism.spatial.joints.prismatic",
    "mechcont.mechanism.spatial.joints.revolute",
    "mechcont.mechanism.spatial.joints.spherical",
    "mechcont.mechanism.spatial.joints.universal",
    "mechcont.mechanism.spatial.joints.weld",
    "mechcont.models",
    "mechcont.models._registry",
    "mechcont.models.dual_sidestay",
    "mechcont.models.dual_sidestay_description",
    "mechcont.models.dual_sidestay_geometry",
    "mechcont.models.nose_gear",
    "mechcont.models.nose_gear_geometry",
    "mechcont.models.overcentre",
    "mechcont.models.overcentre_scene",
    "mechcont.outputs",
    "mechcont.outputs._branch_frames",
    "mechcont.outputs._drawing_parts",
    "mechcont.outputs._explore_cycles",
    "mechcont.outputs._explore_page",
    "mechcont.outputs._explore_points",
    "mechcont.outputs._frames",
    "mechcont.outputs._labels",
    "mechcont.outputs._regions",
    "mechcont.outputs._symbols",
    "mechcont.outputs.animation",
    "mechcont.outputs.critical_plots",
    "mechcont.outputs.cycle_orbits",
    "mechcont.outputs.cycle_plots",
    "mechcont.outputs.design_plots",
    "mechcont.outputs.drawing",
    "mechcont.outputs.drawing3d",
    "mechcont.outputs.explore",
    "mechcont.outputs.history_plots",
    "mechcont.outputs.plotting",
    "mechcont.outputs.retraction_plots",
    "mechcont.outputs.stability_chart",
    "mechcont.outputs.study_plots",
    "mechcont.outputs.sweep_plots",
    "mechcont.outputs.tables",
    "mechcont.paper",
    "mechcont.paper._nose_gear_settings",
    "mechcont.paper._shimmy_gear",
    "mechcont.paper._timing",
    "mechcont.paper.design_optimum",
    "mechcont.paper.doc_numbers",
    "mechcont.paper.freefall",
    "mechcont.paper.sections",
    "mechcont.paper.shimmy",
    "mechcont.units",
}


def _typed_modules() -> set[str]:
    """The modules of every pyproject override that sets disallow_untyped_defs."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    out: set[str] = set()
    for override in config["tool"]["mypy"].get("overrides", []):
        if override.get("disallow_untyped_defs"):
            modules = override["module"]
            out.update([modules] if isinstance(modules, str) else modules)
    return out


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _fully_annotated(path: Path) -> bool:
    """Every function has a return annotation and every parameter (but self/cls) an annotation."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            args = [*node.args.posonlyargs, *node.args.args, *node.args.kwonlyargs,
                    *([node.args.vararg] if node.args.vararg else []), *([node.args.kwarg] if node.args.kwarg else [])]
            if node.returns is None and node.name != "__init__":
                return False
            if any(a.annotation is None and a.arg not in ("self", "cls") for a in args):
                return False
            if node.name == "__init__" and node.returns is None and not any(a.annotation for a in args):
                return False
    return True


def test_the_list_only_grows():
    modules = {_module_name(p) for p in (SRC / "mechcont").rglob("*.py")}
    missing = sorted(m for m in FLOOR if m not in modules)
    assert not missing, f"modules of the ratchet floor no longer exist (put their successors in FLOOR): {missing}"
    dropped = sorted(FLOOR - _typed_modules())
    assert not dropped, f"left the disallow_untyped_defs list of pyproject.toml (it may only grow): {dropped}"


def test_every_annotated_module_is_on_the_list():
    typed = _typed_modules()
    unlisted = sorted(m for p in (SRC / "mechcont").rglob("*.py")
                      if (m := _module_name(p)) not in typed and _fully_annotated(p))
    assert not unlisted, (f"fully annotated but not checked: add them to the disallow_untyped_defs list of "
                          f"pyproject.toml and to FLOOR here: {unlisted}")
