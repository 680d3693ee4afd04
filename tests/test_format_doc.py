"""docs/mechanism-format.md documents every key the description parser accepts (derived from the
parser's own registries, not from a list kept here), with the defaults of the element classes,
and its worked example parses and builds as described."""

from __future__ import annotations

import ast
import dataclasses
import importlib
import pkgutil
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

from mechcont import mechanism
from mechcont.mechanism import _expr, _file, parse_description
from mechcont.mechanism._description import Damper, Gravity, Spring
from mechcont.mechanism._plugin import registry

DOC_PATH = Path(__file__).resolve().parent.parent / "docs" / "mechanism-format.md"
DOC = DOC_PATH.read_text(encoding="utf-8")


def sections() -> dict[str, str]:
    """Heading line -> text up to the next heading of level 2 or 3."""
    out, head, lines = {}, "", []
    for line in DOC.splitlines():
        if line.startswith(("## ", "### ")):
            out[head] = "\n".join(lines)
            head, lines = line, []
        else:
            lines.append(line)
    out[head] = "\n".join(lines)
    return out


def table_section(table: str) -> str:
    """The text of the ``### `[table]``` or ``### `[table.NAME]``` section."""
    found = [text for head, text in sections().items()
             if re.match(rf"^### `\[{re.escape(table)}(\.NAME)?\]`", head)]
    assert found, f"docs/mechanism-format.md has no section '### `[{table}]`' or '### `[{table}.NAME]`'"
    return found[0]


def key_sets(value) -> set[str]:
    """The keys in a key-set constant: a set, or a mapping of sets (or of (class, set) pairs)."""
    if isinstance(value, (set, frozenset)):
        return {k for k in value if isinstance(k, str)}
    if isinstance(value, Mapping):
        out: set[str] = set()
        for v in value.values():
            if isinstance(v, tuple):
                v = next((x for x in v if isinstance(x, (set, frozenset))), set())
            out |= key_sets(v)
        return out
    return set()


def documented(key: str, text: str) -> bool:
    return f"`{key}`" in text


def test_every_top_level_table_has_a_section():
    for table in _file._SECTIONS:
        table_section(table)


def test_the_list_of_top_level_tables_names_every_table():
    listed = re.search(r"The top level holds only these tables: (.*?)\. Every table", DOC, re.S).group(1)
    names = set(re.findall(r"`\[(\w+)(?:\.NAME)?\]`", listed))
    assert names == set(_file._SECTIONS), sorted(names ^ set(_file._SECTIONS))


@pytest.mark.parametrize("path", sorted(_file.KEYS))
def test_every_key_of_the_plain_tables_is_documented_in_its_section(path):
    text = table_section(path.split(".")[0])
    missing = sorted(k for k in _file.KEYS[path] if not documented(k, text))
    assert not missing, f"[{path}] keys missing from docs/mechanism-format.md: {missing}"


@pytest.mark.parametrize("table", ["joints", "loads", "conditions"])
def test_every_type_and_its_keys_are_documented(table):
    """Every plug-in registered for the plane (:func:`mechcont.mechanism._plugin.registry`, the one the
    file reader reads) has its ``type`` and keys in its table's section."""
    text = table_section(table)
    assert documented("type", text)
    for kind, (_cls, keys) in registry(table, "plane").keyed().items():
        assert f'"{kind}"' in text, f"[{table}.NAME] type {kind!r} not documented"
        missing = sorted(k for k in keys if not documented(k, text))
        assert not missing, f"[{table}.NAME] type {kind!r}: keys missing from the doc: {missing}"


def key_constants() -> dict[str, object]:
    """Every module-level ``*_KEYS`` constant of the description package besides ``_file.KEYS``
    (e.g. the keys of newer tables, parsed by their own modules)."""
    out: dict[str, object] = {}
    for info in pkgutil.iter_modules(mechanism.__path__):
        module = importlib.import_module(f"mechcont.mechanism.{info.name}")
        for name, value in vars(module).items():
            if name.upper().endswith("_KEYS") and key_sets(value):
                out.setdefault(name, value)
    return out


@pytest.mark.parametrize("name", sorted(key_constants()))
def test_every_other_key_constant_of_the_parser_is_documented(name):
    """In its own section when there is one (``ACTUATOR_KEYS`` -> ``[actuators...]``), else anywhere;
    a mapping of kinds (every key set has ``type``) also needs each kind documented."""
    value = key_constants()[name]
    table = name.lower().removesuffix("_keys").lstrip("_") + "s"
    heads = [h for h in sections() if h.startswith(f"### `[{table}")]
    text = sections()[heads[0]] if heads else DOC
    missing = sorted(k for k in key_sets(value) if not documented(k, text))
    assert not missing, f"{name}: keys missing from docs/mechanism-format.md: {missing}"
    if isinstance(value, Mapping) and all("type" in key_sets(v) for v in value.values()):
        kinds = sorted(k for k in value if f'"{k}"' not in text)
        assert not kinds, f"{name}: types missing from docs/mechanism-format.md: {kinds}"


