"""Drawing primitives of a generated spatial mechanism at any full variable vector."""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from ...equations import compile_dense
from .._compiled import SpatialScene
from ._kinematics import SpatialKinematics

__all__ = ["spatial_scene_function", "SpatialScene"]


def spatial_scene_function(kin: SpatialKinematics, arrows: Sequence[tuple[str, str, sp.Matrix, sp.Matrix]],
                           symbols: Sequence[sp.Symbol]) -> SpatialScene:
    """Compile ``scene(x) -> Scene`` (3-vectors, m, N, N m) for the spatial mechanism of ``kin``.

    A bar is drawn from ``a`` to ``b`` (a triangle through each declared point); another body
    as a polyline through its declared points. Each joint is a pin (a ground pin when one side
    is the ground) at its point ``b``, with its axes (revolute, universal, cylindrical,
    prismatic) in ``Scene.joint_axes``. Springs, dampers, actuators (with their tension, N),
    their ground anchors, point forces and moments (3-vectors, N m) and every named point follow.
    """
    mech = kin.mech
    items: list[tuple[str, str, int]] = []
    exprs: list[sp.Expr] = []

    def add(kind: str, name: str, pts: list) -> None:
        items.append((kind, name, len(pts)))
        for p in pts:
            exprs.extend(list(p))

    for b in mech.bodies:
        def pt(p: str, _b: str = b.name) -> sp.Matrix:
            return kin.point(f"{_b}.{p}")
        if b.length is not None:
            add("bar", b.name, [pt("a"), pt("b")])
            for pn in b.points:
                add("bar", b.name, [pt("a"), pt(pn), pt("b")])
        else:
            names = list(b.points) or ["origin"]
            add("bar", b.name, [pt(n) for n in names] + ([pt(names[0])] if len(names) > 2 else []))
    ground_refs = {r for j in mech.joints for r in (j.a, j.b) if r.startswith("ground.")}
    for j in mech.joints:
        j.draw(kin, add)
    for el in mech.force_elements():
        el.draw(kin, add)
    anchors: list[str] = []
    for ref in (r for el in mech.force_elements() for r in el.ends()):
        if ref.startswith("ground.") and ref not in ground_refs and ref not in anchors:
            anchors.append(ref)
            add("anchor", ref, [kin.point(ref)])
    for kind, name, P, F in arrows:
        add(kind, name, [P, F])
    for b in mech.bodies:
        off_origin = any(c != 0 for c in kin.local_point(b.name, "cg"))
        for pn in mech.point_names(b.name):
            if pn == "origin" or (pn == "cg" and not off_origin):  # a spatial frame origin marks nothing
                continue
            add("point", f"{b.name}.{pn}", [kin.point(f"{b.name}.{pn}")])
    for gname in mech.ground:
        add("point", f"ground.{gname}", [kin.point(f"ground.{gname}")])
    return SpatialScene(tuple(items), compile_dense(list(symbols), [sp.sympify(e, strict=True) for e in exprs]),
                        kin.mech.units)
