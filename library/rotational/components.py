"""Rotational components (Modelica.Mechanics.Rotational.Components)."""

from __future__ import annotations

import sympy as sp

from acausal.language import (
    Boolean,
    Component,
    Eq,
    If,
    Parameter,
    RealInput,
    RealOutput,
    StateSelect,
    Variable,
    der,
)
from acausal.functions import prescribed
from acausal.hybrid import noEvent
from acausal.components.adaptors import FlowToPotentialAdaptor, PotentialToFlowAdaptor
from acausal.components.checks import check_min, where
from acausal.components.friction import PartialFriction, check_friction_table, friction_table, table_signs
from acausal.components.logic import is_initial, pre_boolean
from acausal.components.rotational import (
    EPS,
    Flange_a,
    Flange_b,
    PartialCompliant,
    PartialCompliantWithRelativeStates,
    PartialElementaryRotationalToTranslational,
    PartialElementaryTwoFlangesAndSupport2,
    PartialTwoFlanges,
)
from acausal.components.thermal import PartialElementaryConditionalHeatPortWithoutT

__all__ = [
    "Inertia",
    "Fixed",
    "Spring",
    "Damper",
    "SpringDamper",
    "IdealGear",
    "IdealPlanetary",
    "BearingFriction",
    "Clutch",
    "Brake",
    "OneWayClutch",
    "IdealGearR2T",
    "IdealRollingWheel",
    "ElastoBacklash",
    "ElastoBacklash2",
    "Disc",
    "RelativeStates",
    "InitializeFlange",
    "TorqueToAngleAdaptor",
    "AngleToTorqueAdaptor",
    "GeneralTorqueToAngleAdaptor",
    "GeneralAngleToTorqueAdaptor",
]


# --------------------------------------------------------------------------
# helpers for the table-driven friction elements


_PEAK_HINT = "peak = tau0_max/tau0 (static over sliding friction at w = 0) must be >= 1"


class _TableFriction:
    """Parameter checks shared by the table-driven friction elements."""

    _table_name = "mu_pos"

    def build(self) -> None:
        self.check_parameters()

    def check_parameters(self) -> None:
        """Raise ParameterError for an invalid friction table, peak < 1 or fn_max < 0."""
        check_friction_table(self, self._table_name)
        check_min(self, "peak", 1.0, _PEAK_HINT)
        if "fn_max" in self.declarations():
            check_min(self, "fn_max", 0.0, "fn_max is the maximum normal force; it must be >= 0")


class _NormalForceFriction(_TableFriction):
    """The friction law Clutch and Brake share: a normal force times a friction coefficient.

    ``fn = fn_max*f_normalized``; free when ``fn <= 0``; sliding torque
    ``mu*cgeo*fn`` with ``mu`` from the table ``mu_pos`` (mirrored by the
    signs of :func:`~acausal.components.friction.table_signs`); static limit
    ``tau0_max = peak*mu_pos(0)*cgeo*fn``.
    """

    _clutch_quirk = False

    mu_pos = Parameter([[0.0, 0.5]], structural=True,
                       description="[w,mu] positive sliding friction coefficient (w_relfric>=0)")
    peak = Parameter(1.0, min=1,
                     description="Peak for maximum value of mu at w==0 (mu0_max = peak*mu_pos[1,2])")
    cgeo = Parameter(1.0, min=0, description="Geometry constant containing friction distribution assumption")
    fn_max = Parameter(1.0, unit="N", min=0, description="Maximum normal force")
    f_normalized = RealInput(unit="1",
                             description="Normalized force signal 0..1 (normal force = fn_max*f_normalized; "
                                         "engaged if > 0)")
    mu = Variable(unit="1", description="Friction coefficient")
    fn = Variable(unit="N", description="Normal force (=fn_max*f_normalized)")

    def equations(self):
        MU = friction_table(self, "mu_pos")
        s1, s2 = table_signs(self, clutch_quirk=self._clutch_quirk)
        mu0 = MU(0)
        return [
            Eq(self.fn, self.fn_max * self.f_normalized),
            Eq(self.free, self.fn <= 0),
            Eq(self.tau0, mu0 * self.cgeo * self.fn),
            Eq(self.tau0_max, self.peak * self.tau0),
            Eq(self.mu, s2 * MU(s1 * self.w_relfric)),
            Eq(self.tau, sp.Piecewise((self.sa, self.locked), (0, self.free),
                                      (self.mu * self.cgeo * self.fn, True))),
            Eq(self.lossPower, self.tau * self.w_relfric),
        ]


# --------------------------------------------------------------------------


