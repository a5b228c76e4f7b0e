"""Rotational components (Modelica.Mechanics.Rotational.Components)."""

from __future__ import annotations

import numbers

import sympy as sp

from acausal.errors import ParameterError
from acausal.language import (
    Boolean,
    Component,
    Eq,
    If,
    Parameter,
    RealInput,
    StateSelect,
    Variable,
    der,
    pre,
)
from acausal.tables import table_function, validate_table
from acausal.components.friction import Forward, PartialFriction
from acausal.components.logic import is_initial, pre_boolean
from acausal.components.rotational import (
    Flange_a,
    Flange_b,
    PartialCompliant,
    PartialCompliantWithRelativeStates,
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
]


# --------------------------------------------------------------------------
# helpers for the table-driven friction elements


def _where(component: Component) -> str:
    return component.path or type(component).__name__


#: What the second column of each friction table holds (for the error hint).
_TABLE_QUANTITY = {"tau_pos": "friction torque", "mu_pos": "friction coefficient"}


def _check_table(component: Component, name: str) -> None:
    """tau_pos/mu_pos: a valid CombiTable1D table whose first column (w) starts at w >= 0
    and whose second column (the friction torque or coefficient) is >= 0."""
    where = f"{_where(component)}.{name}"
    quantity = _TABLE_QUANTITY.get(name, "friction characteristic")
    data = validate_table(getattr(component, name), where, value_min=0.0,
                          value_hint=f"a {quantity} must not be negative: it would drive the motion "
                                     f"it opposes (the MSL assumes {name}[:, 2] >= 0; 0 means no "
                                     f"friction at that speed)")
    if data[0, 0] < 0:
        raise ParameterError(f"table {where}: the first column (relative speed w >= 0) starts at "
                             f"{data[0, 0]:g} < 0",
                             hint="the characteristic is given for w >= 0 and mirrored for w < 0; "
                                  "start the table at w = 0")


def _check_min(component: Component, name: str, minimum: float, hint: str) -> None:
    """A numeric parameter bound must be >= minimum (expressions are checked at flattening)."""
    value = component.parameter_binding(name)
    if isinstance(value, sp.Basic):
        if not value.is_number:
            return
        value = float(value)
    if isinstance(value, numbers.Real) and value < minimum:
        raise ParameterError(f"{_where(component)}.{name} = {value:g} is below its minimum {minimum:g}",
                             hint=hint)


def _table(component: Component, name: str) -> type[sp.Function]:
    """The table function of a structural table parameter, named after the component path."""
    return table_function(f"{component.path}.{name}" if component.path else name, getattr(component, name))


_PEAK_HINT = "peak = tau0_max/tau0 (static over sliding friction at w = 0) must be >= 1"


class _TableFriction:
    """Parameter checks shared by the table-driven friction elements."""

    _table_name = "mu_pos"

    def build(self) -> None:
        self.check_parameters()

    def check_parameters(self) -> None:
        """Raise ParameterError for an invalid friction table, peak < 1 or fn_max < 0."""
        _check_table(self, self._table_name)
        _check_min(self, "peak", 1.0, _PEAK_HINT)
        if "fn_max" in self.declarations():
            _check_min(self, "fn_max", 0.0, "fn_max is the maximum normal force; it must be >= 0")


def _signs(component, clutch_quirk: bool = False):
    """(s1, s2): the signs of the abscissa and of the table value (MSL table_signs)."""
    forward = sp.Eq(pre(component.mode), Forward)
    s1 = sp.Piecewise((1, component.startForward), (1 if clutch_quirk else -1, component.startBackward),
                      (1, forward), (-1, True))
    s2 = sp.Piecewise((1, component.startForward), (-1, component.startBackward), (1, forward), (-1, True))
    return s1, s2


class _NormalForceFriction(_TableFriction):
    """The friction law Clutch and Brake share: a normal force times a friction coefficient.

    ``fn = fn_max*f_normalized``; free when ``fn <= 0``; sliding torque
    ``mu*cgeo*fn`` with ``mu`` from the table ``mu_pos`` (mirrored by the
    signs of :func:`_signs`); static limit ``tau0_max = peak*mu_pos(0)*cgeo*fn``.
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
        MU = _table(self, "mu_pos")
        s1, s2 = _signs(self, clutch_quirk=self._clutch_quirk)
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

    phi0 = Parameter(0.0, unit="rad", description="Fixed offset angle of housing")
    flange = Flange_b(description="Flange fixed in housing at a given angle")

    def equations(self):
        return [Eq(self.flange.phi, self.phi0)]


class Spring(PartialCompliant):
    """Linear 1D rotational spring (Modelica.Mechanics.Rotational.Components.Spring).

    ``tau = c*(phi_rel - phi_rel0)``.
    """

    c = Parameter(1.0e5, unit="N.m/rad", min=0, description="Spring constant")
    phi_rel0 = Parameter(0.0, unit="rad", description="Unstretched spring angle")

    def equations(self):
        return [Eq(self.tau, self.c * (self.phi_rel - self.phi_rel0))]


class Damper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D rotational damper (Modelica.Mechanics.Rotational.Components.Damper).

    ``tau = d*w_rel``; the dissipated power ``lossPower = tau*w_rel`` goes to
    the optional heat port.
    """

    d = Parameter(0.0, unit="N.m.s/rad", min=0, description="Damping constant")

    def equations(self):
        return [Eq(self.tau, self.d * self.w_rel), Eq(self.lossPower, self.tau * self.w_rel)]


class SpringDamper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D rotational spring and damper in parallel (Modelica.Mechanics.Rotational.Components.SpringDamper).

    ``tau = c*(phi_rel - phi_rel0) + d*w_rel``; only the damper part
    dissipates (``lossPower = tau_d*w_rel``).
    """

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

    _table_name = "tau_pos"

    tau_pos = Parameter([[0.0, 1.0]], structural=True, unit="N.m",
                        description="[w,tau] positive sliding friction characteristic (w>=0)")
    peak = Parameter(1.0, min=1,
                     description="Peak for maximum friction torque at w==0 (tau0_max = peak*tau_pos[1,2])")

    def equations(self):
        T = _table(self, "tau_pos")
        s1, s2 = _signs(self)
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


class OneWayClutch(_TableFriction, PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Parallel connection of a freewheel and a clutch (Modelica.Mechanics.Rotational.Components.OneWayClutch).

    The freewheel blocks ``w_rel < 0``; it lets go when the transmitted torque
    ``sa`` exceeds ``tau0_max`` (``peak2*mu_pos(0)*cgeo*fn`` when engaged, the
    tiny ``tau0_max_low = 1e-4*mu_pos(0)*cgeo*fn_max`` when disengaged).  The
    clutch part transmits ``mu_pos(w_rel)*cgeo*fn`` while sliding.  It has its
    own stuck/sliding logic (``startForward``, ``locked``, ``stuck``), not
    PartialFriction; initial values must satisfy ``w_rel >= 0``.
    """

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
    sa = Variable(unit="1",
                  description="Path parameter of tau = f(a_rel) friction characteristic (protected)")

    def equations(self):
        MU = _table(self, "mu_pos")
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
            Eq(self.a_rel, If(self.locked, 0, sa - self.tau0)),
            Eq(self.tau, sp.Piecewise((sa, self.locked), (0, self.free),
                                      (self.mu * self.cgeo * self.fn, True))),
            Eq(self.stuck, sp.Or(self.locked, w_rel <= 0)),
            Eq(self.lossPower, If(self.stuck, 0, self.tau * w_rel)),
        ]
