"""Translational friction elements and a sliding mass with hard stops.

Modelica.Mechanics.Translational.Components: SupportFriction, Brake and
MassWithStopAndFriction (with its base PartialFrictionWithStop).

SupportFriction and Brake use the friction state machine shared with the
rotational elements (:class:`acausal.components.translational.PartialFriction`,
spec section 2.9, F1-F5) and the friction-table helpers of
:mod:`acausal.components.friction` (:func:`check_friction_table`,
:func:`friction_table`, :func:`table_signs`).  MassWithStopAndFriction
uses the same state machine with conditions that keep the mass from
sliding towards a stop it is resting against (the MSL's
PartialFrictionWithStop), plus the impacts at the stops (a ``when`` with
``reinit`` of position and velocity).

As in the rotational friction elements, the MSL 4.1.0 parameter
``smoothness`` is not offered: the tables are always interpolated with
``Smoothness.LinearSegments`` (the MSL default, the only kind the examples
use) and extrapolated through the last two points.
"""

from __future__ import annotations

import sympy as sp

from acausal.errors import ParameterError
from acausal.hybrid import Assert, When, reinit
from acausal.language import (
    Eq,
    If,
    Integer,
    Parameter,
    RealInput,
    StateSelect,
    Variable,
    der,
    initial,
    pre,
)
from acausal.components.checks import check_min, parameter_number, where
from acausal.components.friction import (
    Forward,
    check_friction_table,
    friction_table,
    table_signs,
)
from acausal.components.thermal import PartialElementaryConditionalHeatPortWithoutT
from acausal.components.translational import (
    PartialElementaryTwoFlangesAndSupport2,
    PartialFriction,
    PartialRigid,
)

__all__ = [
    "SupportFriction",
    "Brake",
    "PartialFrictionWithStop",
    "MassWithStopAndFriction",
]

_PEAK_HINT = "peak = f0_max/f0 (static over sliding friction force at v = 0) must be >= 1"


class _HousingFriction:
    """Friction between a rigid rod (flange_a = flange_b) and its housing.

    Shared by SupportFriction and Brake: the rod position relative to the
    support is the friction element's relative motion, and ``f`` is the
    force the element absorbs from its two flanges.
    """

    s = Variable(unit="m", description="Position of flange_a and flange_b relative to the support")
    f = Variable(unit="N", description="Friction force absorbed from the flanges")
    v = Variable(unit="m/s", description="Absolute velocity of flange_a and flange_b")
    a = Variable(unit="m/s2", description="Absolute acceleration of flange_a and flange_b")

    def equations(self):
        return [
            Eq(self.s, self.s_a),
            Eq(self.s, self.s_b),
            Eq(self.v, der(self.s)),
            Eq(self.a, der(self.v)),
            Eq(self.v_relfric, self.v),
            Eq(self.a_relfric, self.a),
            Eq(self.flange_a.f + self.flange_b.f - self.f, 0),
            Eq(self.lossPower, self.f * self.v_relfric),
        ]


