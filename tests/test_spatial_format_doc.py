"""docs/spatial-format.md documents every key, joint type and load type the spatial parser accepts
(derived from its registries, not from a list kept here), the rows and reactions each joint really
generates, the reaction signs it states, and its worked example parses, builds and behaves as the
page says (the downlock force against its virtual-work value, the angle idioms against the
geometry)."""

from __future__ import annotations

import dataclasses
import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from mechcont.continuation import find_equilibrium
from mechcont.errors import InputError
from mechcont.mechanism import check_report, parse_description
from mechcont.mechanism._file import KEYS
from mechcont.mechanism._plugin import registry
from mechcont.mechanism.spatial._description import SpatialGravity
from mechcont.mechanism.spatial._file import SPATIAL_KEYS
from mechcont.mechanism.spatial.joints import JOINT_TYPES

ROOT = Path(__file__).resolve().parent.parent
DOC = (ROOT / "docs" / "spatial-format.md").read_text(encoding="utf-8")
DATA = Path(__file__).parent / "data" / "spatial"


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
    assert found, f"docs/spatial-format.md has no section '### `[{table}]`' or '### `[{table}.NAME]`'"
    return found[0]


def documented(key: str, text: str) -> bool:
    return f"`{key}`" in text


def _rows(text: str) -> dict[str, list[list[str]]]:
    """Markdown table rows of a section by their first cell's key: ``| `key` | ... |``."""
    out: dict[str, list[list[str]]] = {}
    for line in text.splitlines():
        m = re.match(r"^\| `([^`]+)` \|(.*)\|$", line)
        if m:
            out.setdefault(m.group(1), []).append([c.strip() for c in m.group(2).split("|")])
    return out


# -- keys, types and defaults -------------------------------------------------------------------
@pytest.mark.parametrize("path", sorted(SPATIAL_KEYS))
def test_every_key_of_the_spatial_tables_is_documented_in_its_section(path):
    text = table_section(path.split(".")[0])
    missing = sorted(k for k in SPATIAL_KEYS[path] if not documented(k, text))
    assert not missing, f"[{path}] keys missing from docs/spatial-format.md: {missing}"


@pytest.mark.parametrize("table", ["joints", "loads"])
def test_every_type_and_its_keys_are_documented(table):
    """Every plug-in registered for space (the registry the file reader reads) has its ``type`` and keys
    in its table's section."""
    text = table_section(table)
    assert documented("type", text)
    for kind, (_cls, keys) in registry(table, "space").keyed().items():
        assert f'"{kind}"' in text, f"[{table}.NAME] type {kind!r} not documented"
        missing = sorted(k for k in keys if not documented(k, text))
        assert not missing, f"[{table}.NAME] type {kind!r}: keys missing from the doc: {missing}"


def test_the_mechanism_keys_and_the_spatial_condition_keys_are_documented():
    text = table_section("mechanism")
    assert not sorted(k for k in KEYS["mechanism"] if not documented(k, text))
    text = table_section("conditions")  # the keys are the planar doc's (test_format_doc)
    for kind in registry("conditions", "space"):
        assert f'"{kind}"' in text
    assert documented("normal", text) and "refused" in text   # collinear needs it; angle is planar


def _shown(default) -> str:
    if isinstance(default, tuple):
        return "[" + ", ".join(str(v) for v in default) + "]"
    if isinstance(default, str):
        return f'"{default}"'
    return str(default)


@pytest.mark.parametrize("table, classes", [
    ("joints", list(JOINT_TYPES.values())),
    ("loads", list(registry("loads", "space").values())),
    ("gravity", [SpatialGravity]),
])
def test_documented_defaults_are_the_element_classes_defaults(table, classes):
    """Each default of a joint, load or gravity class is in the default column of its key's row,
    unless the doc says the file requires that key."""
    rows = _rows(table_section(table))
    for cls in classes:
        for f in dataclasses.fields(cls):
            if f.default is dataclasses.MISSING or f.default is None or f.name == "name":
                continue
            if cls.__name__ == "PointForce":   # the planar class: its 2-D default does not apply in 3-D
                continue
            assert f.name in rows, f"{cls.__name__}.{f.name}: no row in the [{table}] table"
            defaults = [r[2] for r in rows[f.name] if len(r) >= 4]
            if all("required" in d for d in defaults):
                continue
            want = _shown(f.default)
            assert any(want in d.replace("`", "") for d in defaults), \
                f"{cls.__name__}.{f.name}: default {want} not in the doc's default column {defaults}"


