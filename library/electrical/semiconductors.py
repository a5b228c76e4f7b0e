"""Semiconductor devices (Modelica.Electrical.Analog.Semiconductors).

Diodes (the simple exponential diode, the improved ``Diode2`` with series
resistance and breakdown, the Zener diode), the MOS transistors of the
Shichman-Hodges type, the bipolar transistors after Ebers-Moll, the
thyristor and the simple triac built from two of them.  Every device has the
conditional heat port of its losses; with ``useTemperatureDependency`` the
diode and the transistors take their temperature from it (what earlier MSL
versions called HeatingDiode, HeatingNMOS, HeatingPMOS, HeatingNPN and
HeatingPNP, merged into these classes since MSL 4.0).

The exponentials are continued linearly beyond a limit (:func:`exlin`,
:func:`exlin2`, the MSL's protected functions of the package), so that a
large forward voltage gives a large current instead of an overflow.  The
MSL writes these as functions, whose relations never generate events; here
they are ``noEvent`` expressions for the same reason.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from acausal.hybrid import Assert, noEvent, smooth
from acausal.language import Component, Eq, Parameter, Variable, der
from acausal.components.declarations import DerivedDefaults
from acausal.components.electrical import ConditionalHeatPort, NegativePin, OnePort, Pin, PositivePin

__all__ = [
    "Diode",
    "Diode2",
    "ZDiode",
    "NMOS",
    "PMOS",
    "NPN",
    "PNP",
    "Thyristor",
    "SimpleTriac",
    "exlin",
    "exlin2",
    "powlin",
    "BOLTZMANN",
    "ELEMENTARY_CHARGE",
]

#: Modelica.Constants.k (J/K), exact since the SI redefinition of 2019.
BOLTZMANN = 1.380649e-23
#: Modelica.Constants.q (C), the elementary charge.
ELEMENTARY_CHARGE = 1.602176634e-19
#: k/q (V/K): the thermal voltage per kelvin; also Modelica.Constants.R/F, which the MSL's Diode2 uses.
_K_Q = BOLTZMANN / ELEMENTARY_CHARGE
#: Modelica.Constants.small: the MSL's lower bound of Maxexp.
_SMALL = 1e-60


def exlin(x: Any, maxexp: Any) -> sp.Expr:
    """``exp(x)`` linearly continued for ``x > maxexp`` (Modelica.Electrical.Analog.Semiconductors.exlin).

    Parameters
    ----------
    x, maxexp : sympy expression or number
        The exponent and the limit beyond which the tangent of ``exp`` at
        ``maxexp`` replaces it: ``exp(maxexp)*(1 + x - maxexp)``.

    Returns
    -------
    sympy.Expr
        A ``noEvent`` Piecewise: the MSL's function generates no events, and
        the two branches meet with equal value and slope.
    """
    return noEvent(sp.Piecewise((sp.exp(maxexp) * (1 + x - maxexp), x > maxexp), (sp.exp(x), True)))


def exlin2(x: Any, minexp: Any, maxexp: Any) -> sp.Expr:
    """``exp(x)`` linearly continued below ``minexp`` and above ``maxexp`` (Modelica.Electrical.Analog.Semiconductors.exlin2).

    Below ``minexp`` the tangent at ``minexp``, ``exp(minexp)*(1 + x - minexp)``
    (which may become negative far below it, as in the MSL); otherwise
    :func:`exlin`.
    """
    return noEvent(sp.Piecewise((sp.exp(minexp) * (1 + x - minexp), x < minexp), (exlin(x, maxexp), True)))


def powlin(x: Any, y: Any) -> sp.Expr:
    """``(1 - x)^(-y)`` linearly continued for ``x > 0`` (Modelica.Electrical.Analog.Semiconductors.powlin).

    The depletion capacitance law ``C0/(1 - v/phi)^m`` has a pole at
    ``v = phi``; beyond ``x = 0`` the MSL replaces it by ``1 + y*x``.
    """
    return noEvent(sp.Piecewise((1 + y * x, x > 0), ((1 - x) ** (-y), True)))


class _TemperatureDependency(DerivedDefaults, ConditionalHeatPort):
    """``extends ConditionalHeatPort(useHeatPort=useTemperatureDependency)``.

    The heat port exists by default exactly when the device's parameters
    follow its temperature; a modifier ``useHeatPort`` still overrides it.
    """

    modelica_name = None

    useTemperatureDependency = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                         description="= true, if the device's parameters depend on temperature")

    def _modifier_value(self, name: str, default: Any) -> Any:
        # a structural parameter is read through here: useHeatPort's default is bound to another one
        if name == "useHeatPort" and name not in self._modifiers:
            return bool(self._modifier_value("useTemperatureDependency", False))
        return super()._modifier_value(name, default)


# --------------------------------------------------------------------------
# diodes


class Diode(OnePort, _TemperatureDependency):
    """Simple diode with heating port (Modelica.Electrical.Analog.Semiconductors.Diode).

    ``i = Ids*(exp(v/Vt) - 1) + v/R``, the exponential continued linearly
    beyond ``v/Vt = Maxexp`` (:func:`exlin`), a parallel resistance ``R``.
    With ``useTemperatureDependency`` (and then, by default, the heat port)
    the thermal voltage is ``vt_t = k*T/q`` of the heat port's temperature,
    and the saturation current grows as ``Ids*(T/TNOM)^(XTI/N)*exp((T/TNOM -
    1)*EG/(N*vt_t))``.  ``LossPower = v*i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.Diode"

    Ids = Parameter(1e-6, unit="A", description="Saturation current")
    Vt = Parameter(0.04, unit="V", description="Voltage equivalent of temperature (kT/qn)")
    Maxexp = Parameter(15.0, unit="1", min=_SMALL, description="Max. exponent for linear continuation")
    R = Parameter(1e8, unit="Ohm", description="Parallel ohmic resistance")
    # the MSL declares EG a plain Real; it divides a voltage in an exponent, so it is in volts (eV per charge)
    EG = Parameter(1.11, unit="V", description="Activation energy")
    N = Parameter(1.0, unit="1", description="Emission coefficient")
    TNOM = Parameter(300.15, unit="K", description="Parameter measurement temperature")
    XTI = Parameter(3.0, unit="1", description="Temperature exponent of saturation current")
    vt_t = Variable(unit="V", description="Temperature voltage")
    id = Variable(unit="A", description="Diode current")
    htemp = Variable(unit="K", description="Auxiliary temperature")
    aux = Variable(unit="1", description="Auxiliary exponent (htemp/TNOM - 1)*EG/(N*vt_t)")
    auxp = Variable(unit="1", description="exp(aux)")

    def equations(self):
        if self.useTemperatureDependency:
            current = [Eq(self.id, self.Ids * (exlin(self.v / (self.N * self.vt_t), self.Maxexp) - 1)),
                       Eq(self.i, self.id * (self.htemp / self.TNOM) ** (self.XTI / self.N) * self.auxp
                          + self.v / self.R)]
        else:
            current = [Eq(self.id, self.Ids * (exlin(self.v / self.Vt, self.Maxexp) - 1)),
                       Eq(self.i, smooth(1, self.id + self.v / self.R))]
        return [Assert(self.T_heatPort > 0, "Temperature must be positive"),
                Eq(self.htemp, self.T_heatPort),
                Eq(self.vt_t, _K_Q * self.htemp),
                *current,
                Eq(self.aux, (self.htemp / self.TNOM - 1) * self.EG / (self.N * self.vt_t)),
                Eq(self.auxp, sp.exp(self.aux)),
                Eq(self.LossPower, self.i * self.v)]


