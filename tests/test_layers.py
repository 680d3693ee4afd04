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


# -- private modules, circles, third-party libraries and file sizes (issue 34, item 6) ----------------------------
def _private(part: str) -> bool:
    return part.startswith("_") and not (part.startswith("__") and part.endswith("__"))


def private_imports(root: Path) -> list[str]:
    """Every import (anywhere in a file) of another package's private module or private name: ``from
    ..continuation._branch import x`` or ``from ..equations import _deferred`` in ``mechanism``; a package
    offers what others use in its ``__init__`` (or a public module). The top-level private modules
    (``_io``, ``_dense``, ``_status``, ...) are the shared base layer, not another package's insides."""
    found = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        own = rel.parts[0] if len(rel.parts) > 1 else None
        package = [root.name, *rel.parent.parts]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = package[: len(package) - node.level + 1] if node.level else []
                imported = [([*base, *(node.module.split(".") if node.module else [])], [a.name for a in node.names])]
            elif isinstance(node, ast.Import):
                imported = [(a.name.split("."), []) for a in node.names]
            else:
                continue
            for module, names in imported:
                if module[:1] != [root.name] or len(module) < 2 or not (root / module[1]).is_dir() or module[1] == own:
                    continue
                if any(_private(p) for p in module[2:]) or any(_private(n) for n in names):
                    found.append(f"{rel}:{node.lineno} imports {'.'.join(module)} {names}")
    return found


def test_no_package_imports_another_packages_private_module():
    assert private_imports(SRC) == []


def test_the_private_import_rule_finds_them(tmp_path):
    root = tmp_path / "mechcont"
    for package in ("equations", "mechanism"):
        (root / package).mkdir(parents=True)
    (root / "_io.py").write_text("")
    (root / "mechanism" / "a.py").write_text("from ..equations._codegen import f\nfrom ..equations import _deferred, g\n"
                                             "from .._io import atomic_write\nfrom ._b import h\n"
                                             "from .._version import __version__\n"
                                             "def k():\n    import mechcont.equations._cache\n")
    assert private_imports(root) == ["mechanism/a.py:1 imports mechcont.equations._codegen ['f']",
                                     "mechanism/a.py:2 imports mechcont.equations ['_deferred', 'g']",
                                     "mechanism/a.py:7 imports mechcont.equations._cache []"]


def import_circles(root: Path, lazy: bool = False) -> list[list[str]]:
    """The import circles between the files of one package, each as its modules (sorted).

    Counted at file level: an edge ``a -> b`` is an import of module ``b`` (of the same top-level package) that
    runs when ``a`` is imported: a statement at module level, also inside ``if``/``try``/``with``, but not in a
    function or class body (there it is a lazy dependency, taken on first use) nor under ``TYPE_CHECKING``.
    ``from . import x`` and ``from .x import y`` are edges to ``x``; a circle is a strongly connected set.
    With ``lazy`` the imports in function and class bodies are edges too (not those under ``TYPE_CHECKING``): a
    circle closed only on first use is still two modules that each need the other."""
    modules = {}
    for path in root.rglob("*.py"):
        parts = [root.name, *path.relative_to(root).with_suffix("").parts]
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path

    def runs_at_import(body):
        for node in body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                yield node
            elif isinstance(node, ast.If):
                test = node.test
                if getattr(test, "id", getattr(test, "attr", None)) != "TYPE_CHECKING":
                    yield from runs_at_import(node.body)
                yield from runs_at_import(node.orelse)
            elif isinstance(node, ast.Try):
                for block in (node.body, *(h.body for h in node.handlers), node.orelse, node.finalbody):
                    yield from runs_at_import(block)
            elif isinstance(node, ast.With):
                yield from runs_at_import(node.body)
            elif lazy and isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                for inner in ast.walk(node):
                    if isinstance(inner, (ast.Import, ast.ImportFrom)):
                        yield inner

    edges: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        out = edges.setdefault(name, set())
        for node in runs_at_import(ast.parse(path.read_text(encoding="utf-8")).body):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                base = package[: len(package) - node.level + 1] if node.level else []
                module = ".".join([*base, *(node.module.split(".") if node.module else [])])
                targets = [f"{module}.{a.name}" if f"{module}.{a.name}" in modules else module for a in node.names]
            for target in targets:
                while target not in modules and "." in target:
                    target = target.rsplit(".", 1)[0]
                if target in modules and target != name and target.split(".")[:2] == name.split(".")[:2]:
                    out.add(target)
    # strongly connected components (Tarjan), iteratively
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    circles = []
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    work.append((child, iter(sorted(edges[child]))))
                elif child in stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    circles.append(sorted(component))
    return circles


def test_no_import_circle_between_the_files_of_a_package():
    assert import_circles(SRC) == []


#: the packages whose files still close an import circle through an import inside a function (issue 34: 11 such
#: circles, none left: the last, mechanism's descriptions calling the generators that imported them, went when the
#: generators and kinematics came to know a description by its type alone); the set only shrinks, never add to it
LAZY_CIRCLES_LEFT: set[str] = set()


