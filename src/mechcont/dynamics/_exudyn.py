"""The overcentre in Exudyn: an independent multibody model, as the paper checked its own with ADAMS.

Exudyn (``pip install exudyn``, in mechcont's ``test`` extra) is a C++ multibody code:
two planar rigid bodies with revolute joints, a prismatic slider, a spring-damper connector
and mass-proportional gravity, integrated by its implicit generalized-alpha method with
index-3 constraints — a different formulation and integrator from the Udwadia–Kalaba model.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError

if TYPE_CHECKING:
    from exudyn import MainSystem
    from exudyn.exudynCPP import MarkerIndex, ObjectIndex

__all__ = ["exudyn_available", "exudyn_overcentre", "solve_fixed_step"]

_NEEDED = ("L1", "L2", "m1", "m2", "g", "k", "LU", "m", "n", "c")


def exudyn_available() -> bool:
    """True if the Exudyn package can be imported."""
    try:
        import exudyn  # noqa: F401
    except ImportError:
        return False
    return True


def solve_fixed_step(mbs: MainSystem, t_end: float, h: float, spectral_radius: float = 1.0, newton_tol: float = 1e-12) -> None:
    """Assemble the Exudyn system ``mbs`` and integrate it to ``t_end`` (s) in fixed steps ``h`` (s) by its
    generalized-alpha method (``spectral_radius`` 1: the trapezoidal rule), Newton to ``newton_tol``
    (relative and absolute), quietly, sensors stored every step."""
    import exudyn as exu

    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.numberOfSteps = int(round(t_end / h))
    settings.timeIntegration.endTime = t_end
    settings.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    settings.timeIntegration.newton.relativeTolerance = newton_tol
    settings.timeIntegration.newton.absoluteTolerance = newton_tol
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = h
    settings.show.statistics = False
    settings.show.computationTime = False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        exu.SolveDynamic(mbs, settings)


def exudyn_overcentre(params: Mapping[str, float], theta1_0: float, force: Callable[[float], float], t_end: float,
                      h: float, spectral_radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Simulate the overcentre (paper Fig. 2, same parameters as ``build_overcentre``) in Exudyn.

    Parameters
    ----------
    params:
        ``L1, L2`` (m), ``m1, m2`` (kg), ``g`` (m/s^2), ``k`` (N/m), ``LU`` (m), spring
        offsets ``m, n`` (m) from the bar centres towards the apex, damper ``c`` (N s/m).
    theta1_0:
        Initial angle of bar 1 (rad); the slider end starts on y = 0, everything at rest.
    force:
        Vertical apex force F(t) in N (positive up), t in s.
    t_end, h:
        End time and fixed time step (s).
    spectral_radius:
        Generalized-alpha spectral radius; 1 is the trapezoidal rule (no numerical damping).

    Returns
    -------
    (t, theta1):
        Times (s) every step from 0 and the angle of bar 1 (rad). Raises ``ImportError``
        with installation advice when Exudyn is missing, :class:`InputError` on bad values.
    """
    try:
        import exudyn as exu
        from exudyn.itemInterface import (
            Force,
            LoadMassProportional,
            MarkerBodyMass,
            MarkerBodyPosition,
            MarkerBodyRigid,
            NodeRigidBody2D,
            ObjectConnectorSpringDamper,
            ObjectGround,
            ObjectJointPrismatic2D,
            ObjectRigidBody2D,
            RevoluteJoint2D,
            SensorNode,
        )
    except ImportError:
        raise ImportError("Exudyn is not installed (pip install exudyn, or mechcont's test extra)") from None
    missing = [k for k in _NEEDED if k not in params]
    if missing:
        raise InputError("params", f"missing {', '.join(missing)}")
    P = {k: float(params[k]) for k in _NEEDED}
    if not (t_end > 0 and h > 0 and t_end / h <= 1e7):
        raise InputError("h", "needs t_end > 0 and 0 < h, at most 1e7 steps")
    L1, L2 = P["L1"], P["L2"]
    s2 = L1 * math.sin(theta1_0) / L2
    if abs(s2) > 1:
        raise InputError("theta1_0", "the slider cannot reach y = 0 from that angle")
    th2 = math.pi - math.asin(s2)
    e1, e2 = np.array([math.cos(theta1_0), math.sin(theta1_0)]), np.array([math.cos(th2), math.sin(th2)])
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    nodes, bodies = [], []
    for cg, th, mass, length in ((L1 / 2 * e1, theta1_0, P["m1"], L1), (L1 * e1 - L2 / 2 * e2, th2, P["m2"], L2)):
        nd = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[cg[0], cg[1], th], initialVelocities=[0, 0, 0]))
        nodes.append(nd)
        bodies.append(mbs.AddObject(ObjectRigidBody2D(nodeNumber=nd, mass=mass, inertia=mass * length**2 / 12)))
    b1, b2 = bodies

    def rigid(body: ObjectIndex, x: float) -> MarkerIndex:
        return mbs.AddMarker(MarkerBodyRigid(bodyNumber=body, localPosition=[x, 0, 0]))

    def point(body: ObjectIndex, x: float) -> MarkerIndex:
        return mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[x, 0, 0]))

    origin = rigid(ground, 0.0)
    mbs.AddObject(RevoluteJoint2D(markerNumbers=[origin, rigid(b1, -L1 / 2)]))
    mbs.AddObject(RevoluteJoint2D(markerNumbers=[rigid(b1, L1 / 2), rigid(b2, L2 / 2)]))
    # slider: (p_origin - p_end) . n_ground = 0 with n = +y, rotation free
    mbs.AddObject(ObjectJointPrismatic2D(markerNumbers=[rigid(b2, -L2 / 2), origin], axisMarker0=[1, 0, 0],
                                         normalMarker1=[0, 1, 0], constrainRotation=False))
    mbs.AddObject(ObjectConnectorSpringDamper(markerNumbers=[point(b1, P["m"]), point(b2, P["n"])],
                                              stiffness=P["k"], damping=P["c"], referenceLength=P["LU"]))
    for b in bodies:
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=b)),
                                         loadVector=[0, -P["g"], 0]))
    f0 = float(force(0.0))
    mbs.AddLoad(Force(markerNumber=point(b1, L1 / 2), loadVector=[0, f0, 0],
                      # Exudyn's stub types this as its own callback class; it takes any Python callable
                      loadVectorUserFunction=lambda mbs_, t, load: [0, float(force(t)), 0]))  # type: ignore[arg-type]
    sensor = mbs.AddSensor(SensorNode(nodeNumber=nodes[0], storeInternal=True,
                                      outputVariableType=exu.OutputVariableType.Coordinates))
    solve_fixed_step(mbs, t_end, h, spectral_radius)
    data = np.asarray(mbs.GetSensorStoredData(sensor))  # typed as ArrayLike in Exudyn's stubs
    return data[:, 0], theta1_0 + data[:, 3]  # node coordinates are displacements from the reference
