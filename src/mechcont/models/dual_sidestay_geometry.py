"""Representative geometry of a dual-sidestay main landing gear of a mid-size transport (A320 class).

Knowles et al. (J. Aircraft 51(1), 2014) analysed such a gear with Airbus but published no
dimensions; neither does the 2010 paper. Every value here is *representative*, chosen from the
public figures listed in ``docs/dual-sidestay.md`` (main-gear track about 7.6 m, dual-wheel
main gear retracting inboard, main tyres 46 x 17R20 of about 1.17 m diameter, maximum take-off
mass about 78 t) and from proportion; none is an Airbus value.

Frame of the right main gear (metres): origin on the trunnion axis at the main fitting's
centre line, +x aft, +y outboard, +z up, aircraft level. The trunnion axis is
``(-cos delta, 0, -sin delta)`` (almost fore-aft, inclined by ``delta`` in the x-z plane); a
positive retraction angle ``theta`` swings the wheels inboard (-y) and up.

Each sidestay (``f`` forward, ``a`` aft) runs from an airframe attachment ``A`` to a lug ``B``
on the main fitting, folds at its knee ``K`` and is held straight by a lock-link pair from the
knee to a lug ``P`` on the main fitting through the lock-link joint ``J``. The upper arm turns
about a hinge axis at ``A`` normal to the sidestay's *plane*, so the knee and the lock links
move in that plane; the plane is the vertical plane through the stay line rotated about that
line by the sidestay *plane angle* ``phi``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Sidestay", "GearGeometry", "DEFAULT_GEOMETRY", "rotation", "trunnion_axis"]


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix (3 x 3) by ``angle`` (rad) about the unit vector ``axis`` (Rodrigues)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def trunnion_axis(delta: float) -> np.ndarray:
    """Unit trunnion axis for an inclination ``delta`` (rad): positive rotation retracts inboard."""
    return np.array([-math.cos(delta), 0.0, -math.sin(delta)])


@dataclass(frozen=True)
class Sidestay:
    """One sidestay with its lock links, at the gear-down position (m, rad).

    Attributes
    ----------
    name:
        ``fwd`` or ``aft``: the prefix of this sidestay's variables.
    A, B:
        Airframe attachment and main-fitting lug (3,), m.
    phi:
        Plane angle (rad): the fold plane is the vertical plane through A-B rotated by ``phi``
        about the line A-B (right hand, from A to B).
    upper_fraction, sag:
        The knee sits at ``upper_fraction`` of the span from A and ``sag`` (m) off the stay
        line towards :attr:`w` with the gear down; this fixes the arm lengths.
    lug, link_fraction, lock_sag:
        A point of the main fitting (m, gear down) that the lock-link lug ``P`` is the
        projection of onto the fold plane; the first lock link's share of |K - P|; and how far
        (m) the links' joint J sits off the K-P line with the gear down (on the folding side).
        These fix the lock-link lengths :attr:`link1`, :attr:`link2`.
    upper_mass, lower_mass:
        Arm masses (kg), each at its arm's middle.
    """

    name: str
    A: np.ndarray
    B: np.ndarray
    phi: float
    upper_fraction: float = 0.55
    sag: float = 0.06
    lug: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -0.35]))
    link_fraction: float = 0.53
    lock_sag: float = 0.02
    upper_mass: float = 45.0
    lower_mass: float = 40.0

    @property
    def u(self) -> np.ndarray:
        """Unit vector along the stay line, A to B."""
        d = self.B - self.A
        return d / np.linalg.norm(d)

    @property
    def w(self) -> np.ndarray:
        """Unit in-plane normal to the stay line towards which the knee breaks (rad ``phi`` from vertical)."""
        u = self.u
        z = np.array([0.0, 0.0, 1.0])
        w0 = z - (z @ u) * u
        w0 /= np.linalg.norm(w0)
        return rotation(u, self.phi) @ w0

    @property
    def normal(self) -> np.ndarray:
        """Unit normal of the fold plane = the upper hinge axis at A (and the knee and lock-link axes)."""
        return np.cross(self.u, self.w)

    @property
    def span(self) -> float:
        """|A - B| with the gear down (m)."""
        return float(np.linalg.norm(self.B - self.A))

    @property
    def upper(self) -> float:
        """Upper arm length A-K (m)."""
        return self._arms()[0]

    @property
    def lower(self) -> float:
        """Lower arm length K-B (m)."""
        return self._arms()[1]

    def _arms(self) -> tuple[float, float]:
        # knee 'sag' off the line at the fraction 'upper_fraction' of the span
        s = self.span
        a = self.upper_fraction * s
        return math.hypot(a, self.sag), math.hypot(s - a, self.sag)

    @property
    def K(self) -> np.ndarray:
        """Knee with the gear down: broken by ``sag`` towards ``w`` (m)."""
        return self.A + self.upper_fraction * self.span * self.u + self.sag * self.w

    @property
    def P(self) -> np.ndarray:
        """Lock-link lug on the main fitting (m): :attr:`lug` moved onto the fold plane."""
        return self.lug - ((self.lug - self.A) @ self.normal) * self.normal

    def _links(self) -> tuple[float, float]:
        d = float(np.linalg.norm(self.P - self.K))
        a = self.link_fraction * d
        return math.hypot(a, self.lock_sag), math.hypot(d - a, self.lock_sag)

    @property
    def link1(self) -> float:
        """Lock link K-J length (m)."""
        return self._links()[0]

    @property
    def link2(self) -> float:
        """Lock link J-P length (m)."""
        return self._links()[1]

    @property
    def J(self) -> np.ndarray:
        """Lock-link joint with the gear down, on the unlocked (folding) side (m)."""
        v = self.P - self.K
        v /= np.linalg.norm(v)
        side = np.cross(self.normal, v)
        return self.K + self.link_fraction * float(np.linalg.norm(self.P - self.K)) * v + self.lock_sag * side


@dataclass(frozen=True)
class GearGeometry:
    """The whole gear with the gear down (SI units); see the module docstring for the frame.

    ``delta`` is the trunnion inclination (rad), ``retracted`` the retraction angle of the
    gear-up position (rad); ``axle`` and ``cg`` the axle centre and the centre of gravity of
    the fitting with its wheels (``fitting_mass``, kg); the retraction actuator runs from
    ``actuator_airframe`` to ``actuator_lug`` on the fitting (m, gear down).
    """

    delta: float = math.radians(3.0)
    retracted: float = math.radians(85.0)
    axle: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.05, -2.2]))
    cg: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.03, -1.7]))
    fitting_mass: float = 1150.0
    actuator_airframe: np.ndarray = field(default_factory=lambda: np.array([0.25, -1.45, 0.45]))
    actuator_lug: np.ndarray = field(default_factory=lambda: np.array([0.25, -0.30, 0.25]))
    g: float = 9.81
    forward: Sidestay = field(default_factory=lambda: Sidestay(
        "fwd", np.array([-0.85, -1.55, 0.30]), np.array([-0.12, -0.12, -1.05]), math.radians(-30.0)))
    aft: Sidestay = field(default_factory=lambda: Sidestay(
        "aft", np.array([0.85, -1.55, 0.30]), np.array([0.12, -0.12, -1.05]), math.radians(45.0)))

    @property
    def trunnion(self) -> np.ndarray:
        """Unit trunnion axis (positive rotation retracts inboard)."""
        return trunnion_axis(self.delta)

    def with_aft_plane(self, phi: float) -> GearGeometry:
        """The same gear with the aft sidestay's plane angle ``phi`` (rad)."""
        from dataclasses import replace

        return replace(self, aft=replace(self.aft, phi=float(phi)))


DEFAULT_GEOMETRY = GearGeometry()
