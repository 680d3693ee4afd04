"""The mypy ratchet (issue 34): every function annotated, and the strict list may only grow.

The disallow_untyped_defs list grew module by module until it held every module of ``src/mechcont``; it is now
the global setting of ``[tool.mypy]``, and no override may turn it off (a module leaving it would let its
functions lose their annotations unnoticed). The strict list (the typed public API) may only grow: STRICT_FLOOR
is its floor, and a module that is split or renamed is replaced by its successors."""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"

#: The floor of the strict list (add, never remove).
STRICT_FLOOR = {
    "mechcont",
    "mechcont._roots",
    "mechcont.analysis",
    "mechcont.analysis.design",
    "mechcont.analysis.downlock",
    "mechcont.analysis.dynamic_stability",
    "mechcont.analysis.optimize",
    "mechcont.analysis.redundancy",
    "mechcont.analysis.sensitivity",
    "mechcont.analysis.study",
    "mechcont.analysis.surface",
    "mechcont.analysis.unlock",
    "mechcont.continuation",
    "mechcont.continuation._api",
    "mechcont.continuation._branch",
    "mechcont.continuation._cycle_branch",
    "mechcont.continuation._cycle_start",
    "mechcont.continuation._cycles",
    "mechcont.continuation._events",
    "mechcont.continuation._fold_point",
    "mechcont.continuation._folds",
    "mechcont.continuation._hopf_api",
    "mechcont.continuation._linalg",
    "mechcont.continuation._move",
    "mechcont.continuation._newton",
    "mechcont.continuation._options",
    "mechcont.continuation._palc",
    "mechcont.continuation._problem",
    "mechcont.continuation._special_point",
    "mechcont.continuation._table",
    "mechcont.continuation._variants",
    "mechcont.dynamics",
    "mechcont.dynamics._result",
    "mechcont.dynamics.freefall",
    "mechcont.equations",
    "mechcont.equations._codegen",
    "mechcont.equations._compiled",
    "mechcont.equations._deferred",
    "mechcont.equations._layout",
    "mechcont.equations._model",
    "mechcont.equations._protocols",
    "mechcont.equations._system",
    "mechcont.equations._variables",
    "mechcont.equations._velocity_names",
    "mechcont.errors",
    "mechcont.mechanism",
    "mechcont.mechanism._description",
    "mechcont.mechanism._file",
    "mechcont.mechanism._plugin",
    "mechcont.mechanism.spatial",
    "mechcont.mechanism.spatial._description",
    "mechcont.outputs",
    "mechcont.outputs.animation",
    "mechcont.outputs.drawing",
    "mechcont.outputs.drawing3d",
    "mechcont.outputs.explore",
    "mechcont.outputs.plotting",
}


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


def _mypy() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]


def test_every_module_is_checked_with_every_function_annotated():
    mypy = _mypy()
    assert mypy.get("disallow_untyped_defs") is True and mypy.get("disallow_incomplete_defs") is True
    off = [o["module"] for o in mypy.get("overrides", [])
           if o.get("disallow_untyped_defs") is False or o.get("disallow_incomplete_defs") is False]
    assert not off, f"overrides turning the annotation check off: {off}"
    unannotated = sorted(_module_name(p) for p in (SRC / "mechcont").rglob("*.py") if not _fully_annotated(p))
    assert not unannotated, f"functions without annotations (mypy should have said so): {unannotated}"


def test_the_strict_list_only_grows():
    modules = {_module_name(p) for p in (SRC / "mechcont").rglob("*.py")}
    missing = sorted(m for m in STRICT_FLOOR if m not in modules)
    assert not missing, f"modules of the strict floor no longer exist (put their successors in STRICT_FLOOR): {missing}"
    strict = {m for o in _mypy().get("overrides", []) if o.get("disallow_any_generics")
              for m in ([o["module"]] if isinstance(o["module"], str) else o["module"])}
    dropped = sorted(STRICT_FLOOR - strict)
    assert not dropped, f"left the strict list of pyproject.toml (it may only grow): {dropped}"