class Inertia(PartialTwoFlanges):
    """1D rotational component with inertia (Modelica.Mechanics.Rotational.Components.Inertia).

    Both flanges are rigidly attached to a body with moment of inertia ``J``:
    ``J*a = flange_a.tau + flange_b.tau`` with ``w = der(phi)`` and ``a =
    der(w)``.  The absolute angle ``phi`` and speed ``w`` carry the
    ``stateSelect`` hint (default StateSelect.default).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Inertia"

    J = Parameter(1.0, unit="kg.m2", min=0, description="Moment of inertia")
    stateSelect = Parameter(StateSelect.default, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use phi and w as states")
    phi = Variable(unit="rad", state_select=lambda c: c.stateSelect,
                   description="Absolute rotation angle of component")
    w = Variable(unit="rad/s", state_select=lambda c: c.stateSelect,
                 description="Absolute angular velocity of component (= der(phi))")
    a = Variable(unit="rad/s2", description="Absolute angular acceleration of component (= der(w))")

    def equations(self):
        return [
            Eq(self.phi, self.flange_a.phi),
            Eq(self.phi, self.flange_b.phi),
            Eq(self.w, der(self.phi)),
            Eq(self.a, der(self.w)),
            Eq(self.J * self.a, self.flange_a.tau + self.flange_b.tau),
        ]


class Fixed(Component):
    """Flange fixed in the housing at an angle (Modelica.Mechanics.Rotational.Components.Fixed).

    ``flange.phi = phi0``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Fixed"

    phi0 = Parameter(0.0, unit="rad", description="Fixed offset angle of housing")
    flange = Flange_b(description="Flange fixed in housing at a given angle")

    def equations(self):
        return [Eq(self.flange.phi, self.phi0)]


class Spring(PartialCompliant):
    """Linear 1D rotational spring (Modelica.Mechanics.Rotational.Components.Spring).

    ``tau = c*(phi_rel - phi_rel0)``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Spring"

    c = Parameter(1.0e5, unit="N.m/rad", min=0, description="Spring constant")
    phi_rel0 = Parameter(0.0, unit="rad", description="Unstretched spring angle")

    def equations(self):
        return [Eq(self.tau, self.c * (self.phi_rel - self.phi_rel0))]


class Damper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D rotational damper (Modelica.Mechanics.Rotational.Components.Damper).

    ``tau = d*w_rel``; the dissipated power ``lossPower = tau*w_rel`` goes to
    the optional heat port.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Damper"

    d = Parameter(0.0, unit="N.m.s/rad", min=0, description="Damping constant")

    def equations(self):
        return [Eq(self.tau, self.d * self.w_rel), Eq(self.lossPower, self.tau * self.w_rel)]


class SpringDamper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D rotational spring and damper in parallel (Modelica.Mechanics.Rotational.Components.SpringDamper).

    ``tau = c*(phi_rel - phi_rel0) + d*w_rel``; only the damper part
    dissipates (``lossPower = tau_d*w_rel``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.SpringDamper"

    c = Parameter(1.0e5, unit="N.m/rad", min=0, description="Spring constant")
    d = Parameter(0.0, unit="N.m.s/rad", min=0, description="Damping constant")
    phi_rel0 = Parameter(0.0, unit="rad", description="Unstretched spring angle")
    tau_c = Variable(unit="N.m", description="Spring torque (protected)")
    tau_d = Variable(unit="N.m", description="Damping torque (protected)")

    def equations(self):
        return [
            Eq(self.tau_c, self.c * (self.phi_rel - self.phi_rel0)),
            Eq(self.tau_d, self.d * self.w_rel),
            Eq(self.tau, self.tau_c + self.tau_d),
            Eq(self.lossPower, self.tau_d * self.w_rel),
        ]


class IdealGear(PartialElementaryTwoFlangesAndSupport2):
    """Ideal gear without inertia (Modelica.Mechanics.Rotational.Components.IdealGear).

    ``phi_a = ratio*phi_b`` (angles relative to the support) and ``0 =
    ratio*flange_a.tau + flange_b.tau``; the reaction torque goes to the
    optional support.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.IdealGear"

    ratio = Parameter(1.0, description="Transmission ratio (flange_a.phi/flange_b.phi)")
    phi_a = Variable(unit="rad", description="Angle between left shaft flange and support")
    phi_b = Variable(unit="rad", description="Angle between right shaft flange and support")

    def equations(self):
        return [
            Eq(self.phi_a, self.flange_a.phi - self.phi_support),
            Eq(self.phi_b, self.flange_b.phi - self.phi_support),
            Eq(self.phi_a, self.ratio * self.phi_b),
            Eq(0, self.ratio * self.flange_a.tau + self.flange_b.tau),
        ]