class Diode2(DerivedDefaults, OnePort, ConditionalHeatPort):
    """Improved diode model (Modelica.Electrical.Analog.Semiconductors.Diode2).

    A pure diode ``vd`` in series with ``Rs``, the whole parallel to ``Gp``:
    ``v = vd + id*Rs``, ``i = id + v*Gp``.  The pure diode follows
    ``Ids*(exp(vd/(N*Vt)) - 1)`` up to ``VdMax = Vf + N*Vt`` and its tangent
    beyond; below ``-Bv/2`` the breakdown branch
    ``-Ids*(exp(-(vd + Bv)/(N*Vt)) + 1 - 2*exp(-Bv/(2*N*Vt)))`` takes over,
    continuously differentiable at ``-Bv/2``.  With the heat port the thermal
    voltage is ``R*T_heatPort/F``; otherwise ``Vt`` (default ``R*T/F`` of the
    fixed temperature ``T``, 293.15 K).
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.Diode2"

    derived_defaults = {"Vt": lambda c: _K_Q * c.T}

    T = Parameter(293.15, unit="K", description="Fixed device temperature if useHeatPort = false")
    Vf = Parameter(0.7, unit="V", description="Forward voltage")
    Ids = Parameter(1e-13, unit="A", description="Reverse saturation current")
    Rs = Parameter(16.0, unit="Ohm", description="Ohmic resistance")
    Vt = Parameter(None, unit="V", description="Thermal voltage (kT/q), 0.026 at normal conditions "
                                               "(default R*T/F)")
    N = Parameter(1.0, unit="1", description="Emission coefficient")
    Bv = Parameter(100.0, unit="V", description="Reverse breakdown voltage")
    Gp = Parameter(1e-6, unit="S", description="Parallel conductance for numerical stability")
    vd = Variable(unit="V", description="Voltage across pure diode part")
    id = Variable(unit="A", description="Diode current")
    VdMax = Variable(unit="V", description="Linear continuation threshold")
    iVdMax = Variable(unit="A", description="Current at threshold")
    diVdMax = Variable(unit="S", description="Conductance at threshold")
    Vt_applied = Variable(unit="V", description="Thermal voltage in use")

    def equations(self):
        nvt = self.N * self.Vt_applied
        vd = self.vd
        # R/F = k/q: the MSL writes Modelica.Constants.R*T/Modelica.Constants.F
        vt_applied = _K_Q * self.T_heatPort if self.useHeatPort else self.Vt
        return [Eq(self.VdMax, self.Vf + nvt),
                Eq(self.iVdMax, self.Ids * (sp.exp(self.VdMax / nvt) - 1)),
                Eq(self.diVdMax, self.Ids * sp.exp(self.VdMax / nvt) / nvt),
                Eq(self.Vt_applied, vt_applied),
                Eq(self.id, smooth(1, sp.Piecewise(
                    (-self.Ids * (sp.exp(-(vd + self.Bv) / nvt) + 1 - 2 * sp.exp(-self.Bv / (2 * nvt))),
                     vd < -self.Bv / 2),
                    (self.Ids * (sp.exp(vd / nvt) - 1), vd < self.VdMax),
                    (self.iVdMax + (vd - self.VdMax) * self.diVdMax, True)))),
                Eq(self.v, vd + self.id * self.Rs),
                Eq(self.i, self.id + self.v * self.Gp),
                Eq(self.LossPower, self.i * self.v),
                Assert(self.Bv > 0, "Bv must be greater than zero"),
                Assert(self.Vf > 0, "Vf must be greater than zero"),
                Assert(self.Vt > 0, "Vt must be greater than zero")]


class ZDiode(OnePort, ConditionalHeatPort):
    """Zener diode with 3 working areas (Modelica.Electrical.Analog.Semiconductors.ZDiode).

    ``i = Ids*(exp(v/Vt) - 1) - Ibv*exp(-(v + Bv)/(Nbv*Vt)) + v/R``: the
    forward diode and, beyond the breakdown voltage ``Bv`` in reverse, the
    Zener current.  Each exponential is continued linearly beyond
    ``Maxexp`` (forward for ``v > Maxexp*Vt``, reverse for ``v + Bv <
    -Maxexp*Nbv*Vt``).  ``LossPower = v*i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.ZDiode"

    T = Parameter(293.15, unit="K", description="Fixed device temperature if useHeatPort = false")
    Ids = Parameter(1e-6, unit="A", description="Saturation current")
    Vt = Parameter(0.04, unit="V", description="Voltage equivalent of temperature (kT/qn)")
    Maxexp = Parameter(30.0, unit="1", min=_SMALL, description="Max. exponent for linear continuation")
    R = Parameter(1e8, unit="Ohm", description="Parallel ohmic resistance")
    Bv = Parameter(5.1, unit="V", description="Breakthrough voltage = Zener- or Z-voltage")
    Ibv = Parameter(0.7, unit="A", description="Breakthrough knee current")
    Nbv = Parameter(0.74, unit="1", description="Breakthrough emission coefficient")

    def equations(self):
        v, vt, m = self.v, self.Vt, self.Maxexp
        return [Eq(self.i, smooth(1, sp.Piecewise(
                    (self.Ids * (sp.exp(m) * (1 + v / vt - m) - 1) + v / self.R, v > m * vt),
                    (-self.Ids - self.Ibv * sp.exp(m) * (1 - (v + self.Bv) / (self.Nbv * vt) - m) + v / self.R,
                     (v + self.Bv) < -m * (self.Nbv * vt)),
                    (self.Ids * (sp.exp(v / vt) - 1) - self.Ibv * sp.exp(-(v + self.Bv) / (self.Nbv * vt))
                     + v / self.R, True)))),
                Eq(self.LossPower, v * self.i)]


