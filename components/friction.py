"""The friction state machine shared by BearingFriction, Brake and Clutch."""

from __future__ import annotations

import sympy as sp

from acausal.language import Boolean, Component, Eq, Integer, Parameter, Variable, pre

from .logic import is_initial, pre_boolean

__all__ = ["PartialFriction", "friction_state_machine", "Unknown", "Free", "Forward", "Stuck", "Backward"]

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

    # defined by the subclass
    w_relfric = Variable(unit="rad/s", description="Relative angular velocity between frictional surfaces")
    a_relfric = Variable(unit="rad/s2",
                         description="Relative angular acceleration between frictional surfaces")
    tau0 = Variable(unit="N.m", description="Friction torque for w=0 and forward sliding")
    tau0_max = Variable(unit="N.m", description="Maximum friction torque for w=0 and locked")
    free = Boolean(description="true, if frictional element is not active")

    # defined here
    sa = Variable(unit="1", description="Path parameter of friction characteristic tau = f(a_relfric)")
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
                                      self.w_small, locked_acceleration=-self.K_locked * self.w_relfric)


def friction_state_machine(element, v_relfric, a_relfric, f0, f0_max, v_small, locked_acceleration=0):
    """The five equations F1-F5 of the MSL friction state machine, for either domain.

    Rotational and Translational ``PartialFriction`` share these equations
    (only the names of the relative motion and the limits differ), so both
    build them here from the element's ``sa``, ``startForward``,
    ``startBackward``, ``locked``, ``free`` and ``mode``.

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

    Returns
    -------
    list of Eq
        startForward (F1), startBackward (F2), locked (F3), a_relfric (F4), mode (F5).
    """
    sa, w = element.sa, v_relfric
    pre_mode = pre(element.mode)
    was = {value: sp.Eq(pre_mode, value) for value in (Stuck, Forward, Backward, Free)}

    start_forward = sp.Or(
        sp.And(was[Stuck], sp.Or(sa > f0_max, sp.And(pre_boolean(element.startForward), sa > f0))),
        sp.And(was[Backward], w > v_small),
        sp.And(is_initial(), w > 0))
    start_backward = sp.Or(
        sp.And(was[Stuck], sp.Or(sa < -f0_max, sp.And(pre_boolean(element.startBackward), sa < -f0))),
        sp.And(was[Forward], w < -v_small),
        sp.And(is_initial(), w < 0))
    locked = sp.And(sp.Not(element.free),
                    sp.Not(sp.Or(was[Forward], element.startForward, was[Backward], element.startBackward)))
    acceleration = sp.Piecewise(
        (locked_acceleration, element.locked),
        (sa, element.free),
        (sa - f0_max, element.startForward),
        (sa + f0_max, element.startBackward),
        (sa - f0_max, was[Forward]),
        (sa + f0_max, was[Backward]),
        (sa - sp.sign(w) * f0_max, True))
    mode = sp.Piecewise(
        (Free, element.free),
        (Forward, sp.And(sp.Or(was[Forward], was[Free], element.startForward), w > 0)),
        (Backward, sp.And(sp.Or(was[Backward], was[Free], element.startBackward), w < 0)),
        (Stuck, True))
    return [
        Eq(element.startForward, start_forward),   # F1
        Eq(element.startBackward, start_backward),  # F2
        Eq(element.locked, locked),                 # F3
        Eq(a_relfric, acceleration),                # F4
        Eq(element.mode, mode),                     # F5
    ]