class IdealPlanetary(Component):
    """Ideal planetary gear box (Modelica.Mechanics.Rotational.Components.IdealPlanetary).

    ``(1 + ratio)*carrier.phi = sun.phi + ratio*ring.phi`` with ``ratio`` =
    ring teeth / sun teeth; ``ring.tau = ratio*sun.tau`` and ``carrier.tau =
    -(1 + ratio)*sun.tau``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.IdealPlanetary"

    ratio = Parameter(100 / 50, description="Number of ring_teeth/sun_teeth (e.g. ratio=100/50)")
    sun = Flange_a(description="Flange of sun shaft")
    carrier = Flange_a(description="Flange of carrier shaft")
    ring = Flange_b(description="Flange of ring shaft")

    def equations(self):
        return [
            Eq((1 + self.ratio) * self.carrier.phi, self.sun.phi + self.ratio * self.ring.phi),
            Eq(self.ring.tau, self.ratio * self.sun.tau),
            Eq(self.carrier.tau, -(1 + self.ratio) * self.sun.tau),
        ]


class _HousingFriction:
    """Friction between a rigid shaft (flange_a = flange_b) and its housing.

    Shared by BearingFriction and Brake: the shaft angle relative to the
    support, its speed and acceleration as the friction element's relative
    motion, and the torque the element absorbs from its flanges.
    """

    phi = Variable(unit="rad", description="Angle between shaft flanges (flange_a, flange_b) and support")
    tau = Variable(unit="N.m", description="Friction torque absorbed from the flanges")
    w = Variable(unit="rad/s", description="Absolute angular velocity of flange_a and flange_b")
    a = Variable(unit="rad/s2", description="Absolute angular acceleration of flange_a and flange_b")

    def equations(self):
        return [
            Eq(self.phi, self.flange_a.phi - self.phi_support),
            Eq(self.flange_b.phi, self.flange_a.phi),
            Eq(self.w, der(self.phi)),
            Eq(self.a, der(self.w)),
            Eq(self.w_relfric, self.w),
            Eq(self.a_relfric, self.a),
            Eq(self.flange_a.tau + self.flange_b.tau - self.tau, 0),
        ]


class BearingFriction(_HousingFriction, _TableFriction, PartialElementaryTwoFlangesAndSupport2, PartialFriction,
                      PartialElementaryConditionalHeatPortWithoutT):
    """Coulomb friction in bearings (Modelica.Mechanics.Rotational.Components.BearingFriction).

    Friction between the rigidly connected flanges and the housing: the
    sliding friction torque is ``tau_pos`` (an n x 2 table of w >= 0 against
    torque, interpolated linearly with LastTwoPoints extrapolation and
    mirrored for w < 0), the static limit is ``tau0_max = peak*tau_pos(0)``,
    and the stuck/sliding logic is :class:`acausal.components.friction.PartialFriction`.
    ``lossPower = tau*w`` goes to the optional heat port.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.BearingFriction"

    _table_name = "tau_pos"

    tau_pos = Parameter([[0.0, 1.0]], structural=True, unit="N.m",
                        description="[w,tau] positive sliding friction characteristic (w>=0)")
    peak = Parameter(1.0, min=1,
                     description="Peak for maximum friction torque at w==0 (tau0_max = peak*tau_pos[1,2])")

    def equations(self):
        T = friction_table(self, "tau_pos")
        s1, s2 = table_signs(self)
        return [
            Eq(self.tau0, T(0)),
            Eq(self.tau0_max, self.peak * self.tau0),
            Eq(self.free, sp.false),
            Eq(self.tau, If(self.locked, self.sa, s2 * T(s1 * self.w))),
            Eq(self.lossPower, self.tau * self.w_relfric),
        ]


class Clutch(_NormalForceFriction, PartialCompliantWithRelativeStates, PartialFriction,
             PartialElementaryConditionalHeatPortWithoutT):
    """Clutch with controlled normal force (Modelica.Mechanics.Rotational.Components.Clutch).

    Friction between flange_a and flange_b: ``fn = fn_max*f_normalized``, the
    element is free when ``fn <= 0``, the sliding torque is ``mu*cgeo*fn``
    with ``mu`` from the table ``mu_pos`` (w_rel >= 0), the static limit
    ``tau0_max = peak*mu_pos(0)*cgeo*fn``; stuck/sliding logic from
    :class:`acausal.components.friction.PartialFriction`.  As in the MSL, the start of
    backward sliding evaluates the table at ``+w_rel`` with sign -1.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Clutch"

    _clutch_quirk = True  # MSL evaluates the table at +w_rel when starting backward

    def equations(self):
        return [
            Eq(self.w_relfric, self.w_rel),
            Eq(self.a_relfric, self.a_rel),
        ]


class Brake(_HousingFriction, _NormalForceFriction, PartialElementaryTwoFlangesAndSupport2, PartialFriction,
            PartialElementaryConditionalHeatPortWithoutT):
    """Brake with controlled normal force (Modelica.Mechanics.Rotational.Components.Brake).

    Friction between the rigidly connected flanges and the housing:
    ``fn = fn_max*f_normalized``, free when ``fn <= 0``, sliding torque
    ``mu*cgeo*fn`` with ``mu`` from the table ``mu_pos`` mirrored for w < 0,
    static limit ``tau0_max = peak*mu_pos(0)*cgeo*fn``; stuck/sliding logic
    from :class:`acausal.components.friction.PartialFriction`.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Brake"