# --------------------------------------------------------------------------
# MOS transistors


class _MOS(_TemperatureDependency):
    """What NMOS and PMOS share: pins, parameters, the temperature laws and the pin currents.

    The drain current ``id`` of the Shichman-Hodges model is the subclass's
    (:meth:`channel`): it sorts drain and source by potential so that the
    transistor conducts both ways.
    """

    modelica_name = None

    D = Pin(description="Drain")
    G = Pin(description="Gate")
    S = Pin(description="Source")
    B = Pin(description="Bulk")
    W = Parameter(20e-6, unit="m", description="Width")
    L = Parameter(6e-6, unit="m", description="Length")
    Beta = Parameter(None, unit="A/V2", description="Transconductance parameter")
    Vt = Parameter(None, unit="V", description="Zero bias threshold voltage")
    K2 = Parameter(None, unit="1", description="Bulk threshold parameter")
    K5 = Parameter(None, unit="1", description="Reduction of pinch-off region")
    dW = Parameter(-2.5e-6, unit="m", description="Narrowing of channel")
    dL = Parameter(None, unit="m", description="Shortening of channel")
    RDS = Parameter(1e7, unit="Ohm", description="Drain-Source-Resistance")
    Tnom = Parameter(300.15, unit="K", description="Parameter measurement temperature")
    # the MSL declares kvt and kk2 plain Reals; each multiplies a temperature difference
    kvt = Parameter(None, unit="1/K", description="Fitting parameter for Vt")
    kk2 = Parameter(None, unit="1/K", description="Fitting parameter for K2")
    v = Variable(unit="A/V2", description="Effective transconductance beta_t*(W + dW)/(L + dL)")
    uds = Variable(unit="V", description="Drain-source voltage of the sorted pins")
    ubs = Variable(unit="V", description="Bulk-source voltage (limited)")
    ugst = Variable(unit="V", description="Gate-source voltage above threshold, times K5")
    ud = Variable(unit="V", description="Potential of the drain side")
    us = Variable(unit="V", description="Potential of the source side")
    id = Variable(unit="A", description="Drain current")
    gds = Variable(unit="S", description="Drain-source conductance")
    beta_t = Variable(unit="A/V2", description="Temperature dependent transconductance")
    vt_t = Variable(unit="V", description="Temperature dependent threshold voltage")
    k2_t = Variable(unit="1", description="Temperature dependent bulk threshold parameter")

    #: "NMOS" or "PMOS", in the assertion messages as in the MSL.
    _kind = ""

    def drain_is_source(self) -> sp.Basic:
        """The relation under which drain and source swap roles (override)."""
        raise NotImplementedError

    def channel(self) -> list[sp.Basic]:
        """The equations of ``ubs`` and ``id`` (override)."""
        raise NotImplementedError

    def equations(self):
        swapped = self.drain_is_source()
        temperature = self.T_heatPort
        if self.useTemperatureDependency:
            laws = [Eq(self.beta_t, self.Beta * (temperature / self.Tnom) ** sp.Rational(-3, 2)),
                    Eq(self.vt_t, self.Vt * (1 + (temperature - self.Tnom) * self.kvt)),
                    Eq(self.k2_t, self.K2 * (1 + (temperature - self.Tnom) * self.kk2))]
        else:
            laws = [Eq(self.beta_t, self.Beta), Eq(self.vt_t, self.Vt), Eq(self.k2_t, self.K2)]
        return [Assert(self.L + self.dL > 0, f"{self._kind}: Effective length must be positive"),
                Assert(self.W + self.dW > 0, f"{self._kind}: Effective width must be positive"),
                Assert(temperature > 0, f"{self._kind}: Temperature must be positive"),
                # a zero RDS means a short: the MSL takes a large conductance instead of dividing by zero
                Eq(self.gds, sp.Piecewise((1e20, (self.RDS < 1e-20) & (self.RDS > -1e-20)), (1 / self.RDS, True))),
                Eq(self.v, self.beta_t * (self.W + self.dW) / (self.L + self.dL)),
                Eq(self.ud, smooth(0, sp.Piecewise((self.S.v, swapped), (self.D.v, True)))),
                Eq(self.us, smooth(0, sp.Piecewise((self.D.v, swapped), (self.S.v, True)))),
                Eq(self.uds, self.ud - self.us),
                Eq(self.ugst, (self.G.v - self.us - self.vt_t + self.k2_t * self.ubs) * self.K5),
                *self.channel(),
                *laws,
                Eq(self.G.i, 0),
                Eq(self.D.i, smooth(0, sp.Piecewise((-self.id, swapped), (self.id, True)))),
                Eq(self.S.i, smooth(0, sp.Piecewise((self.id, swapped), (-self.id, True)))),
                Eq(self.B.i, 0),
                Eq(self.LossPower, self.D.i * (self.D.v - self.S.v))]