class SupportFriction(_HousingFriction, PartialElementaryTwoFlangesAndSupport2,
                      PartialElementaryConditionalHeatPortWithoutT, PartialFriction):
    """Coulomb friction in the support (Modelica.Mechanics.Translational.Components.SupportFriction).

    A friction force between the rigidly connected flanges and the housing.
    With ``F(v)`` the table ``f_pos`` (rows ``[v, f]`` for v >= 0, linear
    interpolation, extrapolation through the last two rows, mirrored for
    v < 0) the equations are::

        s = flange_a.s - s_support,   flange_b.s = flange_a.s
        v = der(s),   a = der(v),   v_relfric = v,   a_relfric = a
        flange_a.f + flange_b.f - f = 0
        f0 = F(0),   f0_max = peak*f0,   free = false
        (s1, s2) = (+1, +1) if startForward, (-1, -1) if startBackward,
                   (+1, +1) if pre(mode) == Forward, else (-1, -1)
        f = sa if locked else s2*F(s1*v)
        lossPower = f*v_relfric

    plus the stuck/sliding logic of
    :class:`acausal.components.translational.PartialFriction`.  The element
    breaks away when the holding force exceeds ``peak*F(0)``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.SupportFriction"

    f_pos = Parameter([[0.0, 1.0]], structural=True, unit="N",
                      description="Positive sliding friction characteristic [N] as function of v [m/s] (v>=0)")
    peak = Parameter(1.0, min=1, description="Peak for maximum friction force at v==0 (f0_max = peak*f_pos[1,2])")

    def build(self) -> None:
        check_friction_table(self, "f_pos", speed="v", unit="m/s")
        check_min(self, "peak", 1.0, _PEAK_HINT)

    def equations(self):
        F = friction_table(self, "f_pos")
        s1, s2 = table_signs(self)
        return [
            Eq(self.f0, F(0)),
            Eq(self.f0_max, self.peak * self.f0),
            Eq(self.free, sp.false),
            Eq(self.f, If(self.locked, self.sa, s2 * F(s1 * self.v))),
        ]


class Brake(_HousingFriction, PartialElementaryTwoFlangesAndSupport2, PartialElementaryConditionalHeatPortWithoutT,
            PartialFriction):
    """Brake based on Coulomb friction (Modelica.Mechanics.Translational.Components.Brake).

    A friction force, controlled by a normal force, between the rigidly
    connected flanges and the housing.  With ``MU(v)`` the table ``mu_pos``
    (rows ``[v, mu]`` for v >= 0, linear interpolation, extrapolation through
    the last two rows, mirrored for v < 0)::

        s = s_a = s_b (the flanges' position relative to the support)
        v = der(s),   a = der(v),   v_relfric = v,   a_relfric = a
        flange_a.f + flange_b.f - f = 0
        fn = fn_max*f_normalized,   free = (fn <= 0)
        f0 = MU(0)*cgeo*fn,   f0_max = peak*f0
        mu = s2*MU(s1*v)          (s1, s2 as in SupportFriction)
        f = sa if locked, 0 if free, else mu*cgeo*fn
        lossPower = f*v_relfric

    plus the stuck/sliding logic of
    :class:`acausal.components.translational.PartialFriction`.  The brake is
    free (mode Free) while the normal force is not positive.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Brake"

    mu_pos = Parameter([[0.0, 0.5]], structural=True,
                       description="Positive sliding friction coefficient [-] as function of v [m/s] (v>=0)")
    peak = Parameter(1.0, min=1, description="Peak for maximum value of mu at v==0 (mu0_max = peak*mu_pos[1,2])")
    cgeo = Parameter(1.0, min=0, description="Geometry constant containing friction distribution assumption")
    fn_max = Parameter(1.0, unit="N", min=0, description="Maximum normal force")
    f_normalized = RealInput(unit="1",
                             description="Normalized force signal 0..1 (normal force = fn_max*f_normalized; "
                                         "brake is active if > 0)")
    mu = Variable(unit="1", description="Friction coefficient")
    fn = Variable(unit="N", description="Normal force (=fn_max*f_normalized)")

    def build(self) -> None:
        check_friction_table(self, "mu_pos", speed="v", unit="m/s")
        check_min(self, "peak", 1.0, _PEAK_HINT)
        check_min(self, "fn_max", 0.0, "fn_max is the maximum normal force; it must be >= 0")
        check_min(self, "cgeo", 0.0, "cgeo scales the normal force into a friction force; it must be >= 0")

    def equations(self):
        MU = friction_table(self, "mu_pos")
        s1, s2 = table_signs(self)
        return [
            Eq(self.fn, self.fn_max * self.f_normalized),
            Eq(self.free, self.fn <= 0),
            Eq(self.f0, MU(0) * self.cgeo * self.fn),
            Eq(self.f0_max, self.peak * self.f0),
            Eq(self.mu, s2 * MU(s1 * self.v)),
            Eq(self.f, sp.Piecewise((self.sa, self.locked), (0, self.free),
                                    (self.mu * self.cgeo * self.fn, True))),
        ]


class PartialFrictionWithStop(PartialRigid, PartialFriction):
    """Coulomb friction of a rigid body between two hard stops (protected
    Modelica.Mechanics.Translational.Components.MassWithStopAndFriction.PartialFrictionWithStop).

    The friction state machine of
    :class:`acausal.components.translational.PartialFriction` (Otter,
    Elmqvist and Mattsson 1999) with one change: the body cannot start or go
    on sliding into a stop it touches
    (:func:`acausal.components.friction.friction_state_machine` with
    ``forward_allowed = s < s_right``, ``backward_allowed = s > s_left`` and
    no ``sign()`` fallback in ``a_relfric``).  With ``s_right = smax - L/2``
    and ``s_left = smin + L/2`` (the centre positions at which the right or
    left end of the body is at its stop)::

        startForward  = pre(mode) == Stuck and s < s_right
                            and (sa > f0_max or pre(startForward) and sa > f0)
                        or pre(mode) == Backward and v_relfric > v_small
                        or initial() and v_relfric > 0
        startBackward = pre(mode) == Stuck and s > s_left
                            and (sa < -f0_max or pre(startBackward) and sa < -f0)
                        or pre(mode) == Forward and v_relfric < -v_small
                        or initial() and v_relfric < 0
        locked = not free and not (pre(mode) == Forward or startForward
                                   or pre(mode) == Backward or startBackward)
        a_relfric = 0 if locked, else u times: sa if free, sa - f0_max if startForward,
                    sa + f0_max if startBackward, sa - f0_max if pre(mode) == Forward,
                    else sa + f0_max
        mode = Free if free,
               Forward if (pre(mode) in (Forward, Free) or startForward)
                          and v_relfric > 0 and s < s_right,
               Backward if (pre(mode) in (Backward, Free) or startBackward)
                           and v_relfric < 0 and s > s_left,
               else Stuck

    Here ``sa`` is a force (N) and ``u = unitAcceleration/unitForce`` is the
    MSL's pair of unit constants (both 1) that reads it as an acceleration.
    The subclass defines ``v_relfric``, ``a_relfric``, ``f`` (the friction
    force, ``sa`` while locked), ``f0``, ``f0_max`` and ``free``.  The
    centre position ``s`` is always a state (``StateSelect.always``), since
    the subclass reinitializes it at the stops.

    References
    ----------
    .. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid Modeling in
       Modelica based on the Synchronous Data Flow Principle", CACSD'99,
       Hawaii, August 1999.
    """

    smax = Parameter(25.0, unit="m", description="Right stop for (right end of) sliding mass")
    smin = Parameter(-25.0, unit="m", description="Left stop for (left end of) sliding mass")

    s = Variable(start=0.0, unit="m", state_select=StateSelect.always,
                 description="Absolute position of center of component (s = flange_a.s + L/2 = flange_b.s - L/2)")
    # defined by the subclass, besides those of PartialFriction
    f = Variable(unit="N", description="Friction force (positive, if directed in opposite direction of v_rel)")

    def state_machine_options(self) -> dict:
        return dict(forward_allowed=self.s < self.smax - self.L / 2,
                    backward_allowed=self.s > self.smin + self.L / 2,
                    sign_fallback=False)


class MassWithStopAndFriction(PartialFrictionWithStop, PartialElementaryConditionalHeatPortWithoutT):
    """Sliding mass with hard stops and Stribeck friction
    (Modelica.Mechanics.Translational.Components.MassWithStopAndFriction).

    A rigid body of mass ``m`` and length ``L`` (centre ``s``) slides on a
    fixed surface between a left stop ``smin`` and a right stop ``smax``
    (its ends, ``s -/+ L/2``, cannot pass them).  While sliding forward the
    friction force is the Stribeck-like characteristic (Beater 1999)::

        f = F_prop*v + F_Coulomb + F_Stribeck*exp(-fexp*|v|)

    (mirrored for backward sliding); at the start of sliding it is evaluated
    at v = 0 (``F_prop*v +/- (F_Coulomb + F_Stribeck)``).  The equations::

        f0 = F_Coulomb + F_Stribeck,   f0_max = 1.001*f0
        free = f0 <= 0 and F_prop <= 0 and smin + L/2 < s < smax - L/2
        v = der(s),   a = der(v),   v_relfric = v,   a_relfric = a
        m*a = flange_a.f + flange_b.f - f
        f = sa if locked, 0 if free, else the characteristic above
        lossPower = f*v_relfric
        stopped = -1 if s <= smin + L/2, +1 if s >= smax - L/2, else 0
        when stopped != 0:
            reinit(s, smin + L/2 if stopped < 0 else smax - L/2);  reinit(v, 0)

    plus the state machine of :class:`PartialFrictionWithStop`.  The impact
    at a stop is perfectly plastic: position and velocity are reset, and the
    mass then rests against the stop (mode Stuck, ``a = 0``, ``f = sa``
    takes the contact force too) until a force pulls it away from the stop
    by more than ``f0_max``.  At initialization the body must lie between
    the stops, or touch one with a velocity pointing away from it; the
    reset hides the impulsive contact force, so ``lossPower`` misses the
    kinetic energy lost at an impact.  ``s`` and ``v`` must be states
    (they are reinitialized): do not connect the body rigidly to another mass.

    References
    ----------
    .. [1] P. Beater, "Entwurf hydraulischer Maschinen", Springer, Berlin,
       1999, doi:10.1007/978-3-642-58395-7.
    .. [2] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid Modeling in
       Modelica based on the Synchronous Data Flow Principle", CACSD'99,
       Hawaii, August 1999.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.MassWithStopAndFriction"

    v = Variable(start=0.0, unit="m/s", state_select=StateSelect.always,
                 description="Absolute velocity of flange_a and flange_b")
    a = Variable(start=0.0, unit="m/s2", description="Absolute acceleration of flange_a and flange_b")
    m = Parameter(1.0, unit="kg", min=0, description="Mass")
    F_prop = Parameter(1.0, unit="N.s/m", min=0, description="Velocity dependent friction")
    F_Coulomb = Parameter(5.0, unit="N", description="Constant friction: Coulomb force")
    F_Stribeck = Parameter(10.0, unit="N", description="Stribeck effect")
    fexp = Parameter(2.0, unit="s/m", min=0, description="Exponential decay")
    stopped = Integer(description="Mode of stop (-1: hard stop at flange_a, 0: no stop, +1: hard stop at flange_b)")

    def build(self) -> None:
        smin, smax, length = (parameter_number(self, name) for name in ("smin", "smax", "L"))
        if None not in (smin, smax, length) and smax - smin < length:
            raise ParameterError(
                f"{where(self)}: the stops smin = {smin:g} m and smax = {smax:g} m are closer than the "
                f"length L = {length:g} m of the sliding mass",
                hint="the ends of the mass (s -/+ L/2) must fit between the stops: smax - smin >= L")

    def equations(self):
        s, v, L = self.s, self.v, self.L
        s_left, s_right = self.smin + L / 2, self.smax - L / 2
        decay = sp.exp(-self.fexp * sp.Abs(v))
        sliding_force = sp.Piecewise(
            (self.F_prop * v + self.F_Coulomb + self.F_Stribeck, self.startForward),
            (self.F_prop * v - self.F_Coulomb - self.F_Stribeck, self.startBackward),
            (self.F_prop * v + self.F_Coulomb + self.F_Stribeck * decay, sp.Eq(pre(self.mode), Forward)),
            (self.F_prop * v - self.F_Coulomb - self.F_Stribeck * decay, True))
        return [
            Eq(self.f0, self.F_Coulomb + self.F_Stribeck),
            Eq(self.f0_max, self.f0 * 1.001),
            Eq(self.free, sp.And(self.f0 <= 0, self.F_prop <= 0, s > s_left, s < s_right)),
            Eq(self.v, der(s)),
            Eq(self.a, der(v)),
            Eq(self.v_relfric, v),
            Eq(self.a_relfric, self.a),
            Eq(0, self.flange_a.f + self.flange_b.f - self.f - self.m * self.a),
            Eq(self.f, sp.Piecewise((self.sa, self.locked), (0, self.free), (sliding_force, True))),
            Eq(self.lossPower, self.f * self.v_relfric),
            When(initial(),
                 Assert(sp.Or(s > s_left, sp.And(s >= s_left, v >= 0)),
                        f"Error in initialization of hard stop {where(self)}: (s - L/2) must be >= smin"),
                 Assert(sp.Or(s < s_right, sp.And(s <= s_right, v <= 0)),
                        f"Error in initialization of hard stop {where(self)}: (s + L/2) must be <= smax")),
            Eq(self.stopped, sp.Piecewise((-1, s <= s_left), (1, s >= s_right), (0, True))),
            When(sp.Ne(self.stopped, 0),
                 reinit(s, If(self.stopped < 0, s_left, s_right)),
                 reinit(v, 0)),
        ]
