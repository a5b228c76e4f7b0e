"""Gears with losses (Modelica.Mechanics.Rotational.Components.LossyGear and Gearbox).

LossyGear is an ideal gear whose mesh efficiency and bearing friction depend
on the speed and on the direction of the power flow, with its own
stuck/rolling state machine (it can self-lock).  Gearbox puts a LossyGear in
series with an ElastoBacklash.
"""

from __future__ import annotations

import numbers

import numpy as np
import sympy as sp

from acausal.errors import ParameterError
from acausal.hybrid import noEvent
from acausal.language import Boolean, Component, Eq, If, Integer, Parameter, StateSelect, Variable, der, pre
from acausal.library.blocks.sources import Smoothness
from acausal.tables import check_abscissae, table_function
from acausal.components.checks import where
from acausal.components.logic import is_initial
from acausal.components.rotational import Flange_a, Flange_b, PartialElementaryTwoFlangesAndSupport2, Support
from acausal.components.thermal import HeatPort_a, PartialElementaryConditionalHeatPortWithoutT
from acausal.library.thermal import FixedTemperature

from .components import ElastoBacklash, Fixed

__all__ = ["LossyGear", "Gearbox"]

#: Modelica.Constants.eps: the tolerance of Modelica.Math.isEqual in LossyGear.
EPS = 2.2204460492503131e-16

#: The loss table of a gear without losses (``ideal``).
IDEAL_LOSS_TABLE = ((0.0, 1.0, 1.0, 0.0, 0.0),)

#: Names of the loss-table columns 2..5, for messages.
_LOSS_COLUMNS = ("eta_mf1", "eta_mf2", "tau_bf1", "tau_bf2")


def _loss_table(component, table) -> np.ndarray:
    """``lossTable`` as a float array, checked: n x 5, finite, |w_a| strictly increasing, 0 < eta <= 1.

    Raises
    ------
    ParameterError
        Naming the component, the parameter and the offending row (counted from 1).
    """
    path = f"{where(component)}.lossTable"
    example = "e.g. [[0, 0.5, 0.5, 0, 0]] or [[0, 0.95, 0.9, 0.1, 0.1], [100, 0.9, 0.85, 0.5, 0.5]]"
    try:
        data = np.array(table, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{path} is not a numeric matrix: {table!r}",
                             hint=f"one row [|w_a|, eta_mf1, eta_mf2, tau_bf1, tau_bf2] per speed, "
                                  f"{example}") from exc
    if data.ndim == 1 and data.size == 5:
        data = data.reshape(1, 5)
    if data.size == 0 or data.ndim != 2 or data.shape[1] != 5:
        raise ParameterError(f"{path} must be an n x 5 matrix (n >= 1), but its shape is {data.shape}",
                             hint=f"columns |w_a|, eta_mf1, eta_mf2, tau_bf1, tau_bf2; {example}")
    check_abscissae(data, path, "the speeds |w_a| (first column)", "w",
                    "sort the rows by speed and remove repeated speeds (CombiTable1D needs this)")
    for column in (1, 2):
        bad = (data[:, column] <= 0) | (data[:, column] > 1)
        if np.any(bad):
            row = int(np.argmax(bad))
            raise ParameterError(
                f"{path}: the mesh efficiency {_LOSS_COLUMNS[column - 1]} (column {column + 1}) must be "
                f"in (0, 1], but row {row + 1} (w = {data[row, 0]:g}) has {data[row, column]:g}",
                hint="an efficiency above 1 would create energy and one <= 0 reverses or blocks the "
                     "power flow; 1 means no mesh losses")
    data.setflags(write=False)
    return data


def _is_equal(a: float, b: float) -> bool:
    """Modelica.Math.isEqual(a, b, Modelica.Constants.eps)."""
    return abs(a - b) <= EPS


def _bearing_split(eta_mf1, eta_mf2, tau_bf1, tau_bf2):
    """tau_bf_a, the bearing friction on the flange_a side, from the two resultant friction torques.

    Solves ``tau_bf1 = eta_mf1*tau_bf_a + tau_bf_b/ratio`` and ``tau_bf2 =
    tau_bf_a/eta_mf2 + tau_bf_b/ratio`` for ``tau_bf_a``; with both mesh
    efficiencies 1 the split is not determined and half goes to each side.
    """
    return (tau_bf1 - tau_bf2) / (eta_mf1 - 1.0 / eta_mf2)


