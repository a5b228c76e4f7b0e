"""The friction state machine and the friction tables, shared by both mechanical domains.

:func:`friction_state_machine` holds the equations of the MSL's
``PartialFriction`` (Rotational and Translational alike, and the variant of
Translational's ``MassWithStopAndFriction``); :class:`PartialFriction` is the
rotational partial model built on it.  The table-driven elements (Rotational
BearingFriction, Clutch, Brake, OneWayClutch; Translational SupportFriction
and Brake) check their characteristic with :func:`check_friction_table`,
evaluate it through :func:`friction_table` and mirror it for negative speeds
with :func:`table_signs`.
"""

from __future__ import annotations

import sympy as sp

from acausal.errors import ParameterError
from acausal.language import Boolean, Component, Eq, Integer, Parameter, Variable, pre
from acausal.tables import table_function, validate_table

from .checks import where
from .logic import is_initial, pre_boolean

__all__ = ["PartialFriction", "friction_state_machine", "Unknown", "Free", "Forward", "Stuck", "Backward",
           "TABLE_QUANTITIES", "check_friction_table", "friction_table", "table_signs"]

#: Values of ``mode``.
Unknown = 3  #: value of mode is not known
Free = 2  #: element is not active
Forward = 1  #: w_relfric > 0 (forward sliding)
Stuck = 0  #: w_relfric = 0 (forward sliding, locked or backward sliding starts)
Backward = -1  #: w_relfric < 0 (backward sliding)


