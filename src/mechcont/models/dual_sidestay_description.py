"""The dual-sidestay main gear as a spatial description file, written from its geometry.

:func:`dual_sidestay_description` turns a :class:`~.dual_sidestay_geometry.GearGeometry` into
the TOML text of a spatial mechanism (``examples/dual_sidestay.toml`` is this text for the
representative geometry; ``tests`` check they agree). Hard points are in the gear frame of
:mod:`.dual_sidestay_geometry` (m, gear down, +x aft, +y outboard, +z up), at full precision
so the generated model and the hand-formulated one (:mod:`.dual_sidestay`) describe the same
gear.

Bodies and joints (the same idealisation as the hand model, now as rigid bodies):

* the main fitting (with shock strut and wheels) turns about the trunnion axis: a spherical
  bearing forward and an inline (sliding) bearing aft, together a determinate hinge;
* each sidestay's upper arm is hinged at its airframe attachment ``A`` about the fold-plane
  normal ``n``; the lower arm joins it at the knee ``K`` by a universal joint (``n`` on the upper
  arm, across the lower arm) and the fitting at ``B`` by a spherical joint;
* each lock-link pair: link 1 hinged to the upper arm at ``K`` about ``n``, link 2 joined to it
  at ``J`` by a universal joint and to the fitting at ``P`` by a spherical joint;
* a lock spring per sidestay from link 1 to the lower arm; a retraction actuator (force mode,
  tension ``F_act``) from the airframe to the fitting; an unlock force ``F_<side>`` at each ``J``
  normal to the link line in the fold plane (positive towards unlocking; ``F_lock`` acts at both
  together); gravity;
* each lock-link pair has an overcentre stop 2 deg past aligned (``[stops.<side>_stop]`` on the
  condition ``<side>_lock``, whose sine an unlock force drives negative; contact reaction
  ``R_<side>_stop``, N m). In the design pose (gear down, theta = 0) the links are about 3 deg on
  the unlocking side of aligned (``fwd_lock`` = -0.049, ``aft_lock`` = -0.053); locked, they rest
  on their stops a few thousandths of a degree of retraction away.

The aft sidestay's airframe attachment may be compliant (``k_att``, N/m): with both lock-link
pairs held aligned the gear is over-constrained (one sidestay already fixes the fitting), and
the attachment's deflection is what makes every reaction determinate.

The downlocked gear (``locked=True``, ``examples/dual_sidestay_locked.toml``) welds each lock-link
pair on its stop, not at the design pose: a weld fixes the links' relative orientation as drawn,
and drawn at the design pose (3 deg on the unlocking side) it would lock a gear that is not the
one resting on its stops. So lock link 2 is written turned about ``J`` in the fold plane until
``<side>_lock`` = :data:`STOP_SINE` (:func:`lug_on_stop`; link 1, the lock spring's points and its
free length stay as in the unlocked file). Its end ``P`` then misses the fitting's lug by about
6 cm: the design pose no longer closes, and the first assembly closes the rigid joints
from it (the compliant aft attachment taking up the rest) and Newton finds the locked
equilibrium. That is the unlocked gear's equilibrium with both stops in contact: the same
retraction angle (-0.007 deg), lock-link sines and aft attachment reaction (2.08 kN), as
``tests/test_dual_sidestay_generated.py`` checks. The joints differ where the lock is: a weld at
``J`` and an inline joint at ``P`` (free along ``n``) instead of a universal and a spherical joint,
so the fitting's lug carries no force along ``n`` and half of link 2's weight along ``n`` (7 and
9 N) reaches the airframe through ``K`` instead; this moves the aft attachment reaction by 9 N
(its magnitude by 1.7 N). With massless lock links the two agree to 0.01 N.
"""

from __future__ import annotations

import numpy as np

from .dual_sidestay_geometry import DEFAULT_GEOMETRY, GearGeometry, Sidestay, rotation

__all__ = ["dual_sidestay_description", "lug_on_stop", "SPRING_POSITION", "STOP_ANGLE_DEG", "STOP_SINE"]

#: Lock spring ends: fraction of lock link 1 from K, and of the lower arm from K.
SPRING_POSITION = (0.35, 0.4)
#: How far past aligned (deg) the lock links rest on their stops when locked (a representative rigging).
STOP_ANGLE_DEG = 2.0
#: The stops' limit on the ``<side>_lock`` conditions: an unlock force drives the sine negative, so the
#: overcentre side is positive and the stop is ``max = sin(2 deg)``.
STOP_SINE = float(np.sin(np.radians(STOP_ANGLE_DEG)))