class OneWayClutch(_TableFriction, PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Parallel connection of a freewheel and a clutch (Modelica.Mechanics.Rotational.Components.OneWayClutch).

    The freewheel blocks ``w_rel < 0``; it lets go when the transmitted torque
    ``sa`` exceeds ``tau0_max`` (``peak2*mu_pos(0)*cgeo*fn`` when engaged, the
    tiny ``tau0_max_low = 1e-4*mu_pos(0)*cgeo*fn_max`` when disengaged).  The
    clutch part transmits ``mu_pos(w_rel)*cgeo*fn`` while sliding.  It has its
    own stuck/sliding logic (``startForward``, ``locked``, ``stuck``), not
    PartialFriction; initial values must satisfy ``w_rel >= 0``.

    ``sa`` is declared in N.m (the torque it is compared with and stands for
    while locked); while sliding ``a_rel = (sa -
    tau0)*unitAngularAcceleration/unitTorque``, with the MSL's unit
    constants (both 1; the MSL declares ``sa`` with unit "1" instead).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.OneWayClutch"

    #: constant eps0 of the MSL: relative tolerance for the disengaged threshold
    eps0 = 1.0e-4

    mu_pos = Parameter([[0.0, 0.5]], structural=True,
                       description="[w,mu] positive sliding friction coefficient (w_rel>=0)")
    peak = Parameter(1.0, min=1,
                     description="Peak for maximum value of mu at w==0 (mu0_max = peak*mu_pos[1,2])")
    cgeo = Parameter(1.0, min=0, description="Geometry constant containing friction distribution assumption")
    fn_max = Parameter(1.0, unit="N", min=0, description="Maximum normal force")
    w_small = Parameter(1.0e10, unit="rad/s",
                        description="Relative angular velocity near to zero if jumps due to a reinit(..) "
                                    "of the velocity can occur")
    f_normalized = RealInput(unit="1",
                             description="Normalized force signal 0..1 (normal force = fn_max*f_normalized; clutch is engaged if > 0)")
    u = Variable(unit="1", description="Normalized force input signal (0..1)")
    mu = Variable(unit="1", description="Friction coefficient")
    fn = Variable(unit="N", description="Normal force (=fn_max*inPort.signal)")
    startForward = Boolean(start=False,
                           description="true, if w_rel=0 and start of forward sliding")  # noqa: N815
    locked = Boolean(start=False, description="true, if w_rel=0 and not sliding")
    stuck = Boolean(start=False, description="w_rel <= 0 and not sliding")
    tau0 = Variable(unit="N.m", description="Friction torque for w=0 and sliding (protected)")
    tau0_max = Variable(unit="N.m", description="Maximum friction torque for w=0 and locked (protected)")
    free = Boolean(description="true, if frictional element is not active (protected)")
    sa = Variable(unit="N.m",
                  description="Path parameter of tau = f(a_rel) friction characteristic (protected)")
    # Unit constants (MSL: constant ... = 1): (sa - tau0)*unitAngularAcceleration/unitTorque is a
    # torque read as an acceleration.  The language has no "final"; a value other than 1 scales
    # the dynamics.
    unitAngularAcceleration = Parameter(1.0, unit="rad/s2",  # noqa: N815 - Modelica name
                                        description="Unit constant 1 rad/s2 (do not change)")
    unitTorque = Parameter(1.0, unit="N.m",  # noqa: N815 - Modelica name
                           description="Unit constant 1 N.m (do not change)")

    def equations(self):
        MU = friction_table(self, "mu_pos")
        mu0 = MU(0)
        peak2 = sp.Max(self.peak, 1 + self.eps0)
        tau0_max_low = self.eps0 * mu0 * self.cgeo * self.fn_max
        w_rel, sa = self.w_rel, self.sa
        pre_stuck = pre_boolean(self.stuck)
        start_forward = sp.Or(
            sp.And(pre_stuck, sp.Or(sa > self.tau0_max,
                                    sp.And(pre_boolean(self.startForward), sa > self.tau0),
                                    w_rel > self.w_small)),
            sp.And(is_initial(), w_rel > 0))
        return [
            Eq(self.u, self.f_normalized),
            Eq(self.free, self.u <= 0),
            Eq(self.fn, If(self.free, 0, self.fn_max * self.u)),
            Eq(self.tau0, mu0 * self.cgeo * self.fn),
            Eq(self.tau0_max, If(self.free, tau0_max_low, peak2 * self.tau0)),
            Eq(self.startForward, start_forward),
            Eq(self.locked, sp.And(pre_stuck, sp.Not(self.startForward))),
            Eq(self.mu, MU(w_rel)),
            Eq(self.a_rel, If(self.locked, 0, (sa - self.tau0) * self.unitAngularAcceleration / self.unitTorque)),
            Eq(self.tau, sp.Piecewise((sa, self.locked), (0, self.free),
                                      (self.mu * self.cgeo * self.fn, True))),
            Eq(self.stuck, sp.Or(self.locked, w_rel <= 0)),
            Eq(self.lossPower, If(self.stuck, 0, self.tau * w_rel)),
        ]


# --------------------------------------------------------------------------
# rotational <-> translational


class IdealGearR2T(PartialElementaryRotationalToTranslational):
    """Ideal gearbox from rotation to translation (Modelica.Mechanics.Rotational.Components.IdealGearR2T).

    Massless and lossless (a rack and pinion, a spindle):

    * ``flangeR.phi - phi_support = ratio*(flangeT.s - s_support)``
    * ``0 = ratio*flangeR.tau + flangeT.f``

    so the power ``flangeR.tau*w + flangeT.f*v`` (speeds relative to the
    supports) is zero.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.IdealGearR2T"

    ratio = Parameter(1.0, unit="rad/m", description="Transmission ratio (flange_a.phi/flange_b.s)")

    def equations(self):
        return [
            Eq(self.flangeR.phi - self.phi_support, self.ratio * (self.flangeT.s - self.s_support)),
            Eq(0, self.ratio * self.flangeR.tau + self.flangeT.f),
        ]


class IdealRollingWheel(PartialElementaryRotationalToTranslational):
    """Ideal wheel rolling without slip and without inertia (Modelica.Mechanics.Rotational.Components.IdealRollingWheel).

    * ``(flangeR.phi - phi_support)*radius = flangeT.s - s_support``
    * ``0 = radius*flangeT.f + flangeR.tau``
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.IdealRollingWheel"

    radius = Parameter(0.3, unit="m", description="Wheel radius")

    def equations(self):
        return [
            Eq((self.flangeR.phi - self.phi_support) * self.radius, self.flangeT.s - self.s_support),
            Eq(0, self.radius * self.flangeT.f + self.flangeR.tau),
        ]


# --------------------------------------------------------------------------
# backlash


#: Modelica.Constants.small: the least spring constant ElastoBacklash accepts.
_SMALL = 1.0e-60

#: Backlash below which ElastoBacklash(2) ignores the gap (constant bEps of the MSL): a zero
#: gap would put the equilibrium of the spring on the switching surface, an endless stream
#: of contact events.
BACKLASH_EPS = 1.0e-10

_C_HINT = ("c is the contact stiffness and must be > 0 (the MSL requires c > 0); for a gap "
           "without any contact force use no element at all")
_B_HINT = "b is the total backlash (the gap width, rad); it must be >= 0 (0: no backlash)"
_D_HINT = "d is the damping constant of the contact; it must be >= 0"


class _Backlash:
    """Parameters, checks and the shared characteristic of ElastoBacklash and ElastoBacklash2.

    ``phi_diff = phi_rel - phi_rel0``, ``bMax = b/2``, ``bMin = -b/2``.  At
    initialization the characteristic is the strictly increasing
    approximation the MSL uses there (so that initial values can be solved
    for through it):

    * ``tau_c = c*(phi_diff - bMax)`` if ``phi_diff > 1.5*bMax``,
      ``c*(phi_diff - bMin)`` if ``phi_diff < 1.5*bMin``, else ``(c/3)*phi_diff``
    * ``tau_d = d*w_rel``, ``tau = tau_c + tau_d``, ``lossPower = tau_d*w_rel``

    After initialization the spring torque is

    * ``tau_c = c*phi_diff`` if ``|b| <= bEps`` (1e-10 rad: no gap),
      ``c*(phi_diff - bMax)`` if ``phi_diff > bMax``,
      ``c*(phi_diff - bMin)`` if ``phi_diff < bMin``, else 0

    and ``tau_d = d*w_rel``; the subclass gives the contact torque and the loss.
    """

    c = Parameter(1.0e5, unit="N.m/rad", min=_SMALL, description="Spring constant (c > 0 required)")
    d = Parameter(0.0, unit="N.m.s/rad", min=0, description="Damping constant")
    b = Parameter(0.0, unit="rad", min=0, description="Total backlash")
    phi_rel0 = Parameter(0.0, unit="rad", description="Unstretched spring angle")
    tau_c = Variable(unit="N.m", description="Spring torque (protected)")
    tau_d = Variable(unit="N.m", description="Damping torque (protected)")
    phi_diff = Variable(unit="rad", description="phi_rel - phi_rel0 (protected)")

    def build(self) -> None:
        self.check_parameters()

    def check_parameters(self) -> None:
        """Raise ParameterError for c <= 0, b < 0 or d < 0 (numbers; expressions at flattening)."""
        check_min(self, "c", _SMALL, _C_HINT)
        check_min(self, "b", 0.0, _B_HINT)
        check_min(self, "d", 0.0, _D_HINT)

    def _gap(self):
        """(bMax, bMin, no_gap): the gap limits and the parameter condition |b| <= bEps."""
        b_max = self.b / 2
        return b_max, -b_max, sp.Abs(self.b) <= BACKLASH_EPS

    def _characteristic(self):
        """Equations common to both: phi_diff, tau_d and the two forms of tau_c.

        Returns the equations and ``(initializing, tau_c_initial)``: the
        subclass selects its own torque and loss with the same condition.
        """
        b_max, b_min, no_gap = self._gap()
        phi_diff, c = self.phi_diff, self.c
        initializing = is_initial()
        tau_c_initial = sp.Piecewise((c * (phi_diff - b_max), phi_diff > 1.5 * b_max),
                                     (c * (phi_diff - b_min), phi_diff < 1.5 * b_min),
                                     (c / 3 * phi_diff, True))
        tau_c_running = sp.Piecewise((c * phi_diff, no_gap),
                                     (c * (phi_diff - b_max), phi_diff > b_max),
                                     (c * (phi_diff - b_min), phi_diff < b_min),
                                     (0, True))
        equations = [
            Eq(self.phi_diff, self.phi_rel - self.phi_rel0),
            Eq(self.tau_c, If(initializing, tau_c_initial, tau_c_running)),
            Eq(self.tau_d, self.d * self.w_rel),
        ]
        return equations, initializing


class ElastoBacklash(_Backlash, PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Backlash in series with a spring and a damper in parallel (Modelica.Mechanics.Rotational.Components.ElastoBacklash).

    No torque inside the gap ``bMin <= phi_diff <= bMax`` (``phi_diff =
    phi_rel - phi_rel0``, ``bMax = -bMin = b/2``); outside it the spring
    ``tau_c`` (measured from the gap edge) and the damper ``tau_d = d*w_rel``
    act, limited so that the contact only pushes and the damping never
    exceeds the spring torque (the torque is continuous at the start of
    contact):

    * ``phi_diff > bMax``: ``tau = 0`` if ``tau_c + tau_d <= 0``, else
      ``tau_c + min(tau_c, tau_d)``; ``lossPower = min(tau_c, tau_d)*w_rel``
      (0 without contact force);
    * ``phi_diff < bMin``: ``tau = 0`` if ``tau_c + tau_d >= 0``, else
      ``tau_c + max(tau_c, tau_d)``; ``lossPower = max(tau_c, tau_d)*w_rel``
      (0 without contact force);
    * inside the gap ``tau = 0``, ``lossPower = 0``;
    * with ``|b| <= 1e-10`` rad the gap is ignored: ``tau = tau_c + tau_d``,
      ``lossPower = tau_d*w_rel`` (a SpringDamper).

    The gap edges ``phi_diff = bMax`` and ``phi_diff = bMin`` are events; the
    limiting of the contact torque is wrapped in ``smooth(0, noEvent(...))``
    as in the MSL and makes none.  The spring torque ``tau_c`` and the
    initialization form are those of the shared characteristic (see
    ``_Backlash``).  ``lossPower`` goes to the optional heat port.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.ElastoBacklash"

    def equations(self):
        equations, initializing = self._characteristic()
        b_max, b_min, no_gap = self._gap()
        tau_c, tau_d, w_rel, phi_diff = self.tau_c, self.tau_d, self.w_rel, self.phi_diff
        pushing_forward = tau_c + tau_d <= 0   # true: a forward contact would pull
        pushing_backward = tau_c + tau_d >= 0  # true: a backward contact would pull
        tau_running = sp.Piecewise(
            (tau_c + tau_d, no_gap),
            (noEvent(If(pushing_forward, 0, tau_c + sp.Min(tau_c, tau_d))), phi_diff > b_max),
            (noEvent(If(pushing_backward, 0, tau_c + sp.Max(tau_c, tau_d))), phi_diff < b_min),
            (0, True))
        loss_running = sp.Piecewise(
            (tau_d * w_rel, no_gap),
            (noEvent(If(pushing_forward, 0, sp.Min(tau_c, tau_d) * w_rel)), phi_diff > b_max),
            (noEvent(If(pushing_backward, 0, sp.Max(tau_c, tau_d) * w_rel)), phi_diff < b_min),
            (0, True))
        return equations + [
            Eq(self.tau, If(initializing, tau_c + tau_d, tau_running)),
            Eq(self.lossPower, If(initializing, tau_d * w_rel, loss_running)),
        ]


class ElastoBacklash2(_Backlash, PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Backlash in series with a spring and a damper; the torque may jump at contact (Modelica.Mechanics.Rotational.Components.ElastoBacklash2).

    Like :class:`ElastoBacklash`, but the contact torque is the plain
    ``tau_c + tau_d`` (set to 0 where it would pull), so it jumps by
    ``d*w_rel`` when contact starts:

    * ``phi_diff > bMax``: ``tau = 0`` if ``tau_c + tau_d <= 0``, else
      ``tau_c + tau_d``; ``lossPower`` 0 or ``tau_d*w_rel`` alike;
    * ``phi_diff < bMin``: ``tau = 0`` if ``tau_c + tau_d >= 0``, else
      ``tau_c + tau_d``; ``lossPower`` 0 or ``tau_d*w_rel`` alike;
    * inside the gap ``tau = 0``, ``lossPower = 0``;
    * with ``|b| <= 1e-10`` rad: ``tau = tau_c + tau_d``, ``lossPower = tau_d*w_rel``.

    Every relation, including the release condition ``tau_c + tau_d <= 0``,
    makes events (there is no ``noEvent`` in this model), so contact and
    release are event instants.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.ElastoBacklash2"

    def equations(self):
        equations, initializing = self._characteristic()
        b_max, b_min, no_gap = self._gap()
        tau_c, tau_d, w_rel, phi_diff = self.tau_c, self.tau_d, self.w_rel, self.phi_diff
        contact = tau_c + tau_d
        tau_running = sp.Piecewise(
            (contact, no_gap),
            (If(contact <= 0, 0, contact), phi_diff > b_max),
            (If(contact >= 0, 0, contact), phi_diff < b_min),
            (0, True))
        loss_running = sp.Piecewise(
            (tau_d * w_rel, no_gap),
            (If(contact <= 0, 0, tau_d * w_rel), phi_diff > b_max),
            (If(contact >= 0, 0, tau_d * w_rel), phi_diff < b_min),
            (0, True))
        return equations + [
            Eq(self.tau, If(initializing, contact, tau_running)),
            Eq(self.lossPower, If(initializing, tau_d * w_rel, loss_running)),
        ]


# --------------------------------------------------------------------------
# rigid elements, state definitions, initialization


class Disc(PartialTwoFlanges):
    """Massless rigid disc turning flange_b by a fixed angle against flange_a (Modelica.Mechanics.Rotational.Components.Disc).

    * ``flange_a.phi = phi - deltaPhi/2``, ``flange_b.phi = phi + deltaPhi/2``
    * ``0 = flange_a.tau + flange_b.tau``
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Disc"

    deltaPhi = Parameter(0.0, unit="rad",  # noqa: N815 - Modelica name
                         description="Fixed rotation of left flange with respect to right flange "
                                     "(= flange_b.phi - flange_a.phi)")
    phi = Variable(unit="rad", description="Absolute rotation angle of component")

    def equations(self):
        return [
            Eq(self.flange_a.phi, self.phi - self.deltaPhi / 2),
            Eq(self.flange_b.phi, self.phi + self.deltaPhi / 2),
            Eq(0, self.flange_a.tau + self.flange_b.tau),
        ]


class RelativeStates(PartialTwoFlanges):
    """Relative angle and speed between two flanges as preferred states (Modelica.Mechanics.Rotational.Components.RelativeStates).

    Transmits no torque (``flange_a.tau = flange_b.tau = 0``); it only
    declares ``phi_rel = flange_b.phi - flange_a.phi``, ``w_rel =
    der(phi_rel)``, ``a_rel = der(w_rel)`` with ``stateSelect`` (prefer) on
    ``phi_rel`` and ``w_rel``, so that the relative motion is integrated.
    ``phi_nominal`` (1 rad) scales the error control of ``phi_rel``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.RelativeStates"

    stateSelect = Parameter(StateSelect.prefer, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use the relative angle and relative speed as states")
    phi_nominal = Parameter(1.0, unit="rad", min=0,
                            description="Nominal value of the relative angle (used for scaling)")
    phi_rel = Variable(start=0.0, unit="rad",
                       nominal=lambda c: sp.Piecewise((c.phi_nominal, c.phi_nominal >= EPS), (1, True)),
                       state_select=lambda c: c.stateSelect,
                       description="Relative rotation angle used as state variable")
    w_rel = Variable(start=0.0, unit="rad/s", state_select=lambda c: c.stateSelect,
                     description="Relative angular velocity used as state variable")
    a_rel = Variable(start=0.0, unit="rad/s2", description="Relative angular acceleration")

    def equations(self):
        return [
            Eq(self.phi_rel, self.flange_b.phi - self.flange_a.phi),
            Eq(self.w_rel, der(self.phi_rel)),
            Eq(self.a_rel, der(self.w_rel)),
            Eq(self.flange_a.tau, 0),
            Eq(self.flange_b.tau, 0),
        ]


class InitializeFlange(Component):
    """Initialize a flange's angle, speed and acceleration from input signals (Modelica.Mechanics.Rotational.Components.InitializeFlange).

    Exerts no torque (``flange.tau = 0``).  ``phi_flange = flange.phi`` and
    ``w_flange = der(phi_flange)`` carry ``stateSelect``.  Each enabled input
    adds one initial equation:

    * ``use_phi_start``: ``flange.phi = phi_start``
    * ``use_w_start``: ``w_flange = w_start``
    * ``use_a_start``: ``a_flange = a_start``, with the protected
      ``a_flange = der(w_flange)`` (the MSL writes ``der(w) = a_start``
      inside a helper model; an initial equation on a variable keeps the
      initialization problem free of second derivatives)

    The MSL sets the flange angle to StateSelect.avoid inside its protected
    acceleration-setting part; that hint on a connector alias is not
    expressed here (``stateSelect`` on ``phi_flange`` and ``w_flange`` is).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.InitializeFlange"

    use_phi_start = Parameter(True, structural=True,
                              description="= true, if initial angle is defined by input phi_start, "
                                          "otherwise not initialized")
    use_w_start = Parameter(True, structural=True,
                            description="= true, if initial speed is defined by input w_start, "
                                        "otherwise not initialized")
    use_a_start = Parameter(True, structural=True,
                            description="= true, if initial angular acceleration is defined by input a_start, "
                                        "otherwise not initialized")
    stateSelect = Parameter(StateSelect.default, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use flange angle and speed as states")
    phi_start = RealInput(unit="rad", condition="use_phi_start", description="Initial angle of flange")
    w_start = RealInput(unit="rad/s", condition="use_w_start", description="Initial speed of flange")
    a_start = RealInput(unit="rad/s2", condition="use_a_start",
                        description="Initial angular acceleration of flange")
    flange = Flange_b(description="Flange that is initialized")
    phi_flange = Variable(unit="rad", state_select=lambda c: c.stateSelect, description="Flange angle")
    w_flange = Variable(unit="rad/s", state_select=lambda c: c.stateSelect, description="= der(phi_flange)")
    a_flange = Variable(unit="rad/s2", condition="use_a_start", description="= der(w_flange) (protected)")

    def equations(self):
        equations = [
            Eq(self.phi_flange, self.flange.phi),
            Eq(self.w_flange, der(self.phi_flange)),
            Eq(self.flange.tau, 0),
        ]
        if self.use_a_start:
            equations.append(Eq(self.a_flange, der(self.w_flange)))
        return equations

    def initial_equations(self):
        equations = []
        if self.use_phi_start:
            equations.append(Eq(self.flange.phi, self.phi_start))
        if self.use_w_start:
            equations.append(Eq(self.w_flange, self.w_start))
        if self.use_a_start:
            equations.append(Eq(self.a_flange, self.a_start))
        return equations


# --------------------------------------------------------------------------
# signal adaptors (for FMU export)


class TorqueToAngleAdaptor(Component):
    """Flange driven by an input torque; angle, speed and acceleration as outputs (Modelica.Mechanics.Rotational.Components.TorqueToAngleAdaptor).

    * ``phi = flange.phi``, ``flange.tau = tau``
    * ``w_internal = der(phi)`` if ``use_w``, else 0; ``a_internal =
      der(w_internal)`` if ``use_a``, else 0
    * the conditional outputs: ``w = w_internal``, ``a = a_internal``
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.TorqueToAngleAdaptor"

    use_w = Parameter(True, structural=True, description="= true, enable the output connector w (angular velocity)")
    use_a = Parameter(True, structural=True,
                      description="= true, enable the output connector a (angular acceleration)")
    flange = Flange_a(description="Flange")
    phi = RealOutput(unit="rad", description="Flange moves with angle phi due to torque tau")
    w = RealOutput(unit="rad/s", condition="use_w", description="Flange moves with speed w due to torque tau")
    a = RealOutput(unit="rad/s2", condition="use_a",
                   description="Flange moves with angular acceleration a due to torque tau")
    tau = RealInput(unit="N.m", description="Torque to drive the flange")
    w_internal = Variable(unit="rad/s", description="Needed to connect to conditional connector w (protected)")
    a_internal = Variable(unit="rad/s2", description="Needed to connect to conditional connector a (protected)")

    def equations(self):
        equations = [
            Eq(self.phi, self.flange.phi),
            Eq(self.w_internal, der(self.phi) if self.use_w else 0),
            Eq(self.a_internal, der(self.w_internal) if self.use_a else 0),
            Eq(self.flange.tau, self.tau),
        ]
        if self.use_w:
            equations.append(Eq(self.w, self.w_internal))
        if self.use_a:
            equations.append(Eq(self.a, self.a_internal))
        return equations


class AngleToTorqueAdaptor(Component):
    """Flange moved by input angle, speed and acceleration; the torque needed as output (Modelica.Mechanics.Rotational.Components.AngleToTorqueAdaptor).

    The flange follows the inputs (the MSL builds this from Sources.Move
    and a torque sensor): ``flange.phi`` is ``phi`` whose first derivative
    is taken as ``w`` and second as ``a`` (see :func:`acausal.prescribed`):

    * ``use_a``: ``flange.phi = prescribed(phi, w, a)``
    * ``use_w`` only: ``flange.phi = prescribed(phi, w)``
    * neither: ``flange.phi = phi`` (its derivatives are those of the input)

    A derivative beyond the given ones is that of the last input (``der(w)``
    with ``use_w`` only: ``differentiate_last``, as a Modelica tool
    differentiates the MSL's ``Move_w`` when an inertia needs the
    acceleration).

    and ``tau = -flange.tau``: the torque the flange needs.  The input ``w``
    exists if ``use_w`` or ``use_a``.  The inputs must be consistent
    (``w = der(phi)``, ``a = der(w)``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.AngleToTorqueAdaptor"

    use_w = Parameter(True, structural=True, description="= true, enable the input connector w (angular velocity)")
    use_a = Parameter(True, structural=True,
                      description="= true, enable the input connector a (angular acceleration)")
    flange = Flange_b(description="Flange")
    phi = RealInput(unit="rad", description="Angle to drive the flange")
    w = RealInput(unit="rad/s", condition=lambda c: c.use_w or c.use_a,
                  description="Speed to drive the flange (w=der(phi) required)")
    a = RealInput(unit="rad/s2", condition="use_a",
                  description="Angular acceleration to drive the flange (a = der(w) required)")
    tau = RealOutput(unit="N.m", description="Torque needed to drive the flange according to phi, w, a")

    def equations(self):
        if self.use_a:
            angle = prescribed(self.phi, self.w, self.a, name=f"{where(self)}.phi", differentiate_last=True)
        elif self.use_w:
            angle = prescribed(self.phi, self.w, name=f"{where(self)}.phi", differentiate_last=True)
        else:
            angle = self.phi
        return [Eq(self.flange.phi, angle), Eq(self.tau, -self.flange.tau)]


class GeneralTorqueToAngleAdaptor(FlowToPotentialAdaptor):
    """Torque in; angle, speed and acceleration out, generic form (Modelica.Mechanics.Rotational.Components.GeneralTorqueToAngleAdaptor).

    The flow-to-potential adaptor
    (:class:`acausal.components.adaptors.FlowToPotentialAdaptor`) on a
    rotational flange: ``y = flange.phi`` (potential = angle) and ``u =
    flange.tau`` (flow = torque), so ``flange.phi = p``, ``pder = der(p)``,
    ``pder2 = der(pder)`` and ``flange.tau = f``.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.GeneralTorqueToAngleAdaptor"

    flange = Flange_a(description="Flange")
    p = RealOutput(unit="rad", description="Output for potential (angle)")
    pder = RealOutput(unit="rad/s", condition="use_pder", description="Optional output for der(potential) (speed)")
    pder2 = RealOutput(unit="rad/s2", condition=lambda c: c.use_pder and c.use_pder2,
                       description="Optional output for der2(potential) (angular acceleration)")
    f = RealInput(unit="N.m", description="Input for flow (torque)")

    def equations(self):
        return [Eq(self.y, self.flange.phi), Eq(self.u, self.flange.tau)]


class GeneralAngleToTorqueAdaptor(PotentialToFlowAdaptor):
    """Angle, speed and acceleration in; torque out, generic form (Modelica.Mechanics.Rotational.Components.GeneralAngleToTorqueAdaptor).

    The potential-to-flow adaptor
    (:class:`acausal.components.adaptors.PotentialToFlowAdaptor`) on a
    rotational flange: ``y = flange.tau`` (flow = torque) and ``u =
    flange.phi`` (potential = angle), so ``f = -flange.tau`` and the
    flange follows ``p`` with the derivatives ``pder`` and ``pder2``.  A
    derivative of ``p`` beyond the inputs is that of the last input
    (``differentiate_last``: ``der(pder)`` without ``use_pder2``).
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.GeneralAngleToTorqueAdaptor"

    differentiate_last = True

    flange = Flange_b(description="Flange")
    p = RealInput(unit="rad", description="Input for potential (angle)")
    pder = RealInput(unit="rad/s", condition="use_pder", description="Optional input for der(potential) (speed)")
    pder2 = RealInput(unit="rad/s2", condition=lambda c: c.use_pder and c.use_pder2,
                      description="Optional input for der2(potential) (angular acceleration)")
    f = RealOutput(unit="N.m", description="Output for flow (torque)")

    def equations(self):
        return [Eq(self.y, self.flange.tau), Eq(self.u, self.flange.phi)]