class NMOS(_MOS):
    """Simple NMOS transistor with heating port (Modelica.Electrical.Analog.Semiconductors.NMOS).

    Shichman-Hodges: with ``ugst = (G.v - us - Vt + K2*ubs)*K5`` and ``v =
    Beta*(W + dW)/(L + dL)``, the drain current is ``uds*gds`` when cut off
    (``ugst <= 0``), ``v*uds*(ugst - uds/2) + uds*gds`` in the linear region
    (``ugst > uds``) and ``v*ugst^2/2 + uds*gds`` in saturation; ``us`` and
    ``ud`` are the lower and higher of the source and drain potentials, and
    the bulk voltage ``ubs`` is ``B.v - us`` limited to ``<= 0``.  With
    ``useTemperatureDependency`` Beta, Vt and K2 follow the heat port's
    temperature.  ``LossPower = D.i*(D.v - S.v)``.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.NMOS"
    _kind = "NMOS"

    Beta = Parameter(0.041e-3, unit="A/V2", description="Transconductance parameter")
    Vt = Parameter(0.8, unit="V", description="Zero bias threshold voltage")
    K2 = Parameter(1.144, unit="1", description="Bulk threshold parameter")
    K5 = Parameter(0.7311, unit="1", description="Reduction of pinch-off region")
    dL = Parameter(-1.5e-6, unit="m", description="Shortening of channel")
    kvt = Parameter(-6.96e-3, unit="1/K", description="Fitting parameter for Vt")
    kk2 = Parameter(6e-4, unit="1/K", description="Fitting parameter for K2")

    def drain_is_source(self) -> sp.Basic:
        return self.D.v < self.S.v

    def channel(self) -> list[sp.Basic]:
        uds, ugst = self.uds, self.ugst
        return [Eq(self.ubs, smooth(0, sp.Piecewise((0, self.B.v > self.us), (self.B.v - self.us, True)))),
                Eq(self.id, smooth(0, sp.Piecewise(
                    (uds * self.gds, ugst <= 0),
                    (self.v * uds * (ugst - uds / 2) + uds * self.gds, ugst > uds),
                    (self.v * ugst * ugst / 2 + uds * self.gds, True))))]


class PMOS(_MOS):
    """Simple PMOS transistor with heating port (Modelica.Electrical.Analog.Semiconductors.PMOS).

    The mirror of :class:`NMOS`: ``us`` and ``ud`` are the higher and lower of
    the source and drain potentials, ``ubs = B.v - us`` limited to ``>= 0``,
    and the drain current is ``uds*gds`` when cut off (``ugst >= 0``),
    ``-v*uds*(ugst - uds/2) + uds*gds`` in the linear region (``ugst < uds``)
    and ``-v*ugst^2/2 + uds*gds`` in saturation.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.PMOS"
    _kind = "PMOS"

    Beta = Parameter(0.0105e-3, unit="A/V2", description="Transconductance parameter")
    Vt = Parameter(-1.0, unit="V", description="Zero bias threshold voltage")
    K2 = Parameter(0.41, unit="1", description="Bulk threshold parameter")
    K5 = Parameter(0.839, unit="1", description="Reduction of pinch-off region")
    dL = Parameter(-2.1e-6, unit="m", description="Shortening of channel")
    kvt = Parameter(-2.9e-3, unit="1/K", description="Fitting parameter for Vt")
    kk2 = Parameter(6.2e-4, unit="1/K", description="Fitting parameter for K2")

    def drain_is_source(self) -> sp.Basic:
        return self.D.v > self.S.v

    def channel(self) -> list[sp.Basic]:
        uds, ugst = self.uds, self.ugst
        return [Eq(self.ubs, smooth(0, sp.Piecewise((0, self.B.v < self.us), (self.B.v - self.us, True)))),
                Eq(self.id, smooth(0, sp.Piecewise(
                    (uds * self.gds, ugst >= 0),
                    (-self.v * uds * (ugst - uds / 2) + uds * self.gds, ugst < uds),
                    (-self.v * ugst * ugst / 2 + uds * self.gds, True))))]