def _num(x: float) -> str:
    """``x`` rounded to 12 significant digits, as the shortest text that reads back as that value.

    The geometry is computed with NumPy (norms, cross products), whose last bits depend on the
    BLAS kernel and CPU; rounding makes the generated file the same text on every machine
    (a value 1e-12 from a rounding boundary aside, which the tests allow for).
    """
    return repr(float(f"{float(x):.12g}"))


def _v(a: np.ndarray) -> str:
    """A vector (m) as a TOML array of rounded numbers (:func:`_num`)."""
    return "[" + ", ".join(_num(c) for c in np.asarray(a, float)) + "]"


def _unit(a: np.ndarray) -> np.ndarray:
    """``a`` divided by its length."""
    a = np.asarray(a, float)
    return a / np.linalg.norm(a)


def lug_on_stop(st: Sidestay) -> np.ndarray:
    """Where lock link 2's far end ``P`` (m, gear frame) lies when the links of ``st`` rest on their stop.

    Link 1 stays at its design pose (``K`` to ``J``) and link 2 turns about ``J`` in the fold plane
    (normal ``n``, which holds ``K``, ``J`` and ``P`` with the gear down) until the condition
    ``<side>_lock``, the sine of the angle at ``K`` from ``J`` to ``P`` about ``n``, equals
    :data:`STOP_SINE`: in the triangle ``K J P`` with ``|K J| = L4``, ``|J P| = L5`` and that angle
    ``a`` at ``K``, ``|K P| = L4 cos a + sqrt(L5^2 - L4^2 sin^2 a)``.
    """
    n, a = st.normal, np.radians(STOP_ANGLE_DEG)
    kj = st.J - st.K
    l4, l5 = float(np.linalg.norm(kj)), float(np.linalg.norm(st.P - st.J))
    r = l4 * np.cos(a) + np.sqrt(l5 ** 2 - (l4 * np.sin(a)) ** 2)
    return st.K + r * (rotation(n, a) @ kj) / l4