# -- rows and reactions of each joint, as generated ---------------------------------------------
_DOF = {"spherical": 3, "revolute": 1, "universal": 2, "inline": 4, "cylindrical": 2, "prismatic": 1, "weld": 0}


def _joint_row(kind: str) -> tuple[list[str], list[str]]:
    """The (rows, reactions) named in the doc's joint table for ``kind`` (joint named ``J``)."""
    for line in table_section("joints").splitlines():
        if line.startswith(f'| `"{kind}"` |'):
            cells = [c.strip() for c in line.strip("|").split("|")]
            return re.findall(r"`([^`]+)`", cells[3]), re.findall(r"`([^`]+)`", cells[4])
    raise AssertionError(f"no row for joint type {kind!r} in the joint table")


def test_the_joint_table_covers_every_joint_type():
    assert set(_DOF) == set(JOINT_TYPES)


@pytest.mark.parametrize("kind", sorted(_DOF))
def test_each_joint_generates_the_rows_and_reactions_the_doc_names(kind):
    text = (f'[mechanism]\ndimension = 3\ndof = {_DOF[kind]}\n[ground]\nO = [0, 0, 0]\n'
            f'[bodies.bar]\nlength = 1\nmass = 1\n[joints.J]\ntype = "{kind}"\na = "ground.O"\nb = "bar.a"\n')
    system = parse_description(text, f"{kind}.toml").build()
    rows = [n for n in system.equation_names if n.startswith("J_")]
    reactions = [n for n in system.reaction_names if n.startswith(("R_J", "T_J"))]
    assert (rows, reactions) == _joint_row(kind)
    assert system.dof.dof == _DOF[kind]


# -- the reaction signs the doc states -----------------------------------------------------------
def test_revolute_moments_act_about_minus_g_and_plus_f():
    """The tilted pendulum at rest: the hinge's moment on the bar, -T_1 g + T_2 f, balances gravity's."""
    pend = parse_description((DATA / "pendulum_3d.toml").read_text(), "pendulum_3d.toml").build()
    v = pend.as_dict(find_equilibrium(pend))
    u = np.array([0.0, math.cos(v["beta"]), math.sin(v["beta"])])
    f = np.array([0.0, 0.0, 1.0]) - u[2] * u     # axis mostly along y: f from z, g = u x f
    f /= np.linalg.norm(f)
    g = np.cross(u, f)
    r_cg = np.array([v["x_bar"], v["y_bar"], v["z_bar"]])           # the bar's centre, from the hinge at O
    gravity = np.cross(r_cg, [0.0, 0.0, -v["m"] * v["g"]])
    hinge = -v["T_hinge_1"] * g + v["T_hinge_2"] * f
    np.testing.assert_allclose(hinge + gravity - (gravity @ u) * u, 0.0, atol=1e-9)
    assert abs(v["T_hinge_1"]) > 1.0   # the check is not vacuous


def test_weld_moments_act_about_the_axes_of_body_a():
    """A horizontal cantilever welded to the ground: the weld's moment on it about +y is -m g L/2."""
    text = ('[mechanism]\ndimension = 3\ndof = 0\n[parameters]\ng = 9.81\n[ground]\nO = [0, 0, 0]\n'
            '[bodies.beam]\nlength = 2\nmass = 3\n[joints.W]\ntype = "weld"\na = "ground.O"\nb = "beam.a"\n'
            '[gravity]\n')
    s = parse_description(text, "cantilever.toml").build()
    v = s.as_dict(s.defaults())
    assert v["T_W_2"] == pytest.approx(-3 * 9.81 * 2 / 2, rel=1e-12)
    assert v["R_W_z"] == pytest.approx(3 * 9.81, rel=1e-12)
    assert abs(v["T_W_1"]) + abs(v["T_W_3"]) < 1e-9


def _door(upper: str, lower: str | None = None) -> str:
    text = (DATA / "door_3d.toml").read_text()
    start = text.index("[joints.upper]")
    text = text[:start] + upper.strip() + "\n\n" + text[text.index("[gravity]"):]
    if lower is not None:
        start = text.index("[joints.lower]")
        text = text[:start] + lower.strip() + "\n\n" + text[text.index("[joints.upper]"):]
    return text