class PartialFriction(Component):
    """Coulomb friction state machine (Modelica.Mechanics.Rotational.Interfaces.PartialFriction).

    The friction element is described by a path variable ``sa`` at the
    acceleration level, following Otter, Elmqvist and Mattsson (1999): while
    locked the constraint is on the relative acceleration (``a_relfric = 0``,
    the friction torque ``sa`` is whatever keeps it there), so the relative
    velocity stays a state in every mode and the equation structure never
    changes.  Sliding starts when ``sa`` exceeds the static limit
    ``tau0_max`` (and continues to "start" while it exceeds ``tau0``); the
    ``mode`` becomes Forward or Backward only once the relative velocity has
    the matching sign (the waiting phase).  The subclass defines
    ``w_relfric``, ``a_relfric``, ``tau0``, ``tau0_max`` and ``free`` by
    equations, plus its friction torque (``sa`` when ``locked``).

    ``sa`` is declared in N.m, the unit of the torques it is compared with
    and stands for.  Where it stands for an acceleration (the sliding and
    free branches of ``a_relfric``) it is multiplied by
    ``unitAngularAcceleration/unitTorque``, the MSL's two unit constants
    (both 1, so the numbers are those of the MSL, which declares ``sa``
    with unit "1" and multiplies it by the constants instead).

    The equations are those of MSL v4.1.0 (spec section 2.9, F1-F5), including
    the final ``sa - sign(w_relfric)*tau0_max`` branch of ``a_relfric``.  The
    one extension is ``K_locked``: in the locked branch this project uses
    ``a_relfric = -K_locked*w_relfric`` (a first-order pull of the drifting
    relative velocity back to zero); with the default ``K_locked = 0`` it is
    exactly the MSL equation ``a_relfric = 0``.

    Parameters
    ----------
    w_small : float, default 1e10 rad/s
        Relative angular velocity near zero if jumps due to a reinit of the
        velocity can occur; the large default disables it.
    K_locked : float, default 0 1/s
        Velocity feedback gain in the locked mode (project extension, not MSL).
    unitAngularAcceleration : float, default 1 rad/s2
        Unit constant (MSL ``constant unitAngularAcceleration``); do not change.
    unitTorque : float, default 1 N.m
        Unit constant (MSL ``constant unitTorque``); do not change.

    Notes
    -----
    ``mode`` takes the values of the module constants Unknown (3), Free (2),
    Forward (1), Stuck (0) and Backward (-1).  ``mode``, ``startForward`` and
    ``startBackward`` are fixed at their start values, so during
    initialization ``pre(mode) = Unknown`` and the element starts sliding only
    if ``w_relfric`` is non-zero.

    References
    ----------
    .. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid Modeling in
       Modelica based on the Synchronous Data Flow Principle", CACSD'99,
       Hawaii, August 1999.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Interfaces.PartialFriction"

    hints = {
        "mode": "elements that can lock the same relative motion (two friction elements, or a "
                "bearing and a brake, on one rigid shaft) leave the split of the holding torque "
                "undetermined when both are stuck; put a compliance (SpringDamper) between them "
                "or merge them into one element (MSL Rotational Users Guide, "
                "RequirementsForSimulationTool)",
        "event_iteration": "friction elements that lock the same motion can unlock each other in "
                           "turn; add a compliance between them",
        "chattering": "a friction element without inertia on either side switches between stuck "
                      "and sliding without time passing; give the shaft an inertia",
    }

    Unknown = Unknown
    Free = Free
    Forward = Forward
    Stuck = Stuck
    Backward = Backward

    w_small = Parameter(1.0e10, unit="rad/s",
                        description="Relative angular velocity near to zero if jumps due to a reinit(..) "
                                    "of the velocity can occur (set to low value only if such impulses "
                                    "can occur)")
    K_locked = Parameter(0.0, unit="1/s", min=0,  # noqa: N815 - project name
                         description="Velocity feedback gain while locked: a_relfric = -K_locked*w_relfric "
                                     "(0 = MSL behaviour)")
    # Unit constants (MSL: constant ... = 1): sa*unitAngularAcceleration/unitTorque is sa, a torque,
    # read as an acceleration.  The language has no "final"; a value other than 1 scales the dynamics.
    unitAngularAcceleration = Parameter(1.0, unit="rad/s2",  # noqa: N815 - Modelica name
                                        description="Unit constant 1 rad/s2 (do not change)")
    unitTorque = Parameter(1.0, unit="N.m",  # noqa: N815 - Modelica name
                           description="Unit constant 1 N.m (do not change)")

    # defined by the subclass
    w_relfric = Variable(unit="rad/s", description="Relative angular velocity between frictional surfaces")
    a_relfric = Variable(unit="rad/s2",
                         description="Relative angular acceleration between frictional surfaces")
    tau0 = Variable(unit="N.m", description="Friction torque for w=0 and forward sliding")
    tau0_max = Variable(unit="N.m", description="Maximum friction torque for w=0 and locked")
    free = Boolean(description="true, if frictional element is not active")

    # defined here
    sa = Variable(unit="N.m",
                  description="Path parameter of friction characteristic tau = f(a_relfric) (the friction "
                              "torque while locked)")
    startForward = Boolean(start=False, fixed=True,  # noqa: N815 - Modelica name
                           description="true, if w_rel=0 and start of forward sliding")
    startBackward = Boolean(start=False, fixed=True,  # noqa: N815 - Modelica name
                            description="true, if w_rel=0 and start of backward sliding")
    locked = Boolean(start=False, description="true, if w_rel=0 and not sliding")
    mode = Integer(start=Unknown, fixed=True, min=Backward, max=Unknown,
                   description="Mode of friction (-1 backward sliding, 0 stuck, 1 forward sliding, "
                               "2 inactive, 3 unknown)")

    def equations(self):
        return friction_state_machine(self, self.w_relfric, self.a_relfric, self.tau0, self.tau0_max,
                                      self.w_small, locked_acceleration=-self.K_locked * self.w_relfric,
                                      acceleration_per_force=self.unitAngularAcceleration / self.unitTorque)


def friction_state_machine(element, v_relfric, a_relfric, f0, f0_max, v_small, locked_acceleration=0, *,
                           acceleration_per_force, forward_allowed=sp.true, backward_allowed=sp.true,
                           sign_fallback=True):
    """The five equations F1-F5 of the MSL friction state machine, for either domain.

    Rotational and Translational ``PartialFriction`` share these equations
    (only the names of the relative motion and the limits differ), so both
    build them here from the element's ``sa``, ``startForward``,
    ``startBackward``, ``locked``, ``free`` and ``mode``.  Translational
    ``MassWithStopAndFriction`` (its ``PartialFrictionWithStop``) uses them
    too, with the conditions that keep a body from sliding into a stop.

    Parameters
    ----------
    element : Component
        The friction element, declaring sa, startForward, startBackward,
        locked, free and mode.
    v_relfric, a_relfric : sympy expressions
        Relative velocity and acceleration between the frictional surfaces.
    f0, f0_max : sympy expressions
        Friction force (torque) at zero speed when sliding, and its static limit.
    v_small : sympy expression
        Relative speed above which a reversal of sliding is accepted directly.
    locked_acceleration : sympy expression, default 0
        ``a_relfric`` while locked (the MSL has 0; the rotational elements'
        ``K_locked`` extension uses ``-K_locked*w_relfric``).
    acceleration_per_force : sympy expression
        The element's unit constants, acceleration over force (torque):
        ``unitAcceleration/unitForce`` or
        ``unitAngularAcceleration/unitTorque``, equal to 1.  ``sa`` has the
        unit of ``f0``; the other branches of ``a_relfric`` are multiplied
        by this to make them accelerations.
    forward_allowed, backward_allowed : sympy Boolean, default true
        Conditions for sliding forward (backward): sliding from Stuck starts,
        and the mode is Forward (Backward), only while they hold
        (``PartialFrictionWithStop``: the body is not at its right, left stop).
    sign_fallback : bool, default True
        Whether ``a_relfric`` ends with the MSL PartialFriction's branches
        ``sa + f0_max`` if ``pre(mode) == Backward``, else ``sa -
        sign(v_relfric)*f0_max`` (each times ``acceleration_per_force``);
        False: it ends with ``sa + f0_max`` for every remaining case
        (``PartialFrictionWithStop``, where not locked and not free implies
        one of the cases before it).

    Returns
    -------
    list of Eq
        startForward (F1), startBackward (F2), locked (F3), a_relfric (F4), mode (F5).
    """
    sa, w = element.sa, v_relfric
    pre_mode = pre(element.mode)
    was = {value: sp.Eq(pre_mode, value) for value in (Stuck, Forward, Backward, Free)}

    start_forward = sp.Or(
        sp.And(was[Stuck], forward_allowed,
               sp.Or(sa > f0_max, sp.And(pre_boolean(element.startForward), sa > f0))),
        sp.And(was[Backward], w > v_small),
        sp.And(is_initial(), w > 0))
    start_backward = sp.Or(
        sp.And(was[Stuck], backward_allowed,
               sp.Or(sa < -f0_max, sp.And(pre_boolean(element.startBackward), sa < -f0))),
        sp.And(was[Forward], w < -v_small),
        sp.And(is_initial(), w < 0))
    locked = sp.And(sp.Not(element.free),
                    sp.Not(sp.Or(was[Forward], element.startForward, was[Backward], element.startBackward)))
    # sa and f0_max are forces (torques); the unit constants turn them into accelerations
    # (they are 1: the generated arithmetic multiplies and divides by 1.0, which is exact).
    per_force = acceleration_per_force
    if sign_fallback:
        ending = [((sa + f0_max) * per_force, was[Backward]), ((sa - sp.sign(w) * f0_max) * per_force, True)]
    else:
        ending = [((sa + f0_max) * per_force, True)]
    acceleration = sp.Piecewise(
        (locked_acceleration, element.locked),
        (sa * per_force, element.free),
        ((sa - f0_max) * per_force, element.startForward),
        ((sa + f0_max) * per_force, element.startBackward),
        ((sa - f0_max) * per_force, was[Forward]),
        *ending)
    mode = sp.Piecewise(
        (Free, element.free),
        (Forward, sp.And(sp.Or(was[Forward], was[Free], element.startForward), w > 0, forward_allowed)),
        (Backward, sp.And(sp.Or(was[Backward], was[Free], element.startBackward), w < 0, backward_allowed)),
        (Stuck, True))
    return [
        Eq(element.startForward, start_forward),   # F1
        Eq(element.startBackward, start_backward),  # F2
        Eq(element.locked, locked),                 # F3
        Eq(a_relfric, acceleration),                # F4
        Eq(element.mode, mode),                     # F5
    ]


# --------------------------------------------------------------------------
# friction tables (CombiTable1D characteristics given for relative speeds >= 0)


#: What the second column of a friction table holds, by the MSL's parameter names (for messages).
TABLE_QUANTITIES = {"tau_pos": "friction torque", "f_pos": "friction force", "mu_pos": "friction coefficient"}


def check_friction_table(component: Component, name: str, *, speed: str = "w", unit: str = "rad/s") -> None:
    """Raise ParameterError unless table parameter ``name`` is a valid friction characteristic.

    A valid CombiTable1D table (see :func:`acausal.tables.validate_table`)
    whose first column, the relative speed, starts at ``speed >= 0`` and
    whose second column (a friction torque, force or coefficient, see
    :data:`TABLE_QUANTITIES`) is ``>= 0``.

    Parameters
    ----------
    component : Component
        The friction element; the table is its attribute ``name``.
    name : str
        The table parameter (``tau_pos``, ``f_pos``, ``mu_pos``).
    speed, unit : str
        Name and unit of the relative speed in the first column, for the
        messages (``"w"``, ``"rad/s"`` rotational; ``"v"``, ``"m/s"``
        translational).
    """
    path = f"{where(component)}.{name}"
    quantity = TABLE_QUANTITIES.get(name, "friction characteristic")
    data = validate_table(getattr(component, name), path, value_min=0.0,
                          value_hint=f"a {quantity} must not be negative: it would drive the motion "
                                     f"it opposes (the MSL assumes {name}[:, 2] >= 0; 0 means no "
                                     f"friction at that speed)")
    if data[0, 0] < 0:
        raise ParameterError(f"table {path}: the first column (relative speed {speed} >= 0, in {unit}) "
                             f"starts at {data[0, 0]:g} < 0",
                             hint=f"the characteristic is given for {speed} >= 0 and mirrored for {speed} < 0; "
                                  f"start the table at {speed} = 0")


def friction_table(component: Component, name: str) -> type[sp.Function]:
    """The table function of the structural table parameter ``name``, named after the component path."""
    return table_function(f"{component.path}.{name}" if component.path else name, getattr(component, name))


def table_signs(component: Component, clutch_quirk: bool = False) -> tuple[sp.Expr, sp.Expr]:
    """``(s1, s2)``: the signs of the abscissa and of the table value (the MSL's table_signs).

    A friction table is given for relative speeds >= 0; the elements
    evaluate ``s2*table(s1*speed)``: ``(+1, +1)`` when forward sliding
    starts or goes on, ``(-1, -1)`` otherwise.  ``clutch_quirk``: at the start
    of backward sliding the MSL's Clutch evaluates the table at ``+speed``
    (``s1 = +1``).
    """
    forward = sp.Eq(pre(component.mode), Forward)
    s1 = sp.Piecewise((1, component.startForward), (1 if clutch_quirk else -1, component.startBackward),
                      (1, forward), (-1, True))
    s2 = sp.Piecewise((1, component.startForward), (-1, component.startBackward), (1, forward), (-1, True))
    return s1, s2
