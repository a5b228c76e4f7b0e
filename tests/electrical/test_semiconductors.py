"""Modelica.Electrical.Analog.Semiconductors against closed forms computed here with numpy.

The diode's Shockley law with its linear continuation beyond ``Maxexp``, the
Zener diode's three regions, the MOS drain current in cut-off, linear and
saturation regions (and with drain and source swapped), the NPN's
Ebers-Moll currents at a fixed operating point, the temperature law of the
heating diode, and the energy balance of a heating diode and a heating NMOS
(the heat stored equals the electrical energy dissipated).  Each formula is
written here from the MSL's documentation, not taken from the library.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from library_checks import check_declarations

from acausal import Model, simulate
from acausal.hybrid import without_no_event
from acausal.library.electrical import (
    NMOS,
    NPN,
    PMOS,
    PNP,
    ConstantVoltage,
    Diode,
    Diode2,
    Ground,
    RampVoltage,
    Resistor,
    SimpleTriac,
    SineVoltage,
    Thyristor,
    ZDiode,
)
from acausal.library.electrical.semiconductors import exlin, exlin2, powlin
from acausal.library.thermal import FixedTemperature, HeatCapacitor

K_Q = 1.380649e-23 / 1.602176634e-19  # Boltzmann constant / elementary charge (CODATA 2018, exact)


@pytest.mark.parametrize("component", [
    Diode(), Diode(useTemperatureDependency=True), Diode(useHeatPort=True),
    Diode2(), Diode2(useHeatPort=True), ZDiode(), ZDiode(useHeatPort=True),
    NMOS(), NMOS(useTemperatureDependency=True), PMOS(), PMOS(useTemperatureDependency=True),
    NPN(), NPN(useSubstrate=True, UIC=True), NPN(useTemperatureDependency=True),
    PNP(), PNP(useSubstrate=True), PNP(useTemperatureDependency=True),
    Thyristor(), Thyristor(useHeatPort=True), SimpleTriac(), SimpleTriac(useHeatPort=True),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced."""
    check_declarations(component)


def test_heat_port_follows_the_temperature_dependency_unless_given():
    assert Diode(useTemperatureDependency=True).useHeatPort is True
    assert Diode().useHeatPort is False
    assert Diode(useTemperatureDependency=True, useHeatPort=False).useHeatPort is False
    assert NPN(useTemperatureDependency=True).useHeatPort is True


# --------------------------------------------------------------------------
# the linear continuations


def _numeric(expr, *symbols):
    return sp.lambdify(symbols, without_no_event(expr), "math")


@pytest.mark.parametrize("x", [-120.0, -3.0, 0.0, 2.5, 14.9, 15.0, 15.1, 40.0, 1e3])
def test_exlin_functions_continue_the_exponential_by_its_tangent(x):
    s = sp.Symbol("x", real=True)
    f1, f2 = _numeric(exlin(s, 15), s), _numeric(exlin2(s, -100, 15), s)
    expected = math.exp(15) * (1 + x - 15) if x > 15 else math.exp(x)
    assert f1(x) == pytest.approx(expected, rel=1e-14)
    expected2 = math.exp(-100) * (1 + x + 100) if x < -100 else expected
    assert f2(x) == pytest.approx(expected2, rel=1e-14)


@pytest.mark.parametrize("x", [-2.0, -0.5, 0.0, 0.3, 2.0])
def test_powlin_continues_the_depletion_law_linearly(x):
    s = sp.Symbol("x", real=True)
    expected = 1 + 0.4 * x if x > 0 else (1 - x) ** -0.4
    assert _numeric(powlin(s, 0.4), s)(x) == pytest.approx(expected, rel=1e-14)


# --------------------------------------------------------------------------
# diodes


class DiodeSweep(Model):
    """A voltage ramp from v0 to v0 + dv over 1 s across one two-pin device."""

    def __init__(self, device, v0, dv, **kw):
        super().__init__(**kw)
        object.__setattr__(self, "_setup", (device, v0, dv))  # not a sub-component until build()

    def build(self):
        device, v0, dv = self._setup
        self.source = RampVoltage(V=dv, duration=1, offset=v0)
        self.d = device
        self.ground = Ground()
        self.connect(self.source.p, self.d.p)
        self.connect(self.d.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)