def test_the_determinate_door_of_the_doc_gives_the_stated_hinge_force():
    door = parse_description(_door('[joints.upper]\ntype = "inline"\na = "ground.high"\nb = "door.high"\n'
                                   'axis = [0, 0, 1]',
                                   '[joints.lower]\ntype = "spherical"\na = "ground.low"\nb = "door.low"'),
                             "door.toml").build()
    assert door.dropped_constraints == () and door.dof.dof == 1
    v = door.as_dict(door.defaults())
    assert v["R_upper_1"] == pytest.approx(-v["m"] * v["g"] * v["a"] / v["h"], rel=1e-12)
    assert v["R_lower_z"] == pytest.approx(v["m"] * v["g"], rel=1e-12)


# -- redundancy, compliance and misfit as the doc shows them -------------------------------------
def _snippet(section: str) -> str:
    return re.search(r"```toml\n(.*?)```", sections()[section], re.S).group(1)


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_the_compliance_snippet_makes_the_door_determinate_with_the_stated_split():
    snippet = re.sub(r"^ {3}", "", _snippet("## Redundant constraints"), flags=re.M)
    text = (DATA / "door_3d.toml").read_text()
    text = text[:text.index("[joints.lower]")] + snippet + "\n" + text[text.index("[gravity]"):]
    door = parse_description(text, "door.toml").build()
    assert door.dropped_constraints == () and door.dof.dof == 1
    v = door.as_dict(find_equilibrium(door, hold={"swing": 0.0}, free=["M"], guess=door.defaults()))
    phi = v["m"] * v["g"] * v["a"] / (v["kr"] + v["k"] * v["h"] ** 2)
    assert math.hypot(v["T_lower_1"], v["T_lower_2"]) == pytest.approx(v["kr"] * phi, rel=1e-5)
    assert abs(v["R_upper_x"]) == pytest.approx(v["k"] * v["h"] * phi, rel=1e-5)


def test_a_compliant_joint_beside_a_rigid_one_carries_nothing_and_stiffness_alone_stays_redundant():
    upper = ('[joints.upper]\ntype = "revolute"\na = "ground.high"\nb = "door.high"\naxis = [0, 0, 1]\n'
             'stiffness = "k"\n')
    door = parse_description(_door(upper + 'rotational_stiffness = "kr"'), "door.toml").build()
    v = door.as_dict(find_equilibrium(door, hold={"swing": 0.0}, free=["M"], guess=door.defaults()))
    assert max(abs(v[r]) for r in door.reaction_names if r.startswith(("R_upper", "T_upper"))) < 1e-6
    with pytest.raises(InputError) as err:
        parse_description(_door(upper), "door.toml").build()
    assert "2 redundant constraint(s)" in str(err.value) and "T_upper_1, T_upper_2" in str(err.value)


def test_the_redundancy_and_misfit_messages_are_quoted_as_mechcont_prints_them():
    quoted = re.findall(r"```\n(door_3d\.toml:.*?)```", DOC, re.S)
    assert len(quoted) == 2
    with pytest.raises(InputError) as rigid:
        parse_description((DATA / "door_3d.toml").read_text(), "door_3d.toml").build()
    with pytest.raises(InputError) as misfit:
        parse_description((DATA / "door_3d.toml").read_text(), "door_3d.toml").build(misalign=0.002)
    assert [_flat(q) for q in quoted] == [_flat(str(rigid.value)), _flat(str(misfit.value))]


# -- the worked example --------------------------------------------------------------------------
def worked_example() -> str:
    blocks = re.findall(r"```toml\n(.*?)```", sections()["## Worked example"], re.S)
    assert len(blocks) == 1
    return blocks[0]


@pytest.fixture(scope="module")
def side_brace():
    return parse_description(worked_example(), "side_brace.toml").build()


def test_worked_example_uses_every_table(side_brace):
    data = tomllib.loads(worked_example())
    assert set(data) == {"mechanism", "parameters", "ground", "bodies", "joints", "springs", "dampers",
                         "actuators", "gravity", "loads", "conditions"} | ({"assembly"} & set(data))
    assert data["mechanism"]["dimension"] == 3 and "downlock" in data["mechanism"]
    assert {j["type"] for j in data["joints"].values()} == {"revolute", "universal", "spherical"}
    assert {ld["type"] for ld in data["loads"].values()} == {"force", "drag", "custom"}