class LossyGear(PartialElementaryTwoFlangesAndSupport2, PartialElementaryConditionalHeatPortWithoutT):
    """Gear with mesh efficiency and bearing friction, stuck or rolling (Modelica.Mechanics.Rotational.Components.LossyGear).

    A gear without inertia whose losses depend on the direction of the
    power flow, following Pelchen, Schweiger and Otter (2002) with the
    correction of Bertsch (2009).  Angles are relative to the support
    (grounded unless ``useSupport``):

    * kinematics: ``phi_a = flange_a.phi - phi_support``, ``phi_b =
      flange_b.phi - phi_support``, ``phi_a = ratio*phi_b``, ``w_a =
      der(phi_a)``, ``a_a = der(w_a)``;
    * torque balance: ``0 = flange_b.tau + ratio*(flange_a.tau - tauLoss)``,
      where ``tauLoss`` is the loss torque referred to flange_a;
    * dissipation: ``lossPower = tauLoss*w_a`` (to the optional heat port).

    **Loss table.** Each row of ``lossTable`` is ``[|w_a|, eta_mf1, eta_mf2,
    tau_bf1, tau_bf2]``: the mesh efficiency when flange_a drives
    (``eta_mf1``) and when flange_b drives (``eta_mf2``), and the resultant
    bearing friction torques referred to flange_a in those two cases.  The
    columns are interpolated linearly in ``|w_a|`` (without events; linear
    extrapolation through the last two rows); ``tau_bf1 = |column 4|``,
    ``tau_bf2 = |column 5|``.  The friction on the flange_a side alone is
    ``tau_bf_a = (tau_bf1 - tau_bf2)/(eta_mf1 - 1/eta_mf2)``, or
    ``tau_bf1/2`` when both efficiencies are 1.  The same quantities at
    ``w_a = 0`` are the constants ``eta_mf1_0``, ``eta_mf2_0``,
    ``tau_bf1_0``, ``tau_bf2_0``, ``tau_bf_a_0``.  ``ideal`` is true when the
    table is exactly ``[0, 1, 1, 0, 0]``: the gear is then an IdealGear
    (``tauLoss = 0``, ``mode = Free``).

    **Loss in the four quadrants** (``tau_a = flange_a.tau``)::

        quadrant1 = (1 - eta_mf1)*tau_a + tau_bf1      w_a > 0, flange_a drives
        quadrant2 = (1 - 1/eta_mf2)*tau_a + tau_bf2    w_a > 0, flange_b drives
        quadrant3 = (1 - eta_mf1)*tau_a - tau_bf1      w_a < 0, flange_a drives
        quadrant4 = (1 - 1/eta_mf2)*tau_a - tau_bf2    w_a < 0, flange_b drives

    The driving side is the sign of ``tau_eta``: ``tau_a`` when locked,
    ``tau_a - tau_bf_a`` when rolling or starting forward, ``tau_a +
    tau_bf_a`` otherwise; ``tau_etaPos = tau_eta >= 0`` (an event),
    ``tauLossMax = quadrant1 if tau_etaPos else quadrant2`` (the loss for
    forward motion), ``tauLossMin = quadrant4 if tau_etaPos else quadrant3``.

    **Break-away limits** use the table at ``w_a = 0`` (no events inside)::

        tauLossMax_p = (1 - eta_mf1_0)*tau_a + tau_bf1_0    if tau_a - tau_bf_a_0 > 0
                       (1 - 1/eta_mf2_0)*tau_a + tau_bf2_0   otherwise
        tauLossMin_m = (1 - 1/eta_mf2_0)*tau_a - tau_bf2_0   if tau_a + tau_bf_a_0 > 0
                       (1 - eta_mf1_0)*tau_a - tau_bf1_0     otherwise

    **Stuck/rolling state machine** (``mode`` starts at Free and is fixed,
    so the first evaluation sees ``pre(mode) = Free``).  ``sa`` is the path
    variable of the characteristic, a torque (N.m): the holding torque while
    locked, the acceleration (read as a torque) plus the loss while rolling.
    ``u = unitAngularAcceleration/unitTorque`` is the MSL's pair of unit
    constants (both 1; the MSL declares ``sa`` with unit "1" instead)::

        startForward  = pre(mode) == Stuck and sa > tauLossMax_p  or  initial() and w_a > 0
        startBackward = pre(mode) == Stuck and sa < tauLossMin_m  or  initial() and w_a < 0
        locked  = not (ideal or pre(mode) in (Forward, Backward) or startForward or startBackward)
        tauLoss = 0 if ideal; sa if locked;
                  tauLossMax if startForward or pre(mode) == Forward; tauLossMin otherwise
        a_a     = sa*u if ideal; 0 if locked; else (sa - tauLoss)*u
        mode    = Free if ideal;
                  Forward  if (pre(mode) == Forward or startForward) and w_a > 0;
                  Backward if (pre(mode) == Backward or startBackward) and w_a < 0;
                  Stuck otherwise

    **Self-locking.** Without bearing friction and with ``tau_a > 0`` held
    at the locked gear (``tau_a``, ``flange_b.tau``: the torques the
    neighbours apply at zero acceleration), the gear stays locked while
    ``-tau_a/eta_mf2 <= flange_b.tau/ratio <= -eta_mf1*tau_a``: a band of
    width ``(1/eta_mf2 - eta_mf1)*tau_a`` in which neither side can drive
    the other.

    Parameters
    ----------
    ratio : float
        Transmission ratio ``flange_a.phi/flange_b.phi``; must not be 0.
    lossTable : array_like, shape (n, 5)
        Rows ``[|w_a|, eta_mf1, eta_mf2, tau_bf1, tau_bf2]``, speeds strictly
        increasing, efficiencies in (0, 1].
    smoothness : Smoothness
        Only ``Smoothness.LinearSegments`` (the MSL default) is supported.
    unitAngularAcceleration : float, default 1 rad/s2
        Unit constant (MSL ``constant unitAngularAcceleration``); do not change.
    unitTorque : float, default 1 N.m
        Unit constant (MSL ``constant unitTorque``); do not change.

    Notes
    -----
    ``tau_aPos`` only repeats ``tau_etaPos`` (kept for compatibility, as in
    the MSL).  ``mode`` takes the values of the class constants Unknown
    (3), Free (2), Forward (1), Stuck (0) and Backward (-1).

    References
    ----------
    .. [1] C. Pelchen, C. Schweiger and M. Otter, "Modeling and Simulating
       the Efficiency of Gearboxes and of Planetary Gearboxes", Proceedings
       of the 2nd International Modelica Conference, Oberpfaffenhofen,
       Germany, pp. 257-266, March 18-19, 2002.
    .. [2] C. Bertsch, "Problem with model LossyGear and a proposed
       solution", Modelica Standard Library ticket #108, September 11, 2009.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.LossyGear"

    hints = {
        "mode": "a LossyGear locks the motion of flange_a relative to its support; another element "
                "that can lock the same motion (a BearingFriction, Brake or second LossyGear on a rigidly "
                "connected shaft) leaves the split of the holding torque undetermined when both are "
                "stuck; put a compliance between them, or move the bearing friction into the gear's "
                "lossTable (columns tau_bf1, tau_bf2)",
        "chattering": "a LossyGear without inertia on either side switches between stuck and rolling "
                      "without time passing; give one of its shafts an inertia",
    }

    Unknown = 3  #: value of mode is not known
    Free = 2  #: element is not active
    Forward = 1  #: w_a > 0 (forward rolling)
    Stuck = 0  #: w_a = 0 (locked, or starting to roll forward or backward)
    Backward = -1  #: w_a < 0 (backward rolling)

    ratio = Parameter(1.0, description="Transmission ratio (flange_a.phi/flange_b.phi)")
    lossTable = Parameter(IDEAL_LOSS_TABLE, structural=True,  # noqa: N815 - Modelica name
                          description="Array for mesh efficiencies and bearing friction depending on speed")
    smoothness = Parameter(Smoothness.LinearSegments, structural=True,
                           description="Smoothness of interpolation in lossTable table")

    # Unit constants (MSL: constant ... = 1): sa*unitAngularAcceleration/unitTorque is sa, a torque,
    # read as an acceleration.  The language has no "final"; a value other than 1 scales the dynamics.
    unitAngularAcceleration = Parameter(1.0, unit="rad/s2",  # noqa: N815 - Modelica name
                                        description="Unit constant 1 rad/s2 (do not change)")
    unitTorque = Parameter(1.0, unit="N.m",  # noqa: N815 - Modelica name
                           description="Unit constant 1 N.m (do not change)")

    phi_a = Variable(unit="rad", description="Angle between left shaft flange and support")
    phi_b = Variable(unit="rad", description="Angle between right shaft flange and support")
    sa = Variable(unit="N.m", description="Path parameter for acceleration and torque loss")
    w_a = Variable(unit="rad/s", description="Angular velocity of flange_a with respect to support")
    a_a = Variable(unit="rad/s2", description="Angular acceleration of flange_a with respect to support")

    eta_mf1 = Variable(unit="1", description="Mesh efficiency in case that flange_a is driving")
    eta_mf2 = Variable(unit="1", description="Mesh efficiency in case that flange_b is driving")
    tau_bf_a = Variable(unit="N.m", description="Bearing friction torque on flange_a side")
    tau_eta = Variable(unit="N.m",
                       description="Torque that determines the driving side (= flange_a.tau -/+ tau_bf_a "
                                   "when rolling forward/backward, flange_a.tau when locked)")
    tau_bf1 = Variable(unit="N.m",
                       description="Absolute resultant bearing friction torque with respect to flange_a in case "
                                   "that flange_a is driving (= |tau_bf_a*eta_mf1 + tau_bf_b/i|)")
    tau_bf2 = Variable(unit="N.m",
                       description="Absolute resultant bearing friction torque with respect to flange_a in case "
                                   "that flange_b is driving (= |tau_bf_a/eta_mf2 + tau_bf_b/i|)")

    quadrant1 = Variable(unit="N.m", description="Torque loss if w_a > 0 and flange_a drives (tau_eta >= 0)")
    quadrant2 = Variable(unit="N.m", description="Torque loss if w_a > 0 and flange_b drives (tau_eta < 0)")
    quadrant3 = Variable(unit="N.m", description="Torque loss if w_a < 0 and flange_a drives (tau_eta < 0)")
    quadrant4 = Variable(unit="N.m", description="Torque loss if w_a < 0 and flange_b drives (tau_eta >= 0)")
    quadrant1_p = Variable(unit="N.m",
                           description="Torque loss at w_a = 0+ if flange_a drives (tau_eta_p > 0)")
    quadrant2_p = Variable(unit="N.m",
                           description="Torque loss at w_a = 0+ if flange_b drives (tau_eta_p <= 0)")
    quadrant3_m = Variable(unit="N.m",
                           description="Torque loss at w_a = 0- if flange_a drives (tau_eta_m <= 0)")
    quadrant4_m = Variable(unit="N.m",
                           description="Torque loss at w_a = 0- if flange_b drives (tau_eta_m > 0)")

    tauLoss = Variable(unit="N.m",  # noqa: N815 - Modelica name
                       description="Torque loss due to friction in the gear teeth and in the bearings")
    tauLossMax = Variable(unit="N.m", description="Torque loss for positive speed")  # noqa: N815
    tauLossMin = Variable(unit="N.m", description="Torque loss for negative speed")  # noqa: N815
    tauLossMax_p = Variable(unit="N.m", description="Break-away limit of sa for rolling forward (table at w_a = 0)")  # noqa: N815
    tauLossMin_m = Variable(unit="N.m", description="Break-away limit of sa for rolling backward (table at w_a = 0)")  # noqa: N815

    tau_aPos = Boolean(start=True,  # noqa: N815 - Modelica name
                       description="Only for backwards compatibility (was previously: true, if torque of "
                                   "flange_a is not negative)")
    tau_etaPos = Boolean(start=True, description="= true, if torque tau_eta is not negative")  # noqa: N815
    startForward = Boolean(start=False, description="= true, if starting to roll forward")  # noqa: N815
    startBackward = Boolean(start=False, description="= true, if starting to roll backward")  # noqa: N815
    locked = Boolean(start=False, description="= true, if gear is locked")
    ideal = Boolean(description="= true, if losses are neglected (that is lossTable = [0, 1, 1, 0, 0])")
    mode = Integer(start=Free, fixed=True, min=Backward, max=Unknown,
                   description="Mode of friction element (unknown, not active, forward/backward rolling, "
                               "stuck)")

    tau_eta_p = Variable(unit="N.m", description="tau_eta assuming positive omega")
    tau_eta_m = Variable(unit="N.m", description="tau_eta assuming negative omega")

    # -- structural helpers ------------------------------------------------

    def build(self) -> None:
        self.check_parameters()

    def check_parameters(self) -> None:
        """Raise ParameterError for a zero ratio, an invalid lossTable or an unsupported smoothness."""
        _loss_table(self, self.lossTable)
        if Smoothness(self.smoothness) is not Smoothness.LinearSegments:
            raise ParameterError(
                f"{where(self)}.smoothness = {Smoothness(self.smoothness).name} is not supported",
                hint="LossyGear interpolates its lossTable with Smoothness.LinearSegments (the MSL default)")
        ratio = self.parameter_binding("ratio")
        if isinstance(ratio, sp.Basic) and ratio.is_number:
            ratio = float(ratio)
        if isinstance(ratio, numbers.Real) and ratio == 0:
            raise ParameterError(f"{where(self)}.ratio = 0: the transmission ratio may not be zero",
                                 hint="ratio = flange_a.phi/flange_b.phi; e.g. ratio=2 for a reduction 2:1")

    @property
    def is_ideal(self) -> bool:
        """Whether lossTable equals [0, 1, 1, 0, 0] within Modelica.Constants.eps (no losses)."""
        data = _loss_table(self, self.lossTable)
        return data.shape == (1, 5) and bool(np.all(np.abs(data - np.array(IDEAL_LOSS_TABLE)) <= EPS))

    def loss_columns(self) -> list[type[sp.Function]]:
        """The table functions of lossTable columns 2..5 against |w_a| (CombiTable1D, LinearSegments)."""
        data = _loss_table(self, self.lossTable)
        stem = f"{self.path}.lossTable" if self.path else "lossTable"
        return [table_function(f"{stem}.{name}", data[:, [0, column]])
                for column, name in enumerate(_LOSS_COLUMNS, start=1)]

    def at_rest(self) -> dict[str, float]:
        """The loss characteristics at w_a = 0: eta_mf1_0, eta_mf2_0, tau_bf1_0, tau_bf2_0, tau_bf_a_0."""
        eta1, eta2, tau1, tau2 = (float(column(0)) for column in self.loss_columns())
        tau1, tau2 = abs(tau1), abs(tau2)
        if _is_equal(eta1, 1.0) and _is_equal(eta2, 1.0):
            tau_a = tau1 / 2  # the split between the two sides is not determined: half each
        else:
            tau_a = _bearing_split(eta1, eta2, tau1, tau2)
        return {"eta_mf1_0": eta1, "eta_mf2_0": eta2, "tau_bf1_0": tau1, "tau_bf2_0": tau2,
                "tau_bf_a_0": tau_a}

    # -- equations ---------------------------------------------------------

    def equations(self):
        ideal = self.is_ideal
        tau_a, w_a, sa = self.flange_a.tau, self.w_a, self.sa
        # sa is a torque; the unit constants (both 1) read a torque as an acceleration
        acceleration_per_torque = self.unitAngularAcceleration / self.unitTorque
        interpolated = [getattr(self, name) for name in _INTERPOLATION_RESULT]
        equations = [
            Eq(self.ideal, sp.true if ideal else sp.false),
            Eq(self.phi_a, self.flange_a.phi - self.phi_support),
            Eq(self.phi_b, self.flange_b.phi - self.phi_support),
            Eq(self.phi_a, self.ratio * self.phi_b),
            Eq(0, self.flange_b.tau + self.ratio * (tau_a - self.tauLoss)),
            Eq(w_a, der(self.phi_a)),
            Eq(self.a_a, der(w_a)),
        ]

        # interpolation in |w_a| (no events, as in the MSL)
        if ideal:
            equations += [Eq(x, v) for x, v in zip(interpolated, (1, 1, 0, 0))]
            equations += [Eq(self.eta_mf1, 1), Eq(self.eta_mf2, 1), Eq(self.tau_bf1, 0), Eq(self.tau_bf2, 0)]
        else:
            speed = noEvent(sp.Abs(w_a))
            equations += [Eq(x, column(speed)) for x, column in zip(interpolated, self.loss_columns())]
            equations += [
                Eq(self.eta_mf1, interpolated[0]),
                Eq(self.eta_mf2, interpolated[1]),
                Eq(self.tau_bf1, noEvent(sp.Abs(interpolated[2]))),
                Eq(self.tau_bf2, noEvent(sp.Abs(interpolated[3]))),
            ]

        # bearing friction on the flange_a side
        data = _loss_table(self, self.lossTable)
        if np.all(np.abs(data[:, 1:3] - 1.0) <= EPS):
            # both efficiencies are 1 at every speed (linear segments of ones stay exactly 1)
            equations.append(Eq(self.tau_bf_a, self.tau_bf1 / 2))
        else:
            both_one = sp.And(sp.Abs(self.eta_mf1 - 1) <= EPS, sp.Abs(self.eta_mf2 - 1) <= EPS)
            equations.append(Eq(self.tau_bf_a, noEvent(If(
                both_one, self.tau_bf1 / 2,
                _bearing_split(self.eta_mf1, self.eta_mf2, self.tau_bf1, self.tau_bf2)))))

        # break-away limits from the characteristics at w_a = 0 (no events inside)
        rest = self.at_rest()
        eta1_0, eta2_0 = rest["eta_mf1_0"], rest["eta_mf2_0"]
        tau1_0, tau2_0, tau_a_0 = rest["tau_bf1_0"], rest["tau_bf2_0"], rest["tau_bf_a_0"]
        equations += [
            Eq(self.tau_eta_p, tau_a - tau_a_0),
            Eq(self.tau_eta_m, tau_a + tau_a_0),
            Eq(self.quadrant1_p, (1 - eta1_0) * tau_a + tau1_0),
            Eq(self.quadrant2_p, (1 - 1 / eta2_0) * tau_a + tau2_0),
            Eq(self.tauLossMax_p, noEvent(If(self.tau_eta_p > 0, self.quadrant1_p, self.quadrant2_p))),
            Eq(self.quadrant4_m, (1 - 1 / eta2_0) * tau_a - tau2_0),
            Eq(self.quadrant3_m, (1 - eta1_0) * tau_a - tau1_0),
            Eq(self.tauLossMin_m, noEvent(If(self.tau_eta_m > 0, self.quadrant4_m, self.quadrant3_m))),
        ]

        # losses in the four quadrants at the current speed
        equations += [
            Eq(self.quadrant1, (1 - self.eta_mf1) * tau_a + self.tau_bf1),
            Eq(self.quadrant2, (1 - 1 / self.eta_mf2) * tau_a + self.tau_bf2),
            Eq(self.quadrant4, (1 - 1 / self.eta_mf2) * tau_a - self.tau_bf2),
            Eq(self.quadrant3, (1 - self.eta_mf1) * tau_a - self.tau_bf1),
        ]

        # driving side and the state machine
        was_forward = sp.Eq(pre(self.mode), self.Forward)
        was_backward = sp.Eq(pre(self.mode), self.Backward)
        was_stuck = sp.Eq(pre(self.mode), self.Stuck)
        forward = sp.Or(self.startForward, was_forward)
        if ideal:
            tau_eta = tau_a
        else:
            tau_eta = sp.Piecewise((tau_a, self.locked), (tau_a - self.tau_bf_a, forward),
                                   (tau_a + self.tau_bf_a, True))
        equations += [
            Eq(self.tau_eta, tau_eta),
            Eq(self.tau_etaPos, self.tau_eta >= 0),
            Eq(self.tau_aPos, self.tau_etaPos),
            Eq(self.tauLossMax, If(self.tau_etaPos, self.quadrant1, self.quadrant2)),
            Eq(self.tauLossMin, If(self.tau_etaPos, self.quadrant4, self.quadrant3)),
            Eq(self.startForward, sp.Or(sp.And(was_stuck, sa > self.tauLossMax_p),
                                        sp.And(is_initial(), w_a > 0))),
            Eq(self.startBackward, sp.Or(sp.And(was_stuck, sa < self.tauLossMin_m),
                                         sp.And(is_initial(), w_a < 0))),
        ]
        if ideal:
            equations += [
                Eq(self.locked, sp.false),
                Eq(self.tauLoss, 0),
                Eq(self.a_a, sa * acceleration_per_torque),
                Eq(self.mode, self.Free),
            ]
        else:
            equations += [
                Eq(self.locked, sp.Not(sp.Or(was_forward, self.startForward, was_backward, self.startBackward))),
                Eq(self.tauLoss, sp.Piecewise((sa, self.locked), (self.tauLossMax, forward),
                                              (self.tauLossMin, True))),
                Eq(self.a_a, If(self.locked, 0, (sa - self.tauLoss) * acceleration_per_torque)),
                Eq(self.mode, sp.Piecewise(
                    (self.Forward, sp.And(forward, w_a > 0)),
                    (self.Backward, sp.And(sp.Or(was_backward, self.startBackward), w_a < 0)),
                    (self.Stuck, True))),
            ]
        equations.append(Eq(self.lossPower, self.tauLoss * w_a))
        return equations


#: The MSL's ``interpolation_result[1, 4]``, one declaration per element.
_INTERPOLATION_RESULT = tuple(f"interpolation_result[1, {i}]" for i in range(1, 5))


def _declare_interpolation_result() -> None:
    """Add the elements of ``interpolation_result`` to LossyGear under their Modelica names.

    A name like ``interpolation_result[1, 1]`` is not a Python identifier, so
    the declarations are attached after the class body, with the
    ``__set_name__`` call the class body would have made.
    """
    for i, name in enumerate(_INTERPOLATION_RESULT):
        column = _LOSS_COLUMNS[i]
        declaration = Variable(unit="1" if i < 2 else "N.m",
                               description=f"Result of interpolation in lossTable (column {i + 2}: "
                                           f"{'signed ' if i >= 2 else ''}{column} at |w_a|)")
        declaration.__set_name__(LossyGear, name)
        setattr(LossyGear, name, declaration)


_declare_interpolation_result()


class Gearbox(Component):
    """Realistic model of a gearbox: LossyGear followed by ElastoBacklash (Modelica.Mechanics.Rotational.Components.Gearbox).

    A graphical composite of two sub-components, connected in series:

    * ``lossyGear``: :class:`LossyGear` with ``ratio`` and ``lossTable``
      (mesh efficiency and bearing friction, stuck or rolling), its support
      on the gearbox housing and its heat port on the gearbox heat node;
    * ``elastoBacklash``: ElastoBacklash with the gear elasticity ``c``,
      damping ``d`` and total backlash ``b`` (``phi_rel0 = 0``), between
      ``lossyGear.flange_b`` and ``flange_b``, its heat port on the same node.

    The gearbox's own relative states describe the elasticity:
    ``phi_rel = flange_b.phi - lossyGear.flange_b.phi``, ``w_rel =
    der(phi_rel)``, ``a_rel = der(w_rel)`` (``phi_rel`` and ``w_rel`` carry
    ``stateSelect``, prefer by default).  Through the connections these are
    the ElastoBacklash's ``phi_rel``, ``w_rel`` and ``a_rel``, and that is
    how they are written here (the same quantities, without differentiating
    the angle twice more).  The gear wheels have no inertia; connect Inertia
    components to the flanges where it matters.

    The housing is ``support`` when ``useSupport``, otherwise a Fixed named
    ``fixed``; the losses of both parts leave through ``heatPort`` when
    ``useHeatPort``, otherwise into a FixedTemperature ``fixedTemperature``
    at ``T`` (293.15 K, final in the MSL).  The MSL routes both through
    protected connectors (``internalSupport``, ``internalHeatPort``); here
    the sub-components are connected to the support or the fixed element
    directly, which gives the same connection sets.
    """

    modelica_name = "Modelica.Mechanics.Rotational.Components.Gearbox"

    ratio = Parameter(1.0, description="Transmission ratio (flange_a.phi/flange_b.phi)")
    lossTable = Parameter(IDEAL_LOSS_TABLE, structural=True,  # noqa: N815 - Modelica name
                          description="Array for mesh efficiencies and bearing friction depending on speed "
                                      "(see docu of LossyGear)")
    c = Parameter(1.0e5, unit="N.m/rad", min=1.0e-60, description="Gear elasticity (spring constant)")
    d = Parameter(0.0, unit="N.m.s/rad", min=0, description="Gear damping (relative damping)")
    b = Parameter(0.0, unit="rad", min=0, description="Total backlash")
    stateSelect = Parameter(StateSelect.prefer, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use phi_rel and w_rel as states")
    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="= true, if support flange enabled, otherwise implicitly grounded")
    useHeatPort = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if HeatPort is enabled")
    T = Parameter(293.15, unit="K", description="Fixed device temperature if useHeatPort = false")

    flange_a = Flange_a(description="Flange of left shaft")
    flange_b = Flange_b(description="Flange of right shaft")
    support = Support(condition="useSupport", description="Support/housing of component")
    heatPort = HeatPort_a(condition="useHeatPort",  # noqa: N815 - Modelica name
                          description="Optional port to which dissipated losses are transported in form of heat")

    phi_rel = Variable(start=0.0, unit="rad", nominal=1e-4, state_select=lambda c: c.stateSelect,
                       description="Relative rotation angle over gear elasticity "
                                   "(= flange_b.phi - lossyGear.flange_b.phi)")
    w_rel = Variable(start=0.0, unit="rad/s", state_select=lambda c: c.stateSelect,
                     description="Relative angular velocity over gear elasticity (= der(phi_rel))")
    a_rel = Variable(start=0.0, unit="rad/s2",
                     description="Relative angular acceleration over gear elasticity (= der(w_rel))")

    def build(self) -> None:
        self.lossyGear = LossyGear(ratio=self.ratio, lossTable=self.lossTable, useSupport=True, useHeatPort=True)
        self.elastoBacklash = ElastoBacklash(b=self.b, c=self.c, phi_rel0=0.0, d=self.d, useHeatPort=True)
        self.connect(self.flange_a, self.lossyGear.flange_a)
        self.connect(self.lossyGear.flange_b, self.elastoBacklash.flange_a)
        self.connect(self.elastoBacklash.flange_b, self.flange_b)
        if self.useSupport:
            housing = self.support
        else:
            self.fixed = Fixed()
            housing = self.fixed.flange
        self.connect(self.lossyGear.support, housing)
        if self.useHeatPort:
            heat_node = self.heatPort
        else:
            self.fixedTemperature = FixedTemperature(T=self.T)
            heat_node = self.fixedTemperature.port
        self.connect(self.lossyGear.heatPort, heat_node)
        self.connect(self.elastoBacklash.heatPort, heat_node)

    def equations(self):
        # flange_b.phi - lossyGear.flange_b.phi is, by the connections, the ElastoBacklash's own
        # relative angle, and w_rel, a_rel are its derivatives: state them as aliases rather
        # than differentiating the same angle a second time (a second der() chain down to a_rel
        # makes the engine's initialization singular; reported as an engine limitation).
        backlash = self.elastoBacklash
        return [
            Eq(self.phi_rel, backlash.phi_rel),
            Eq(self.w_rel, backlash.w_rel),
            Eq(self.a_rel, backlash.a_rel),
        ]
