"""Drawing primitives of a generated mechanism at any full variable vector."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
import sympy as sp

from ..equations import Scene, compile_dense
from ._compiled import GeneratedScene
from ._kinematics import PlanarKinematics

__all__ = ["scene_function"]


def scene_function(kin: PlanarKinematics, arrows: Sequence[tuple[str, str, sp.Matrix, sp.Matrix]],
                   symbols: Sequence[sp.Symbol],
                   subs: Mapping[sp.Symbol, sp.Expr] | None = None) -> Callable[[np.ndarray], Scene]:
    """Compile ``scene(x) -> Scene`` for a system whose variables have ``symbols``.

    ``subs`` maps eliminated coordinates to expressions in the system's variables (reduced
    form). Bodies are drawn as polylines ``a -> b`` (bars; each point off the bar axis adds
    a triangle ``a -> p -> b``) or through their declared points (other bodies). Each
    load adds its arrows and draws itself (:meth:`~.loads.Load.draw`: a planar moment around the
    body's pin to the ground if it has one, else around the body's origin).
    Each force element draws itself (:meth:`~.elements.Element.draw`); the ground points they attach
    to (and no pin or weld does) are anchors. Actuators carry their tension (N): the force
    parameter, or the reaction ``T_<name>``. Lengths and loads are in the description's units (``Scene.units``).
    ``Scene.points`` names, for labels, every ground point and every named body point: the
    ends ``a``/``b`` and declared points of a bar (and its ``cg`` when off the centre), the
    declared points, ``origin`` and ``cg`` of any other body (``cg`` when off the origin).
    """
    mech, subs = kin.mech, subs or {}
    items: list[tuple[str, str, object]] = []  # (kind, name, extra)
    exprs: list[sp.Expr] = []

    def add(kind: str, name: str, pts: list[sp.Matrix], extra: object = None) -> None:
        items.append((kind, name, (len(pts), extra)))
        for p in pts:
            exprs.extend([p[0], p[1]])

    for b in mech.bodies:
        pt = lambda p, _b=b.name: kin.point(f"{_b}.{p}")  # noqa: E731
        if b.length is not None:
            add("bar", b.name, [pt("a"), pt("b")])
            for pn in b.points:
                if pn not in ("a", "b") and kin.local_point(b.name, pn)[1] != 0:
                    add("bar", b.name, [pt("a"), pt(pn), pt("b")])
        else:
            names = list(b.points) or ["origin"]
            add("bar", b.name, [pt(n) for n in names] + ([pt(names[0])] if len(names) > 2 else []))
    for j in mech.joints:
        j.draw(kin, add)
    ground_joints = {here for j in mech.joints if j.COINCIDENT for here in (j.a, j.b) if here.split(".")[0] == "ground"}
    anchors: list[str] = []
    for el in mech.force_elements():
        el.draw(kin, add)
    for ref in (r for el in mech.force_elements() for r in el.ends()):
        if ref.split(".")[0] == "ground" and ref not in ground_joints and ref not in anchors:
            anchors.append(ref)
            add("anchor", ref, [kin.point(ref)])
    for kind, name, P, F in arrows:
        add(kind, name, [P, F])
    for ld in mech.loads:
        ld.draw(kin, add)
    for b in mech.bodies:
        names = mech.point_names(b.name)
        off_origin = any(c != 0 for c in kin.local_point(b.name, "cg"))
        for pn in names:
            if (pn == "origin" and b.length is not None) or (pn == "cg" and not off_origin):
                continue
            add("point", f"{b.name}.{pn}", [kin.point(f"{b.name}.{pn}")])
    for gname in mech.ground:
        add("point", f"ground.{gname}", [kin.point(f"ground.{gname}")])
    exprs = [sp.sympify(e, strict=True).xreplace(subs) for e in exprs]
    return GeneratedScene(tuple(items), compile_dense(list(symbols), exprs), kin.mech.units)