def test_worked_example_builds_as_described(side_brace):
    s = side_brace
    assert s.dof.dof == 1 and s.dropped_constraints == ()
    assert len(s.mechanics.coordinates) == 21 and len(s.reaction_names) == 20
    assert len(s.parameter_names) == 12
    for name in ("x_leg", "e3_lower", "mu_leg", "mu_upper", "mu_lower", "R_trunnion_x", "T_trunnion_2", "R_top_z",
                 "T_top_1", "T_knee_2", "R_ball_z", "locked", "retraction", "span", "knee_bend"):
        s.index(name)
    assert {"Fx_leg", "Qe3_lower", "norm_leg", "trunnion_rot2", "top_rot1", "ball_z", "cond_locked"} \
        <= set(s.equation_names)
    v = s.as_dict(s.defaults())
    assert v["locked"] == pytest.approx(0.0254, abs=5e-5)                  # the knee 1.45 deg off the line S - brace
    assert math.degrees(math.asin(v["locked"])) == pytest.approx(1.45, abs=0.01)


def test_worked_example_check_is_clean_and_stable(side_brace):
    rep = check_report(parse_description(worked_example(), "side_brace.toml"))
    assert rep.ok and rep.dof == 1 and not rep.redundant
    assert all(q.value == 0.0 for q in rep.closure)                        # the design pose is assembled
    assert rep.stability is not None and rep.stability.stable
    locked = next(st for st in rep.states if st.name == "locked")
    assert locked.equilibrium == pytest.approx(0.043, abs=5e-4)


def test_worked_example_downlock_force_is_the_weight_of_one_stay_half(side_brace):
    s = side_brace
    for k_lock in (10000.0, 40000.0):
        x = find_equilibrium(s, hold={"locked": 0.0}, free=["F"], values={"k_lock": k_lock}, guess=s.defaults())
        v = s.as_dict(x)
        assert v["F"] == pytest.approx(v["m_stay"] * v["g"], rel=1e-9)


def _turn(e) -> np.ndarray:
    e0, eps = e[0], np.asarray(e[1:])
    skew = np.array([[0, -eps[2], eps[1]], [eps[2], 0, -eps[0]], [-eps[1], eps[0], 0]])
    return (e0 ** 2 - eps @ eps) * np.eye(3) + 2 * np.outer(eps, eps) + 2 * e0 * skew


def test_worked_example_angle_expressions_are_the_geometric_angles(side_brace):
    s = side_brace
    for held in (-0.4, -1.0):
        v = s.as_dict(find_equilibrium(s, hold={"retraction": held}, free=["F_act"], guess=s.defaults()))
        A = {b: _turn([v[f"e{i}_{b}"] for i in range(4)]) for b in ("leg", "upper", "lower")}

        def at(body, p, _v=v, _A=A):
            return np.array([_v[f"x_{body}"], _v[f"y_{body}"], _v[f"z_{body}"]]) + _A[body] @ np.array(p)

        # the leg's turn about the trunnion axis, from where its brace point went
        u = np.array([1.0, 0.0, v["tilt"]]) / math.hypot(1.0, v["tilt"])
        b0 = np.array([0.0, 0.0, -0.9])
        b1 = at("leg", b0)
        b0, b1 = b0 - (b0 @ u) * u, b1 - (b1 @ u) * u
        assert v["retraction"] == pytest.approx(math.atan2(np.cross(b0, b1) @ u, b0 @ b1), abs=1e-10)
        assert v["retraction"] == pytest.approx(held, abs=1e-10)
        # the knee's bend: the turn from the upper stay's direction to the lower's, about the knee axis
        S, K, B = at("upper", [0, -1.1, 0.25]), at("upper", [0, -0.6, -0.3]), at("lower", [0, 0, -0.9])
        axis = A["upper"] @ np.array([1.0, 0.0, 0.0])
        now = math.atan2(np.cross(K - S, B - K) @ axis, (K - S) @ (B - K))
        up0, low0 = np.array([0, 0.5, -0.55]), np.array([0, 0.6, -0.6])
        design = math.atan2(np.cross(up0, low0)[0], up0 @ low0)
        assert v["knee_bend"] == pytest.approx(now - design, abs=1e-10)
        assert abs(v["knee_bend"]) > 0.5     # the knee really folded


def test_readme_links_the_spatial_reference():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "docs/spatial-format.md" in readme
    assert "spatial-format.md" in (ROOT / "docs" / "mechanism-format.md").read_text(encoding="utf-8")