# --------------------------------------------------------------------------
# bipolar transistors


class _BJT(_TemperatureDependency):
    """What NPN and PNP share: parameters, pins, the temperature laws and the substrate.

    The collector-substrate capacitance ``Ccs`` carries ``iS = -Ccs*der(vcs)``;
    the substrate is grounded inside unless ``useSubstrate`` gives it the pin
    ``S`` (``S.i = iS``, ``S.v = vS``).  ``UIC`` starts ``vcs`` at ``IC``.
    """

    modelica_name = None

    Bf = Parameter(50.0, unit="1", description="Forward beta")
    Br = Parameter(0.1, unit="1", description="Reverse beta")
    Is = Parameter(1e-16, unit="A", description="Transport saturation current")
    Vak = Parameter(0.02, unit="1/V", description="Early voltage (inverse), 1/Volt")
    Tauf = Parameter(0.12e-9, unit="s", description="Ideal forward transit time")
    Taur = Parameter(5e-9, unit="s", description="Ideal reverse transit time")
    Ccs = Parameter(1e-12, unit="F", description="Collector-substrate(ground) cap.")
    Cje = Parameter(0.4e-12, unit="F", description="Base-emitter zero bias depletion cap.")
    Cjc = Parameter(0.5e-12, unit="F", description="Base-coll. zero bias depletion cap.")
    Phie = Parameter(0.8, unit="V", description="Base-emitter diffusion voltage")
    Me = Parameter(0.4, unit="1", description="Base-emitter gradation exponent")
    Phic = Parameter(0.8, unit="V", description="Base-collector diffusion voltage")
    Mc = Parameter(0.333, unit="1", description="Base-collector gradation exponent")
    Gbc = Parameter(1e-15, unit="S", description="Base-collector conductance")
    Gbe = Parameter(1e-15, unit="S", description="Base-emitter conductance")
    EMin = Parameter(-100.0, unit="1", description="If x < EMin, the exp(x) function is linearized")
    EMax = Parameter(40.0, unit="1", description="If x > EMax, the exp(x) function is linearized")
    Vt = Parameter(0.02585, unit="V", description="Voltage equivalent of temperature")
    Tnom = Parameter(300.15, unit="K", description="Parameter measurement temperature")
    XTI = Parameter(3.0, unit="1", description="Temperature exponent for effect on Is")
    XTB = Parameter(0.0, unit="1", description="Forward and reverse beta temperature exponent")
    EG = Parameter(1.11, unit="V", description="Energy gap for temperature effect on Is")
    NF = Parameter(1.0, unit="1", description="Forward current emission coefficient")
    NR = Parameter(1.0, unit="1", description="Reverse current emission coefficient")
    IC = Parameter(0.0, unit="V", description="Initial value of collector to substrate voltage")
    UIC = Parameter(False, structural=True, description="Decision if initial value IC should be used")
    useSubstrate = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                             description="= false, if substrate is implicitly grounded")

    vcs = Variable(unit="V", description="Collector-substrate voltage")
    qbk = Variable(unit="1", description="Relative majority carrier charge, inverse")
    Capcje = Variable(unit="F", description="Effective base-emitter depletion capacitance")
    Capcjc = Variable(unit="F", description="Effective base-collector depletion capacitance")
    is_t = Variable(unit="A", description="Temperature dependent transport saturation current")
    br_t = Variable(unit="1", description="Temperature dependent reverse beta")
    bf_t = Variable(unit="1", description="Temperature dependent forward beta")
    vt_t = Variable(unit="V", description="Voltage equivalent of effective temperature")
    hexp = Variable(unit="1", description="Auxiliary quantity temperature dependent exponent")
    htempexp = Variable(unit="1", description="Auxiliary quantity exp(hexp)")
    vS = Variable(unit="V", description="Substrate potential")  # noqa: N815 - Modelica name
    iS = Variable(unit="A", description="Substrate current")  # noqa: N815 - Modelica name

    C = Pin(description="Collector")
    B = Pin(description="Base")
    E = Pin(description="Emitter")
    S = NegativePin(condition="useSubstrate", description="Substrate")

    def initial_equations(self):
        return [Eq(self.vcs, self.IC)] if self.UIC else []

    def diode(self, voltage: sp.Basic, emission: sp.Basic) -> sp.Expr:
        """``exlin2(voltage/(emission*vt_t), EMin, EMax)``: a junction's exponential."""
        return exlin2(voltage / (emission * self.vt_t), self.EMin, self.EMax)

    def shared(self) -> list[Any]:
        """The equations of the temperature laws and the substrate."""
        temperature = self.T_heatPort
        ratio = temperature / self.Tnom
        if self.useTemperatureDependency:
            laws = [Eq(self.is_t, self.Is * ratio ** self.XTI * self.htempexp),
                    Eq(self.br_t, self.Br * ratio ** self.XTB),
                    Eq(self.bf_t, self.Bf * ratio ** self.XTB),
                    Eq(self.vt_t, _K_Q * temperature)]
        else:
            laws = [Eq(self.is_t, self.Is), Eq(self.br_t, self.Br), Eq(self.bf_t, self.Bf),
                    Eq(self.vt_t, self.Vt)]
        substrate = [Eq(self.S.i, self.iS), Eq(self.S.v, self.vS)] if self.useSubstrate else [Eq(self.vS, 0)]
        return [Assert(temperature > 0, "Temperature must be positive"),
                Eq(self.vcs, self.C.v - self.vS),
                Eq(self.hexp, (ratio - 1) * self.EG / self.vt_t),
                Eq(self.htempexp, smooth(1, exlin2(self.hexp, self.EMin, self.EMax))),
                *laws,
                Eq(self.iS, -self.Ccs * der(self.vcs)),
                *substrate]