def dual_sidestay_description(geo: GearGeometry = DEFAULT_GEOMETRY, *, compliant_aft: bool = True,
                              locked: bool = False) -> str:
    """TOML text of the spatial description of ``geo`` (see the module docstring).

    ``compliant_aft`` gives the aft sidestay's airframe attachment the translational stiffness
    parameter ``k_att`` (N/m); otherwise every joint is rigid. ``locked`` describes the gear
    downlocked: each lock-link pair welded at its joint ``J`` on its stop (link 2 written turned
    about ``J`` to :data:`STOP_SINE`, see the module docstring) and free to slide along the
    fold-plane normal at the fitting lug ``P`` (so a locked pair holds the knee in its plane and
    nothing else): each sidestay is a strut, and the two together over-constrain the fitting's one
    degree of freedom (``dof = 0``; assembled and determinate only with ``compliant_aft``).
    """
    e = geo.trunnion
    out = [
        "# A representative dual-sidestay main landing gear (A320 class), generated by",
        "# mechcont.models.dual_sidestay_description from the geometry documented in docs/dual-sidestay.md.",
        "# Hard points in the gear frame (m, gear down): +x aft, +y outboard, +z up; representative values,",
        "# not an Airbus design. See that module's docstring for the bodies and joints.",
        *([f"# Downlocked: each lock-link pair welded on its overcentre stop, {STOP_ANGLE_DEG:g} deg past aligned",
           "# (<side>_lock = sin of that): lock link 2 is written turned about J to that angle, so its end P misses",
           "# the fitting's lug and the loops close only when assembled, which moves the gear to its locked pose",
           "# (a few thousandths of a degree of retraction, the aft attachment taking up the misfit)."]
          if locked else []),
        "",
        "[mechanism]",
        f'name = "dual_sidestay{"_locked" if locked else ""}"',
        "dimension = 3",
        f"dof = {0 if locked else 1}",
        'description = "Dual-sidestay main gear: fitting on its trunnion, two folding sidestays with lock links'
        + (', downlocked (lock links welded)"' if locked else '"'),
        "",
        "[parameters]",
        'g = { value = 9.81, unit = "m/s^2" }',
        'F_act = { value = 0.0, unit = "N", description = "retraction actuator tension (+ pulls its ends together)" }',
        'F_fwd = { value = 0.0, unit = "N", description = "unlock force at the forward lock-link joint" }',
        'F_aft = { value = 0.0, unit = "N", description = "unlock force at the aft lock-link joint" }',
        'F_lock = { value = 0.0, unit = "N", description = "unlock force at both lock-link joints together" }',
        'k_lock = { value = 8000.0, unit = "N/m", description = "lock spring stiffness" }',
        'stretch = { value = 0.7, unit = "", description = "lock spring free length / its gear-down length" }',
        'm_link1 = { value = 4.0, unit = "kg", description = "lock link 1 mass" }',
        'm_link2 = { value = 3.5, unit = "kg", description = "lock link 2 mass" }',
    ]
    if compliant_aft:
        out.append('k_att = { value = 5.0e7, unit = "N/m", description = "aft sidestay airframe attachment stiffness" }')
    freefall = compliant_aft and not locked
    if freefall:
        out += ['c_ret = { value = 2.0e4, unit = "N s/m", description = "retraction actuator as a damper, laminar term '
                '(freefall: hydraulics failed)" }',
                'c2_ret = { value = 2.0e5, unit = "N s^2/m^2", description = "retraction actuator restrictor, '
                'quadratic term" }',
                'zeta_att = { value = 0.05, unit = "", description = "damping ratio of the aft upper arm on its '
                'attachment" }']
    trunnion_fwd, trunnion_aft = 0.35 * e, -0.35 * e
    out += ["", "[ground]", f"T_fwd = {_v(trunnion_fwd)}", f"T_aft = {_v(trunnion_aft)}",
            f"C = {_v(geo.actuator_airframe)}"]
    for st in (geo.forward, geo.aft):
        out.append(f"A_{st.name} = {_v(st.A)}")
    if freefall:  # 1 m from the aft attachment along each axis: one damper along each
        out += [f"A_aft_{axis} = {_v(geo.aft.A + np.eye(3)[k])}" for k, axis in enumerate("xyz")]
    fit_points = {"T_fwd": trunnion_fwd, "T_aft": trunnion_aft, "axle": geo.axle, "D": geo.actuator_lug}
    for st in (geo.forward, geo.aft):
        fit_points[f"B_{st.name}"], fit_points[f"P_{st.name}"] = st.B, st.P
    out += ["", "[bodies.fitting]", f"mass = {_num(geo.fitting_mass)}", "inertia = [1400.0, 1500.0, 250.0]",
            f"cg = {_v(geo.cg)}", "description = \"main fitting, shock strut and wheels\"",
            "points = { " + ", ".join(f"{k} = {_v(p)}" for k, p in fit_points.items()) + " }"]
    sa, sb = SPRING_POSITION
    for st in (geo.forward, geo.aft):
        s, n = st.name, st.normal
        spring_1 = st.K + sa * (st.J - st.K)
        spring_2 = st.K + sb * (st.B - st.K)
        link2_end = lug_on_stop(st) if locked else st.P
        for body, mass, a, b, extra in (("upper", st.upper_mass, st.A, st.K, {}),
                                        ("lower", st.lower_mass, st.K, st.B, {"spring": spring_2}),
                                        ("link1", "m_link1", st.K, st.J, {"spring": spring_1}),
                                        ("link2", "m_link2", st.J, link2_end, {})):
            length = float(np.linalg.norm(b - a))
            pts = {"a": a, "b": b, **extra}
            across = f'"{mass}*{_num(length ** 2 / 12)}"' if isinstance(mass, str) else _num(mass * length ** 2 / 12)
            shown = f'"{mass}"' if isinstance(mass, str) else _num(mass)
            out += ["", f"[bodies.{s}_{body}]", f"mass = {shown}",
                    f"inertia = [{across}, {across}, {across}]", f"cg = {_v((a + b) / 2)}",
                    "points = { " + ", ".join(f"{k} = {_v(p)}" for k, p in pts.items()) + " }"]
        stiff = '\nstiffness = "k_att"' if (compliant_aft and s == "aft") else ""
        knee_cross = _unit(np.cross(n, st.B - st.K))
        link_cross = _unit(np.cross(n, st.P - st.J))
        out += ["", f"[joints.{s}_A]", 'type = "revolute"', f'a = "ground.A_{s}"', f'b = "{s}_upper.a"',
                f"axis = {_v(n)}{stiff}",
                "", f"[joints.{s}_knee]", 'type = "universal"', f'a = "{s}_upper.b"', f'b = "{s}_lower.a"',
                f"axis_a = {_v(n)}", f"axis_b = {_v(knee_cross)}",
                "", f"[joints.{s}_B]", 'type = "spherical"', f'a = "{s}_lower.b"', f'b = "fitting.B_{s}"',
                "", f"[joints.{s}_K]", 'type = "revolute"', f'a = "{s}_upper.b"', f'b = "{s}_link1.a"',
                f"axis = {_v(n)}",
                "", f"[joints.{s}_J]", *(['type = "weld"', f'a = "{s}_link1.b"', f'b = "{s}_link2.a"'] if locked else
                                         ['type = "universal"', f'a = "{s}_link1.b"', f'b = "{s}_link2.a"',
                                          f"axis_a = {_v(n)}", f"axis_b = {_v(link_cross)}"]),
                "", f"[joints.{s}_P]", *(['type = "inline"', f'a = "{s}_link2.b"', f'b = "fitting.P_{s}"',
                                          f"axis = {_v(n)}"] if locked else
                                         ['type = "spherical"', f'a = "{s}_link2.b"', f'b = "fitting.P_{s}"'])]
    out += ["", "[joints.trunnion_fwd]", 'type = "spherical"', 'a = "ground.T_fwd"', 'b = "fitting.T_fwd"',
            "", "[joints.trunnion_aft]", 'type = "inline"', 'a = "ground.T_aft"', 'b = "fitting.T_aft"',
            f"axis = {_v(e)}"]
    for st in (geo.forward, geo.aft):
        s = st.name
        free = float(np.linalg.norm((st.K + sa * (st.J - st.K)) - (st.K + sb * (st.B - st.K))))
        out += ["", f"[springs.{s}_spring]", f'a = "{s}_link1.spring"', f'b = "{s}_lower.spring"', 'k = "k_lock"',
                f'free_length = "stretch*{_num(free)}"']
    out += ["", "[actuators.retraction]", 'a = "ground.C"', 'b = "fitting.D"', 'force = "F_act"',
            'description = "retraction actuator"', "", "[gravity]", 'g = "g"', "direction = [0, 0, -1]"]
    if freefall:  # they act only in time simulation (a freefall): no static equation changes
        out += ["", "[dampers.actuator]", 'a = "ground.C"', 'b = "fitting.D"', 'c = "c_ret"', 'c2 = "c2_ret"']
        for axis in "xyz":
            out += ["", f"[dampers.attachment_{axis}]", f'a = "ground.A_aft_{axis}"', 'b = "aft_upper.a"',
                    f'c = "2*zeta_att*sqrt(k_att*{_num(geo.aft.upper_mass)})"']
    for st in (geo.forward, geo.aft):
        s = st.name
        unlock = _unit(np.cross(st.normal, st.P - st.K))
        out += ["", f"[loads.F_{s}]", 'type = "force"', f'at = "{s}_link1.b"', f'magnitude = "F_{s} + F_lock"',
                f"direction = {_v(unlock)}"]
    out += ["", "[conditions]"]
    # the retraction angle: the fitting's rotation about the trunnion axis e (right hand) from gear down
    out.append('theta = { expr = "2*atan2(' + " + ".join(f"({_num(c)})*e{i + 1}_fitting" for i, c in enumerate(e))
               + ', e0_fitting)", unit = "rad", description = "retraction angle about the trunnion axis" }')
    for st in (geo.forward, geo.aft):
        s = st.name
        out.append(f'{s}_lock = {{ type = "collinear", points = ["{s}_link1.a", "{s}_link1.b", "{s}_link2.b"], '
                   f'normal = {_v(st.normal)}, description = "sine of the {s} lock links\' angle (0: aligned)" }}')
    if not locked:
        for st in (geo.forward, geo.aft):
            out += ["", f"[stops.{st.name}_stop]", f'condition = "{st.name}_lock"', f"max = {_num(STOP_SINE)}",
                    f'description = "{st.name} lock links\' overcentre stop, {STOP_ANGLE_DEG:g} deg past aligned"']
    return "\n".join(out) + "\n"
