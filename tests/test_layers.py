"""The layers the folder list promises: every package imports only lower layers (the contract
below, imports inside functions included); the CLI parses, calls the public API and prints (no
plotting, no global Matplotlib backend); the paper's analyses call the public API (no CLI,
no private names of other packages)."""

from __future__ import annotations

import ast
from pathlib import Path

import mechcont

SRC = Path(mechcont.__file__).parent


def _imports(path: Path):
    """``(module, names)`` of every import in ``path``, relative modules resolved to ``mechcont.*``."""
    package = ["mechcont", *path.relative_to(SRC).parent.parts]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, []
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *(node.module.split(".") if node.module else [])])
            yield module, [a.name for a in node.names]


def test_cli_does_no_plotting():
    for path in sorted((SRC / "cli").glob("*.py")):
        text = path.read_text(encoding="utf-8")
        assert "matplotlib" not in text, f"{path.name}: plotting belongs in mechcont.outputs"
        for module, _ in _imports(path):
            assert not module.startswith("matplotlib"), path.name


def test_paper_uses_the_public_api():
    for path in sorted((SRC / "paper").glob("*.py")):
        for module, names in _imports(path):
            if not module.startswith("mechcont"):
                continue
            assert not module.startswith("mechcont.cli"), f"{path.name} imports the CLI"
            if module.startswith("mechcont.paper") or module == "mechcont._progress":
                continue
            private = [p for p in module.split(".") if p.startswith("_")] + [n for n in names if n.startswith("_")]
            assert not private, f"{path.name}: from {module} import {names} (private)"


# -- the layer contract of every package ------------------------------------------------------
#: Lowest first. A module may import its own package and the packages of lower layers; never one
#: of a higher layer nor a sibling of its own layer (so there are no cycles between packages).
#: ``equations`` is the kernel (the Model type, code generation); ``mechanism`` builds a Model
#: from a description, ``continuation`` solves any Model; ``models`` are data (built-in models)
#: below the analyses; ``dynamics`` sits beside ``analysis`` and draws nothing; ``mechcont``
#: (its ``__init__``) is the public API.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("errors", "_version", "_dense", "_lazy", "_progress", "_roots", "_signals", "units"),
    ("_io", "_status"),
    ("equations",),
    ("mechanism", "continuation"),
    ("models",),
    ("dynamics",),
    ("analysis",),
    ("outputs",),
    ("mechcont",),
    ("paper",),
    ("cli",),
    ("__main__",),
)


def _unit(root: Path, dotted: str) -> str | None:
    """The package (or top-level module) of ``root`` that ``dotted`` (``mechcont.x.y``) belongs to, or
    ``None`` when it is not mechcont's; ``"mechcont"`` for the package itself (its public API)."""
    parts = dotted.split(".")
    if parts[0] != root.name:
        return None
    if len(parts) > 1 and ((root / parts[1]).is_dir() or (root / f"{parts[1]}.py").is_file()):
        return parts[1]
    return root.name


def _all_imports(root: Path, path: Path):
    """``(unit, line)`` of every mechcont import in ``path`` anywhere in it (also inside functions and
    ``TYPE_CHECKING`` blocks), ``importlib.import_module("mechcont....")`` calls included."""
    package = [root.name, *path.relative_to(root).parent.parts]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *(node.module.split(".") if node.module else [])])
            # ``from mechcont import analysis`` imports the subpackage, ``from . import x`` the module x
            names = [f"{module}.{a.name}" for a in node.names] if module == root.name or not node.module else [module]
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) == "import_module":
            arg = node.args[0] if node.args else None
            if isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.Constant):
                arg = arg.values[0]
            if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                names = [arg.value.rstrip(".")]
        for name in names:
            unit = _unit(root, name)
            if unit is not None:
                yield unit, node.lineno


def layer_violations(root: Path, layers=LAYERS) -> list[str]:
    """Every import in the package at ``root`` that goes up or sideways in ``layers`` (one line each)."""
    level = {unit: i for i, layer in enumerate(layers) for unit in layer}
    found = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        own = rel.parts[0] if len(rel.parts) > 1 else (root.name if rel.stem == "__init__" else rel.stem)
        assert own in level, f"{rel}: package {own!r} has no layer in the contract"
        for unit, line in _all_imports(root, path):
            if unit != own and (unit not in level or level[unit] >= level[own]):
                found.append(f"{rel}:{line} imports {unit} ({own} may import only lower layers)")
    return found


def test_every_package_imports_only_lower_layers():
    assert layer_violations(SRC) == []


def test_the_contract_finds_an_upward_import(tmp_path):
    """The checker itself: an import from a higher layer, even one inside a function, a sibling
    import and a lazy ``import_module`` are each reported; downward imports are not."""
    root = tmp_path / "mechcont"
    for package in ("equations", "continuation", "mechanism", "analysis"):
        (root / package).mkdir(parents=True)
        (root / package / "__init__.py").write_text("")
    (root / "__init__.py").write_text("")
    (root / "errors.py").write_text("")
    (root / "equations" / "_model.py").write_text("from ..errors import InputError\n\n"
                                                  "def f():\n    from ..analysis import sensitivity\n")
    (root / "continuation" / "_branch.py").write_text("import mechcont.equations\nfrom mechcont import mechanism\n")
    (root / "mechanism" / "_lazy.py").write_text("import importlib\nimportlib.import_module(f'mechcont.analysis.{x}')\n")
    (root / "analysis" / "ok.py").write_text("from ..continuation import _branch\nfrom . import ok\nimport numpy\n")
    assert layer_violations(root) == [
        "continuation/_branch.py:2 imports mechanism (continuation may import only lower layers)",
        "equations/_model.py:4 imports analysis (equations may import only lower layers)",
        "mechanism/_lazy.py:2 imports analysis (mechanism may import only lower layers)",
    ]