def test_no_import_circle_on_first_use_outside_the_packages_left():
    """Counting the imports inside functions too, a circle stays inside the packages of :data:`LAZY_CIRCLES_LEFT`
    (one to be removed by moving code where it belongs, not by hiding an import in a function): none."""
    circles = import_circles(SRC, lazy=True)
    packages = {circle[0].split(".")[1] for circle in circles}
    assert packages <= LAZY_CIRCLES_LEFT, f"import circles (lazy imports counted) in {packages - LAZY_CIRCLES_LEFT}"
    assert len(circles) == 0, circles


def test_the_circle_finder_finds_one(tmp_path):
    """The checker itself: a circle of module-level imports is found (through a package's ``__init__`` too);
    one closed only inside a function or under ``TYPE_CHECKING`` is not a circle."""
    root = tmp_path / "mechcont"
    (root / "a" / "sub").mkdir(parents=True)
    (root / "__init__.py").write_text("")
    (root / "a" / "__init__.py").write_text("from .x import f\n")
    (root / "a" / "x.py").write_text("from .sub import g\n\ndef f():\n    pass\n")
    (root / "a" / "sub" / "__init__.py").write_text("from .y import g\n")
    (root / "a" / "sub" / "y.py").write_text("from typing import TYPE_CHECKING\nfrom .. import x\n\ndef g():\n    pass\n")
    (root / "a" / "z.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .w import h\n"
                                     "def k():\n    from .w import h\n")
    (root / "a" / "w.py").write_text("from .z import k\n")
    assert import_circles(root) == [["mechcont.a.sub", "mechcont.a.sub.y", "mechcont.a.x"]]
    assert import_circles(root, lazy=True) == [["mechcont.a.sub", "mechcont.a.sub.y", "mechcont.a.x"],
                                               ["mechcont.a.w", "mechcont.a.z"]]


#: third-party libraries and the packages that may import them (anywhere in a file): plotting draws outputs,
#: SymPy/SymEngine build equations, click parses the command line
THIRD_PARTY = {
    "matplotlib": ("outputs", "paper"),
    "sympy": ("equations", "mechanism", "models"),
    "symengine": ("equations",),
    "click": ("cli",),
}


def third_party_violations(root: Path) -> list[str]:
    """Every import of a library of :data:`THIRD_PARTY` outside the packages allowed it."""
    found = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        own = rel.parts[0] if len(rel.parts) > 1 else rel.stem
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                libraries = [a.name.split(".")[0] for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                libraries = [node.module.split(".")[0]]
            else:
                continue
            for library in libraries:
                if library in THIRD_PARTY and own not in THIRD_PARTY[library]:
                    found.append(f"{rel}:{node.lineno} imports {library} (only {', '.join(THIRD_PARTY[library])})")
    return found


def test_third_party_libraries_stay_in_their_packages():
    assert third_party_violations(SRC) == []


def test_the_third_party_rule_finds_a_plot_in_dynamics(tmp_path):
    root = tmp_path / "mechcont"
    (root / "dynamics").mkdir(parents=True)
    (root / "outputs").mkdir()
    (root / "dynamics" / "a.py").write_text("def f():\n    import matplotlib.pyplot as plt\n")
    (root / "dynamics" / "b.py").write_text("from sympy import Symbol\nimport numpy\n")
    (root / "outputs" / "c.py").write_text("import matplotlib\n")
    assert third_party_violations(root) == ["dynamics/a.py:2 imports matplotlib (only outputs, paper)",
                                            "dynamics/b.py:1 imports sympy (only equations, mechanism, models)"]


#: the limit on a source file's length (lines, blank and comment lines counted)
MAX_LINES = 500
#: the files over :data:`MAX_LINES` when the rule came (issue 34), with their lines then: a file may stay over the
#: limit only while it is here, and may not grow. The list only shrinks: a file split below the limit must leave
#: it, and :data:`LONG_FILES` may never hold a file that is not in :data:`LONG_FILES_AT_START` (never add to either).
LONG_FILES_AT_START: dict[str, int] = {}
LONG_FILES = dict(LONG_FILES_AT_START)


def _lines(path: Path) -> int:
    return len(path.read_text(encoding="utf-8").splitlines())


def test_no_file_over_500_lines_but_the_shrinking_allowlist():
    assert LONG_FILES.keys() <= LONG_FILES_AT_START.keys(), "a file may leave LONG_FILES, never join it"
    lines = {str(p.relative_to(SRC)): _lines(p) for p in sorted(SRC.rglob("*.py"))}
    too_long = {f: n for f, n in lines.items() if n > MAX_LINES and f not in LONG_FILES}
    assert not too_long, f"over {MAX_LINES} lines (split them: one job per module): {too_long}"
    grown = {f: (lines[f], LONG_FILES[f]) for f in LONG_FILES if f in lines and lines[f] > LONG_FILES[f]}
    assert not grown, f"allowed long files grew (lines now, allowed): {grown}"
    short = [f for f in LONG_FILES if lines.get(f, 0) <= MAX_LINES]
    assert not short, f"{short} no longer over {MAX_LINES} lines (or gone): remove them from LONG_FILES"