class NPN(_BJT):
    """Simple NPN BJT according to Ebers-Moll with heating port (Modelica.Electrical.Analog.Semiconductors.NPN).

    The junction currents ``ibc = is_t*(exp(vbc/(NR*vt_t)) - 1) + vbc*Gbc``
    and ``ibe = is_t*(exp(vbe/(NF*vt_t)) - 1) + vbe*Gbe`` (exponentials
    continued linearly outside ``[EMin, EMax]``) give the collector current
    ``(ibe - ibc)*qbk - ibc/br_t`` and the base current ``ibe/bf_t +
    ibc/br_t`` (``qbk = 1 - vbc*Vak``: the Early effect), plus the currents
    of the junction capacitances (diffusion ``Tau*is_t/(N*vt_t)*exp(...)``
    and depletion ``Cj*(1 - v/Phi)^(-M)``, continued linearly in forward
    bias) and of the collector-substrate capacitance.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.NPN"

    vbc = Variable(unit="V", description="Base-collector voltage")
    vbe = Variable(unit="V", description="Base-emitter voltage")
    ibc = Variable(unit="A", description="Base-collector diode current")
    ibe = Variable(unit="A", description="Base-emitter diode current")
    cbc = Variable(unit="F", description="Total base-collector capacitance")
    cbe = Variable(unit="F", description="Total base-emitter capacitance")

    def equations(self):
        ebc, ebe = self.diode(self.vbc, self.NR), self.diode(self.vbe, self.NF)
        return [Eq(self.vbc, self.B.v - self.C.v),
                Eq(self.vbe, self.B.v - self.E.v),
                Eq(self.qbk, 1 - self.vbc * self.Vak),
                Eq(self.ibc, smooth(1, self.is_t * (ebc - 1) + self.vbc * self.Gbc)),
                Eq(self.ibe, smooth(1, self.is_t * (ebe - 1) + self.vbe * self.Gbe)),
                Eq(self.Capcjc, smooth(1, self.Cjc * powlin(self.vbc / self.Phic, self.Mc))),
                Eq(self.Capcje, smooth(1, self.Cje * powlin(self.vbe / self.Phie, self.Me))),
                Eq(self.cbc, smooth(1, self.Taur * self.is_t / (self.NR * self.vt_t) * ebc + self.Capcjc)),
                Eq(self.cbe, smooth(1, self.Tauf * self.is_t / (self.NF * self.vt_t) * ebe + self.Capcje)),
                Eq(self.C.i, (self.ibe - self.ibc) * self.qbk - self.ibc / self.br_t
                   - self.cbc * der(self.vbc) - self.iS),
                Eq(self.B.i, self.ibe / self.bf_t + self.ibc / self.br_t + self.cbc * der(self.vbc)
                   + self.cbe * der(self.vbe)),
                Eq(self.E.i, -self.B.i - self.C.i - self.iS),
                *self.shared(),
                Eq(self.LossPower, self.vbc * self.ibc / self.br_t + self.vbe * self.ibe / self.bf_t
                   + (self.ibe - self.ibc) * self.qbk * (self.C.v - self.E.v))]


class PNP(_BJT):
    """Simple PNP BJT according to Ebers-Moll with heating port (Modelica.Electrical.Analog.Semiconductors.PNP).

    The mirror of :class:`NPN` with the junction voltages ``vcb = C.v - B.v``
    and ``veb = E.v - B.v``: ``icb`` and ``ieb`` as NPN's ``ibc`` and
    ``ibe``, the collector current ``icb/br_t + (icb - ieb)*qbk`` and the base
    current ``-ieb/bf_t - icb/br_t`` (plus the capacitive currents).
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.PNP"

    vcb = Variable(unit="V", description="Collector-base voltage")
    veb = Variable(unit="V", description="Emitter-base voltage")
    icb = Variable(unit="A", description="Collector-base diode current")
    ieb = Variable(unit="A", description="Emitter-base diode current")
    ccb = Variable(unit="F", description="Total collector-base capacitance")
    ceb = Variable(unit="F", description="Total emitter-base capacitance")

    def equations(self):
        ecb, eeb = self.diode(self.vcb, self.NR), self.diode(self.veb, self.NF)
        return [Eq(self.vcb, self.C.v - self.B.v),
                Eq(self.veb, self.E.v - self.B.v),
                Eq(self.qbk, 1 - self.vcb * self.Vak),
                Eq(self.icb, smooth(1, self.is_t * (ecb - 1) + self.vcb * self.Gbc)),
                Eq(self.ieb, smooth(1, self.is_t * (eeb - 1) + self.veb * self.Gbe)),
                Eq(self.Capcjc, smooth(1, self.Cjc * powlin(self.vcb / self.Phic, self.Mc))),
                Eq(self.Capcje, smooth(1, self.Cje * powlin(self.veb / self.Phie, self.Me))),
                Eq(self.ccb, smooth(1, self.Taur * self.is_t / (self.NR * self.vt_t) * ecb + self.Capcjc)),
                Eq(self.ceb, smooth(1, self.Tauf * self.is_t / (self.NF * self.vt_t) * eeb + self.Capcje)),
                Eq(self.C.i, self.icb / self.br_t + self.ccb * der(self.vcb) + (self.icb - self.ieb) * self.qbk
                   - self.iS),
                Eq(self.B.i, -self.ieb / self.bf_t - self.icb / self.br_t - self.ceb * der(self.veb)
                   - self.ccb * der(self.vcb)),
                Eq(self.E.i, -self.B.i - self.C.i - self.iS),
                *self.shared(),
                Eq(self.LossPower, self.vcb * self.icb / self.br_t + self.veb * self.ieb / self.bf_t
                   + (self.icb - self.ieb) * self.qbk * (self.C.v - self.E.v))]