def test_diode_follows_shockley_and_its_linear_continuation():
    ids, vt, maxexp, r = 1e-6, 0.04, 15.0, 1e8
    result = simulate(DiodeSweep(Diode(Ids=ids, Vt=vt, Maxexp=maxexp, R=r), -1.0, 2.0), stop_time=1, interval=0.01)
    assert result.success, result.message
    v = result["d.v"]
    x = v / vt
    expected = ids * (np.where(x > maxexp, math.exp(maxexp) * (1 + x - maxexp), np.exp(np.minimum(x, maxexp))) - 1) + v / r
    assert (v > maxexp * vt).sum() > 10 and (v < 0).sum() > 10  # both ends of the characteristic are met
    np.testing.assert_allclose(result["d.i"], expected, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(result["d.LossPower"], v * expected, rtol=1e-9, atol=1e-15)


def test_zener_diode_breaks_down_beyond_bv():
    ids, vt, maxexp, r, bv, ibv, nbv = 1e-6, 0.04, 30.0, 1e8, 5.1, 0.7, 0.74
    result = simulate(DiodeSweep(ZDiode(), -6.5, 8.0), stop_time=1, interval=0.005)
    assert result.success, result.message
    v = result["d.v"]
    forward = v > maxexp * vt
    reverse = (v + bv) < -maxexp * nbv * vt
    with np.errstate(over="ignore"):
        middle = ids * (np.exp(v / vt) - 1) - ibv * np.exp(-(v + bv) / (nbv * vt)) + v / r
    expected = np.where(forward, ids * (math.exp(maxexp) * (1 + v / vt - maxexp) - 1) + v / r,
                        np.where(reverse, -ids - ibv * math.exp(maxexp) * (1 - (v + bv) / (nbv * vt) - maxexp) + v / r,
                                 middle))
    assert reverse.sum() > 3 and forward.sum() > 3
    np.testing.assert_allclose(result["d.i"], expected, rtol=1e-9, atol=1e-15)
    # a few tenths of a volt below -Bv the Zener current is already amperes, in reverse
    assert result["d.i"][np.argmin(np.abs(v + 5.6))] < -1.0


def test_diode2_pure_diode_and_series_resistance():
    """v = vd + id*Rs, i = id + v*Gp, id the Shockley law up to VdMax = Vf + Vt."""
    result = simulate(DiodeSweep(Diode2(), -2.0, 3.0), stop_time=1, interval=0.01)
    assert result.success, result.message
    vd, v = result["d.vd"], result["d.v"]
    ids, rs, gp, vt = 1e-13, 16.0, 1e-6, K_Q * 293.15
    vdmax = 0.7 + vt
    expected_id = np.where(vd < vdmax, ids * (np.exp(np.minimum(vd, vdmax) / vt) - 1),
                           ids * (math.exp(vdmax / vt) - 1) + (vd - vdmax) * ids * math.exp(vdmax / vt) / vt)
    np.testing.assert_allclose(result["d.id"], expected_id, rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(v, vd + expected_id * rs, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result["d.i"], expected_id + v * gp, rtol=1e-9, atol=1e-15)


class HeatedDiode(Model):
    def __init__(self, temperature, **kw):
        self._t = temperature
        super().__init__(**kw)

    def build(self):
        self.source = ConstantVoltage(V=0.3)
        self.d = Diode(useTemperatureDependency=True)
        self.ground = Ground()
        self.ambient = FixedTemperature(T=self._t)
        self.connect(self.source.p, self.d.p)
        self.connect(self.d.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.d.heatPort, self.ambient.port)


@pytest.mark.parametrize("temperature", [250.0, 300.15, 350.0])
def test_heating_diode_current_follows_its_temperature(temperature):
    """i = Ids*(exp(v/(N*k*T/q)) - 1)*(T/TNOM)^(XTI/N)*exp((T/TNOM - 1)*EG/(N*k*T/q)) + v/R."""
    result = simulate(HeatedDiode(temperature), stop_time=1, interval=0.5)
    vt = K_Q * temperature
    ratio = temperature / 300.15
    expected = 1e-6 * (math.exp(0.3 / vt) - 1) * ratio ** 3 * math.exp((ratio - 1) * 1.11 / vt) + 0.3 / 1e8
    assert result.final("d.vt_t") == pytest.approx(vt, rel=1e-12)
    assert result.final("d.i") == pytest.approx(expected, rel=1e-9)
    assert result.final("d.heatPort.Q_flow") == pytest.approx(-0.3 * expected, rel=1e-9)


# --------------------------------------------------------------------------
# heat balance


class HeatingRectifierLike(Model):
    """A sine through a heating diode into a resistor; the loss warms a heat capacitor."""

    def build(self):
        self.source = SineVoltage(V=1, f=1)
        self.d = Diode(useTemperatureDependency=True)
        self.load = Resistor(R=1)
        self.heat = HeatCapacitor(C=0.01, T=dict(start=293.15, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.d.p)
        self.connect(self.d.n, self.load.p)
        self.connect(self.load.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.d.heatPort, self.heat.port)


def _integral(t, y):
    return np.concatenate([[0], np.cumsum(np.diff(t) * (y[1:] + y[:-1]) / 2)])


def test_heating_diode_energy_goes_into_the_heat_capacitor():
    # max_step: the integrator must see every half wave (its one state barely moves between them)
    result = simulate(HeatingRectifierLike(), stop_time=1, interval=1e-3, method="BDF", rtol=1e-8, atol=1e-10,
                      max_step=1e-3)
    assert result.success, result.message
    t = result.time
    electrical = _integral(t, result["d.v"] * result["d.i"])
    heat = 0.01 * (result["heat.T"] - 293.15)
    assert heat[-1] > 0.05  # a sizeable effect, not rounding
    np.testing.assert_allclose(heat, electrical, rtol=0, atol=2e-4 * heat[-1])


class HeatingInverterLike(Model):
    """An NMOS switching a resistor load from a 5 V supply, its loss into a heat capacitor."""

    def build(self):
        self.supply = ConstantVoltage(V=5)
        self.gate = SineVoltage(V=5, f=2)
        self.load = Resistor(R=2e4)
        self.t = NMOS(useTemperatureDependency=True)
        self.heat = HeatCapacitor(C=1e-3, T=dict(start=300, fixed=True))
        self.ground = Ground()
        self.connect(self.supply.p, self.load.p)
        self.connect(self.load.n, self.t.D)
        self.connect(self.t.S, self.ground.p)
        self.connect(self.t.B, self.ground.p)
        self.connect(self.gate.p, self.t.G)
        self.connect(self.gate.n, self.ground.p)
        self.connect(self.supply.n, self.ground.p)
        self.connect(self.t.heatPort, self.heat.port)


def test_heating_nmos_energy_goes_into_the_heat_capacitor():
    result = simulate(HeatingInverterLike(), stop_time=1, interval=1e-3, method="BDF", rtol=1e-8, atol=1e-10,
                      max_step=1e-3)
    assert result.success, result.message
    t = result.time
    electrical = _integral(t, result["t.D.i"] * (result["t.D.v"] - result["t.S.v"]))
    heat = 1e-3 * (result["heat.T"] - 300)
    assert heat[-1] > 1e-5
    np.testing.assert_allclose(heat, electrical, rtol=0, atol=2e-3 * heat[-1])


# --------------------------------------------------------------------------
# MOS drain current (Shichman-Hodges)


class MOSBench(Model):
    """Gate, drain, source and bulk held by voltage sources (the drain swept by a ramp)."""

    def __init__(self, device, vg, vd0, dvd, vs=0.0, vb=0.0, **kw):
        super().__init__(**kw)
        object.__setattr__(self, "_setup", (device, vg, vd0, dvd, vs, vb))

    def build(self):
        device, vg, vd0, dvd, vs, vb = self._setup
        self.t = device
        self.vg = ConstantVoltage(V=vg)
        self.vd = RampVoltage(V=dvd, duration=1, offset=vd0)
        self.vs = ConstantVoltage(V=vs)
        self.vb = ConstantVoltage(V=vb)
        self.ground = Ground()
        for name, pin in (("vg", self.t.G), ("vd", self.t.D), ("vs", self.t.S), ("vb", self.t.B)):
            source = getattr(self, name)
            self.connect(source.p, pin)
            self.connect(source.n, self.ground.p)


def _nmos_current(vd, vg, vs, vb, beta=0.041e-3, vt=0.8, k2=1.144, k5=0.7311, w=20e-6, l=6e-6,
                  dw=-2.5e-6, dl=-1.5e-6, rds=1e7):
    """Drain current into D of the MSL's NMOS, for arrays of drain voltages."""
    swapped = vd < vs
    ud, us = np.where(swapped, vs, vd), np.where(swapped, vd, vs)
    uds = ud - us
    ubs = np.where(vb > us, 0.0, vb - us)
    ugst = (vg - us - vt + k2 * ubs) * k5
    gain = beta * (w + dw) / (l + dl)
    channel = np.where(ugst <= 0, 0.0, np.where(ugst > uds, gain * uds * (ugst - uds / 2), gain * ugst ** 2 / 2))
    drain = channel + uds / rds
    return np.where(swapped, -drain, drain), ugst, uds


def test_nmos_drain_current_in_its_three_regions_and_reversed():
    vg = 3.0
    result = simulate(MOSBench(NMOS(), vg, -2.0, 7.0), stop_time=1, interval=0.005)
    assert result.success, result.message
    vd = result["t.D.v"]
    expected, ugst, uds = _nmos_current(vd, vg, 0.0, 0.0)
    regions = {"reversed": vd < 0, "linear": (vd > 0) & (ugst > uds), "saturated": (vd > 0) & (ugst <= uds)}
    assert all(mask.sum() > 5 for mask in regions.values())
    np.testing.assert_allclose(result["t.D.i"], expected, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(result["t.S.i"], -expected, rtol=1e-9, atol=1e-15)
    assert np.all(result["t.G.i"] == 0) and np.all(result["t.B.i"] == 0)


def test_nmos_cut_off_leaves_only_rds_and_the_bulk_raises_the_threshold():
    result = simulate(MOSBench(NMOS(), 0.5, 0.0, 5.0), stop_time=1, interval=0.05)  # vg below Vt: cut off
    np.testing.assert_allclose(result["t.D.i"], result["t.D.v"] / 1e7, rtol=1e-12, atol=1e-18)
    biased = simulate(MOSBench(NMOS(), 3.0, 0.0, 5.0, vb=-1.0), stop_time=1, interval=0.05)
    expected, _, _ = _nmos_current(biased["t.D.v"], 3.0, 0.0, -1.0)
    np.testing.assert_allclose(biased["t.D.i"], expected, rtol=1e-9, atol=1e-15)


def test_pmos_drain_current_mirrors_the_nmos_law():
    """The MSL's PMOS: us/ud the higher/lower of S and D, ubs >= 0, id = -v*... (written here directly)."""
    beta, vt, k2, k5, w, l, dw, dl, rds = 0.0105e-3, -1.0, 0.41, 0.839, 20e-6, 6e-6, -2.5e-6, -2.1e-6, 1e7
    vs, vg, vb = 5.0, 1.0, 5.0
    result = simulate(MOSBench(PMOS(), vg, 7.0, -7.0, vs=vs, vb=vb), stop_time=1, interval=0.005)
    assert result.success, result.message
    vd = result["t.D.v"]
    swapped = vd > vs
    ud, us = np.where(swapped, vs, vd), np.where(swapped, vd, vs)
    uds = ud - us
    ubs = np.where(vb < us, 0.0, vb - us)
    ugst = (vg - us - vt + k2 * ubs) * k5
    gain = beta * (w + dw) / (l + dl)
    current = np.where(ugst >= 0, uds / rds, np.where(ugst < uds, -gain * uds * (ugst - uds / 2) + uds / rds,
                                                        -gain * ugst ** 2 / 2 + uds / rds))
    expected = np.where(swapped, -current, current)
    assert ((ugst < uds) & ~swapped).sum() > 5 and ((ugst >= uds) & ~swapped).sum() > 5 and swapped.sum() > 5
    np.testing.assert_allclose(result["t.D.i"], expected, rtol=1e-9, atol=1e-15)


# --------------------------------------------------------------------------
# bipolar transistors (Ebers-Moll)


class BJTBench(Model):
    """Base, collector and emitter held at constant voltages: the capacitive currents vanish."""

    def __init__(self, device, vb, vc, ve, **kw):
        super().__init__(**kw)
        object.__setattr__(self, "_setup", (device, vb, vc, ve))

    def build(self):
        device, *values = self._setup
        self.t = device
        self.ground = Ground()
        for name, value, pin in zip(("sb", "sc", "se"), values, (self.t.B, self.t.C, self.t.E)):
            setattr(self, name, ConstantVoltage(V=value))
            self.connect(getattr(self, name).p, pin)
            self.connect(getattr(self, name).n, self.ground.p)


def _ebers_moll(vbc, vbe, bf=50.0, br=0.1, is_=1e-16, vak=0.02, vt=0.02585, gbc=1e-15, gbe=1e-15):
    def junction(v):
        x = v / vt
        return is_ * ((math.exp(40) * (1 + x - 40) if x > 40 else math.exp(x)) - 1)
    ibc = junction(vbc) + vbc * gbc
    ibe = junction(vbe) + vbe * gbe
    qbk = 1 - vbc * vak
    return (ibe - ibc) * qbk - ibc / br, ibe / bf + ibc / br


@pytest.mark.parametrize("vb, vc, ve", [(0.7, 5.0, 0.0), (0.75, 0.3, 0.0), (0.0, 5.0, 0.0), (1.2, 3.0, 0.0)])
def test_npn_collector_and_base_currents_follow_ebers_moll(vb, vc, ve):
    result = simulate(BJTBench(NPN(), vb, vc, ve), stop_time=1e-6, interval=5e-7)
    assert result.success, result.message
    ic, ib = _ebers_moll(vb - vc, vb - ve)
    assert result.final("t.C.i") == pytest.approx(ic, rel=1e-9, abs=1e-20)
    assert result.final("t.B.i") == pytest.approx(ib, rel=1e-9, abs=1e-20)
    assert result.final("t.E.i") == pytest.approx(-ic - ib, rel=1e-9, abs=1e-20)


def test_pnp_is_the_mirror_of_the_npn():
    """All voltages negated: the PNP's currents are the NPN's, negated."""
    result = simulate(BJTBench(PNP(), -0.7, -5.0, 0.0), stop_time=1e-6, interval=5e-7)
    ic, ib = _ebers_moll(0.7 - 5.0, 0.7)
    assert result.final("t.C.i") == pytest.approx(-ic, rel=1e-9)
    assert result.final("t.B.i") == pytest.approx(-ib, rel=1e-9)


# --------------------------------------------------------------------------
# the engine's tearing, which the MOS heat loop relies on


def test_tearing_prefers_solutions_that_divide_by_no_unknown():
    """A loop T -> id -> D.i -> P -> T: with T torn, P = D.i*u is the residual, not solved for D.i.

    e0: T = T0 + P; e1: P = Di*u (u an unknown outside the chain, possibly
    zero); e2: id = f(T); e3: Di = id.  Once T is torn, e1 could give Di
    before e3 does (block order); the safe solution from e3 is taken instead.
    """
    from acausal.compiler.algebraic import tear

    incidence = [{3, 0}, {2, 3}, {0, 1}, {1, 2}]  # unknowns: 0 T, 1 id, 2 Di, 3 P
    unsafe = {(1, 2)}
    solved, tears, residuals = tear(incidence, 4, lambda i, j: True, lambda i, j: (i, j) not in unsafe)
    assert tears == [0] and (1, 2) not in solved and residuals == [1]
    # without the preference, block order would have divided by u
    solved, _, _ = tear(incidence, 4, lambda i, j: True)
    assert (1, 2) in solved
