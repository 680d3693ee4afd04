"""The layers the folder list promises: the CLI parses, calls the public API and prints (no
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