# --------------------------------------------------------------------------
# thyristors


class _ThyristorParameters(Component):
    """The parameters Thyristor and SimpleTriac share."""

    modelica_name = None

    VDRM = Parameter(100.0, unit="V", min=0, description="Forward breakthrough voltage")
    VRRM = Parameter(100.0, unit="V", min=0, description="Reverse breakthrough voltage")
    IDRM = Parameter(0.1, unit="A", description="Saturation current")
    VTM = Parameter(1.7, unit="V", description="Conducting voltage")
    IH = Parameter(6e-3, unit="A", description="Holding current")
    ITM = Parameter(25.0, unit="A", description="Conducting current")
    VGT = Parameter(0.7, unit="V", description="Gate trigger voltage")
    IGT = Parameter(5e-3, unit="A", description="Gate trigger current")
    TON = Parameter(1e-6, unit="s", description="Switch on time")
    TOFF = Parameter(15e-6, unit="s", description="Switch off time")
    Vt = Parameter(0.04, unit="V", description="Voltage equivalent of temperature (kT/qn)")
    Nbv = Parameter(0.74, unit="1", description="Reverse Breakthrough emission coefficient")


class Thyristor(DerivedDefaults, _ThyristorParameters, ConditionalHeatPort):
    """Simple Thyristor Model (Modelica.Electrical.Analog.Semiconductors.Thyristor).

    A control voltage ``vControl`` follows ``vContot`` with the time constant
    ``1.87*TON`` when rising and ``0.638*TOFF`` when falling.  ``vContot`` is
    ``Von`` while the anode current exceeds the holding current ``IH`` or the
    anode-cathode voltage exceeds ``VDRM`` (forward breakthrough), plus a
    term growing with ``vAK`` once the gate current reaches ``0.95*IGT``.
    The anode current is ``vAK/Roff`` below ``vControl = Voff``, ``vAK/Ron``
    above ``Von``, with a smooth log-resistance blend between, and the
    exponential reverse breakthrough below ``-VRRM``.  The gate is a
    resistor ``VGT/IGT`` up to ``vRef`` and flatter beyond.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.Thyristor"

    derived_defaults = {"Ron": lambda c: (c.VTM - 0.7) / c.ITM,
                        "Roff": lambda c: c.VDRM ** 2 / c.VTM / c.IH}

    vRef = Parameter(0.65, unit="V", description="Gate voltage where the gate characteristic bends")  # noqa: N815
    Von = Parameter(5.0, unit="V", description="Control voltage of the conducting state")
    Voff = Parameter(1.5, unit="V", description="Control voltage below which the thyristor blocks")
    Ron = Parameter(None, unit="Ohm", description="Forward conducting mode resistance (default (VTM - 0.7)/ITM)")
    Roff = Parameter(None, unit="Ohm", description="Blocking mode resistance (default VDRM^2/VTM/IH)")
    iGK = Variable(unit="A", description="Gate current")  # noqa: N815 - Modelica name
    vGK = Variable(unit="V", description="Voltage between gate and cathode")  # noqa: N815
    vAK = Variable(unit="V", description="Voltage between anode and cathode")  # noqa: N815
    vControl = Variable(unit="V", start=0.0, description="Control voltage")  # noqa: N815
    vContot = Variable(unit="V", description="Target of the control voltage")  # noqa: N815
    vConmain = Variable(unit="V", description="Main part of the control target (holding, breakthrough)")  # noqa: N815
    Anode = PositivePin(description="Anode")
    Cathode = NegativePin(description="Cathode")
    Gate = PositivePin(description="Gate")

    def equations(self):
        vak, igk, vcontrol = self.vAK, self.iGK, self.vControl
        von, voff, ron, roff = self.Von, self.Voff, self.Ron, self.Roff
        # position of vControl between Voff and Von, from -1 to 1; the blend of log(R) is a cubic in it
        x = (2 * vcontrol - von - voff) / (2 * (von - voff))
        blended = vak / (sp.sqrt(ron * roff) * (ron / roff) ** ((3 * x - 4 * x ** 3) / 2))
        gate_trigger = smooth(0, sp.Piecewise(
            (0, igk < 0.95 * self.IGT),
            (10000 * (igk - 0.95 * self.IGT) * vak, igk < 0.95 * self.IGT + 1e-3),
            (10 * vak, True)))
        return [Eq(self.Anode.i + self.Gate.i + self.Cathode.i, 0),
                Eq(self.vGK, self.Gate.v - self.Cathode.v),
                Eq(vak, self.Anode.v - self.Cathode.v),
                Eq(igk, self.Gate.i),
                Eq(self.vGK, smooth(0, sp.Piecewise(
                    (self.VGT / self.IGT * igk, self.vGK < self.vRef),
                    (self.vRef ** 2 / self.VGT + igk * (self.VGT - self.vRef) / self.IGT, True)))),
                Eq(self.vContot, self.vConmain + gate_trigger),
                # the relation of the time constant generates events (it is not inside smooth in the MSL)
                Eq(der(vcontrol), (self.vContot - vcontrol)
                   / sp.Piecewise((1.87 * self.TON, (self.vContot - vcontrol) > 0), (0.638 * self.TOFF, True))),
                Eq(self.Anode.i, smooth(1, sp.Piecewise(
                    (-self.VRRM / roff * sp.exp(-(vak + self.VRRM) / (self.Nbv * self.Vt)), vak < -self.VRRM),
                    (vak / roff, vcontrol < voff),
                    (blended, vcontrol < von),
                    (vak / ron, True)))),
                # holding effect and forward breakthrough
                Eq(self.vConmain, sp.Piecewise((von, (self.Anode.i > self.IH) | (vak > self.VDRM)), (0, True))),
                Eq(self.LossPower, self.Anode.i * self.Anode.v + self.Cathode.i * self.Cathode.v
                   + self.Gate.i * self.Gate.v)]


class SimpleTriac(_ThyristorParameters, ConditionalHeatPort):
    """Simple triac, based on Semiconductors.Thyristor model (Modelica.Electrical.Analog.Semiconductors.SimpleTriac).

    Two thyristors in antiparallel between ``p`` and ``n``, each gate fed
    from ``g`` through an ideal diode (``Vknee = 0``), so that a gate
    current fires the thyristor that is forward biased.  Both share the
    triac's parameters and heat port; ``LossPower = p.i*p.v + n.i*n.v +
    g.i*g.v``.
    """

    modelica_name = "Modelica.Electrical.Analog.Semiconductors.SimpleTriac"

    n = NegativePin(description="Cathode")
    p = PositivePin(description="Anode")
    g = PositivePin(description="Gate")

    def build(self):
        from .ideal import IdealDiode  # Analog.Ideal builds on the basic components only

        shared = {name: getattr(self, name) for name in
                  ("VDRM", "VRRM", "IDRM", "VTM", "IH", "ITM", "VGT", "IGT", "TON", "TOFF", "Vt", "Nbv", "T")}
        self.thyristor = Thyristor(useHeatPort=self.useHeatPort, **shared)
        self.thyristor1 = Thyristor(useHeatPort=self.useHeatPort, **shared)
        self.idealDiode = IdealDiode(Vknee=0)
        self.idealDiode1 = IdealDiode(Vknee=0)
        if self.useHeatPort:
            self.connect(self.heatPort, self.thyristor.heatPort)
            self.connect(self.heatPort, self.thyristor1.heatPort)
        self.connect(self.thyristor.Anode, self.n)
        self.connect(self.thyristor1.Anode, self.p)
        self.connect(self.thyristor1.Anode, self.thyristor.Cathode)
        self.connect(self.thyristor1.Cathode, self.thyristor.Anode)
        self.connect(self.thyristor.Gate, self.idealDiode.n)
        self.connect(self.idealDiode.p, self.g)
        self.connect(self.idealDiode1.n, self.thyristor1.Gate)
        self.connect(self.idealDiode1.p, self.g)

    def equations(self):
        return [Eq(self.LossPower, self.p.i * self.p.v + self.n.i * self.n.v + self.g.i * self.g.v)]