def test_every_literal_key_set_checked_by_the_parser_is_documented():
    """Any ``_only(table, {...}, field)`` written with a literal set (not a constant) in _file.py."""
    tree = ast.parse(Path(_file.__file__).read_text(encoding="utf-8"))
    literal: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "_only" and len(node.args) >= 2:
            arg = node.args[1]
            if isinstance(arg, ast.Set):
                literal |= {e.value for e in arg.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)}
    missing = sorted(k for k in literal if not documented(k, DOC))
    assert not missing, f"keys accepted by _file.py missing from docs/mechanism-format.md: {missing}"


def _shown(default) -> str:
    if isinstance(default, tuple):
        return "[" + ", ".join(str(v) for v in default) + "]"
    if isinstance(default, str):
        return f'"{default}"'
    return str(default).replace(" ", "")


def _rows(text: str) -> dict[str, list[list[str]]]:
    """Markdown table rows of a section by their first cell's key: ``| `key` | ... |``."""
    out: dict[str, list[list[str]]] = {}
    for line in text.splitlines():
        m = re.match(r"^\| `([^`]+)` \|(.*)\|$", line)
        if m:
            out.setdefault(m.group(1), []).append([c.strip() for c in m.group(2).split("|")])
    return out


@pytest.mark.parametrize("table, classes", [
    ("joints", list(registry("joints", "plane").values())),
    ("loads", list(registry("loads", "plane").values())),
    ("springs", [Spring]), ("dampers", [Damper]), ("gravity", [Gravity]),
])
def test_documented_defaults_are_the_element_classes_defaults(table, classes):
    rows = _rows(table_section(table))
    for cls in classes:
        for f in dataclasses.fields(cls):
            if f.default is dataclasses.MISSING or f.default is None:
                continue
            assert f.name in rows, f"{cls.__name__}.{f.name}: no row in the [{table}] table"
            want = _shown(f.default)
            defaults = [r[2] for r in rows[f.name] if len(r) >= 4]   # type | unit | default | meaning
            assert any(want in d.replace(" ", "").replace("`", "") or want in d.replace("`", "") for d in defaults), \
                f"{cls.__name__}.{f.name}: default {want} not in the doc's default column {defaults}"


def test_every_expression_function_is_documented():
    text = sections()["## Expressions"]
    missing = sorted(f for f in _expr.FUNCTIONS if not documented(f, text))
    assert not missing, f"expression functions missing from the doc: {missing}"


def worked_example() -> str:
    text = sections()["## Worked example"]
    blocks = re.findall(r"```toml\n(.*?)```", text, re.S)
    assert len(blocks) == 1
    return blocks[0]


def test_worked_example_parses_builds_and_matches_its_description():
    text = worked_example()
    tables = set(tomllib.loads(text))
    assert tables >= {"mechanism", "parameters", "ground", "bodies", "joints", "springs", "dampers", "gravity",
                      "loads", "assembly"}
    mech = parse_description(text, "plate_linkage.toml")
    kinds = {type(j).__name__ for j in mech.joints}
    assert kinds == {"Revolute", "Slider", "Weld"}
    assert {type(ld).__name__ for ld in mech.loads} == {"PointForce", "Moment", "Drag", "CustomLoad"}
    assert tables >= {"actuators", "conditions"} and "downlock" in tomllib.loads(text)["mechanism"]
    system = mech.build()
    assert system.dof.dof == mech.dof == 1
    assert len(system.mechanics.coordinates) == 15 and len(system.mechanics.constraints) == 14
    assert len(system.parameter_names) == 24
    for name in ("x_crank", "theta_rod", "R_A_x", "R_W_x", "R_W_y", "T_W", "R_E_x", "R_E_y", "R_block",
                 "locked", "fold"):
        system.index(name)
    assert {"Fx_crank", "M_plate", "W_angle", "block_n", "A_x", "cond_locked"} <= set(system.equation_names)
    # the held crank angle is where the example says
    assert system.defaults()[system.index("theta_crank")] == pytest.approx(1.2)


def test_readme_links_the_reference_and_mentions_check():
    readme = (DOC_PATH.parent.parent / "README.md").read_text(encoding="utf-8")
    assert "docs/mechanism-format.md" in readme
    assert "mechcont check" in readme


def test_conditions_example_builds_with_the_worked_example():
    """The [conditions] snippet (written for the worked example) adds one state and row per condition."""
    snippet = re.search(r"```toml\n(\[conditions\].*?)```", sections()["### `[conditions]`"], re.S).group(1)
    text = worked_example().replace("[conditions]\n", "[conditions]\n" + snippet.split("\n", 1)[1], 1)
    system = parse_description(text, "plate_linkage.toml").build()
    x = system.defaults()
    values = dict(zip(system.names, x))
    assert values["square"] == pytest.approx(0.0, abs=1e-12)          # the weld holds the horn square
    assert values["turn"] == pytest.approx(values["theta_plate"] - values["theta_crank"])
    assert values["reach"] > 0 and abs(values["in_line"]) <= 1
    rows = [system.equation_names.index(f"cond_{n}") for n in ("square", "in_line", "reach", "turn")]
    np.testing.assert_allclose(system.residual(x)[rows], 0, atol=1e-12)   # condition rows hold at assembly
