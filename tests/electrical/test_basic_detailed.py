"""The detailed Analog.Basic classes and the remaining Analog.Sources against closed forms.

OpAmpDetailed in its linear range against a nodal analysis of the same
circuit written by hand (offset voltage, bias currents, common-mode and
differential input resistances, finite differential and common-mode gains,
output resistance), its open-loop DC gain against the parameter formulas,
its output clipped at the supply less ``vcp``, its output current at
``Imaxso``, and a large step of a voltage follower ramping at the slew rate.
M_Transformer for N = 2 and 3 against scipy's solution of ``Lm*di/dt = vs(t)
- R*i`` written by hand, with ``Lm`` built from ``L`` by hand.
LightningImpulse (Heidler and double exponential) against its data-sheet
definition measured on the trajectory (peak = amplitude, 10 % to 90 % in
0.8*T1, half value T2 after the virtual start); DCPowerSupply swept by a
load resistance through cv, cp and cc against the three laws' closed forms.
"""

from __future__ import annotations

import numpy as np
import pytest
from library_checks import check_declarations

from acausal import Model, simulate
from scipy.integrate import solve_ivp

from acausal.library.blocks import Ramp
from acausal.library.electrical import (
    ConstantVoltage,
    DCPowerSupply,
    Ground,
    ImpulseApproximation,
    LightningImpulse,
    LightningImpulseCurrent,
    LightningImpulseVoltage,
    M_Transformer,
    OpAmpDetailed,
    Resistor,
    SineVoltage,
    StepVoltage,
    VariableResistor,
)

# --------------------------------------------------------------------------
# declarations


@pytest.mark.parametrize("component", [
    OpAmpDetailed(), OpAmpDetailed(Avd0=80, CMRR=70, vcp=1, vcm=-1, sr_p=1e6, sr_m=-2e5),
    M_Transformer(), M_Transformer(N=2, L=[1.0, 0.5, 2.0]), M_Transformer(N=1, L=[0.3]),
    LightningImpulse(), LightningImpulse(approximation=ImpulseApproximation.DoubleExp, amplitude=2, m=7),
    LightningImpulseVoltage(V=100, approximation=ImpulseApproximation.DoubleExp),
    LightningImpulseCurrent(I=2, T1=8e-6, T2=20e-6),
    DCPowerSupply(), DCPowerSupply(V0=30, I0=5, P0=200),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced, every Boolean defined once."""
    check_declarations(component)


# --------------------------------------------------------------------------
# OpAmpDetailed

# the MSL leaves five of the op-amp's states to their start values (0): acausal warns, as it should
pytestmark = pytest.mark.filterwarnings("ignore::acausal.errors.StartValueWarning")

SUPPLY = 15.0


class _Supplied(Model):
    """An OpAmpDetailed on a +-15 V supply; ``circuit()`` adds the rest."""

    opamp_modifiers: dict = {}

    def build(self):
        self.opamp = OpAmpDetailed(**self.opamp_modifiers)
        self.positive = ConstantVoltage(V=SUPPLY)
        self.negative = ConstantVoltage(V=SUPPLY)
        self.ground = Ground()
        self.connect(self.positive.p, self.opamp.p_supply)
        self.connect(self.positive.n, self.ground.p)
        self.connect(self.negative.n, self.opamp.m_supply)
        self.connect(self.negative.p, self.ground.p)
        self.circuit()

    def circuit(self):
        raise NotImplementedError


# default data sheet values (the MSL's defaults)
VOS, IB, IOS, RDM, RCM, ROUT = 1e-3, 80e-9, 20e-9, 2e6, 2e9, 75.0
AVD = 10 ** (106 / 20)
AVCM = AVD / 10 ** (90 / 20) / 2
I1, I2 = IB + IOS / 2, IB - IOS / 2

R1, R2, VIN = 1e3, 10e3, 0.5


class InvertingAmplifier(_Supplied):
    """0.5 V through R1 = 1 kOhm into m, R2 = 10 kOhm from the output back to m, p grounded."""

    def circuit(self):
        self.source = ConstantVoltage(V=VIN)
        self.r1 = Resistor(R=R1)
        self.r2 = Resistor(R=R2)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.source.p, self.r1.p)
        self.connect(self.r1.n, self.opamp.m)
        self.connect(self.opamp.m, self.r2.p)
        self.connect(self.r2.n, self.opamp.outp)
        self.connect(self.opamp.p, self.ground.p)


def _inverting_amplifier_dc() -> tuple[float, float]:
    """(v_m, v_out) of the inverting amplifier at DC, from the macromodel's stages written out by hand.

    p is grounded: the internal node behind the offset source is at ``v3 =
    -Vos``; ``v_in = v3 - v_m``; the pin m draws ``I2 + v_m/Rcm - v_in/Rdm``;
    the internal source is ``Avd*v_in + Avcm*(v3 + v_m)`` behind ``Rout``.
    """
    v3 = -VOS
    # unknowns (v_m, v_out); KCL at m, KCL at the output
    a = np.array([
        [-1 / R1 - 1 / R2 - 1 / RCM - 1 / RDM, 1 / R2],
        [-1 / R2 + (AVD - AVCM) / ROUT, 1 / R2 + 1 / ROUT],
    ])
    b = np.array([
        -VIN / R1 + I2 - v3 / RDM,
        (AVD * v3 + AVCM * v3) / ROUT,
    ])
    v_m, v_out = np.linalg.solve(a, b)
    return float(v_m), float(v_out)


def test_inverting_amplifier_settles_at_the_nodal_solution():
    """The closed-loop DC output agrees with the hand-written nodal analysis to 1e-8 relative."""
    result = simulate(InvertingAmplifier(), stop_time=200e-6, interval=1e-6, rtol=1e-8, atol=1e-10,
                      method="LSODA")
    assert result.success, result.message
    v_m, v_out = _inverting_amplifier_dc()
    assert result.final("opamp.v_out") == pytest.approx(v_out, rel=1e-8)
    assert result.final("opamp.m.v") == pytest.approx(v_m, rel=1e-6)
    # close to the ideal -R2/R1*vin, off by the offset voltage times the noise gain 1 + R2/R1
    assert v_out == pytest.approx(-R2 / R1 * VIN - (1 + R2 / R1) * VOS, rel=1e-3)


RLOAD = 10e3


class OpenLoop(_Supplied):
    """p driven by ``vp``, m grounded, the output loaded by 10 kOhm."""

    vp = VOS + 20e-6

    def circuit(self):
        self.source = ConstantVoltage(V=self.vp)
        self.load = Resistor(R=RLOAD)
        self.connect(self.source.p, self.opamp.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.opamp.m, self.ground.p)
        self.connect(self.opamp.outp, self.load.p)
        self.connect(self.load.n, self.ground.p)


def test_open_loop_dc_gain_follows_the_parameter_formulas():
    """v_source = Avd0_val*v_in + Avcm_val*(v_3 + v_4), Avd0_val = 10^(Avd0/20), Avcm_val = Avd0_val/10^(CMRR/20)/2."""
    # the dominant pole at fp1 = 5 Hz: 1 s is 31 time constants
    result = simulate(OpenLoop(), stop_time=1.0, interval=1e-3, rtol=1e-9, atol=1e-12, method="LSODA")
    assert result.success, result.message
    assert result.final("opamp.Avd0_val") == pytest.approx(AVD, rel=1e-12)
    assert result.final("opamp.Avcm_val") == pytest.approx(AVCM, rel=1e-12)
    v_in = OpenLoop.vp - VOS  # p driven, m grounded: Vos in series with p, then Rdm
    v_source = AVD * v_in + AVCM * (OpenLoop.vp - VOS + 0.0)
    assert result.final("opamp.v_in") == pytest.approx(v_in, rel=1e-9)
    assert result.final("opamp.v_source") == pytest.approx(v_source, rel=1e-6)
    # the output resistance and the load divide it
    v_out = v_source * RLOAD / (RLOAD + ROUT)
    assert result.final("opamp.v_out") == pytest.approx(v_out, rel=1e-6)
    # the dominant pole: after one time constant 1/(2*pi*fp1) the output has 1 - 1/e of its final value
    # (the MHz poles and the slew stage are done within microseconds)
    tau = 1 / (2 * np.pi * 5.0)
    assert np.interp(tau, result.time, result["opamp.v_out"]) == pytest.approx(v_out * (1 - np.exp(-1)), rel=1e-3)


@pytest.mark.parametrize("sign", [1, -1])
def test_overdriven_output_stops_at_the_supply_less_the_correction(sign):
    """Overdriven, the internal source stops at v_pos - |vcp| (v_neg + |vcm|)."""

    class Overdriven(OpenLoop):
        opamp_modifiers = dict(vcp=1.0, vcm=-2.0)
        vp = sign * 0.1

    # BDF: at the rail the gain stage sits on the limiter's switching line (noEvent), where LSODA's
    # switch between its stiff and non-stiff methods crawls
    result = simulate(Overdriven(), stop_time=0.2, interval=1e-3, rtol=1e-8, atol=1e-10, method="BDF")
    assert result.success, result.message
    limit = SUPPLY - 1.0 if sign > 0 else -(SUPPLY - 2.0)
    assert result.final("opamp.v_source") == pytest.approx(limit, abs=1e-5)
    assert result.final("opamp.v_out") == pytest.approx(limit * RLOAD / (RLOAD + ROUT), abs=1e-5)


class Follower(_Supplied):
    """Voltage follower (outp fed back to m) under a step of ``height`` at 1 us, loaded by ``load``."""

    height = 5.0
    load = None

    def circuit(self):
        self.source = StepVoltage(V=self.height, startTime=1e-6)
        self.connect(self.source.p, self.opamp.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.opamp.outp, self.opamp.m)
        if self.load is not None:
            self.resistor = Resistor(R=self.load)
            self.connect(self.opamp.outp, self.resistor.p)
            self.connect(self.resistor.n, self.ground.p)


@pytest.mark.parametrize("height, sr_p, sr_m", [(5.0, 0.5e6, 0.5e6), (-6.0, 1e6, 0.25e6)])
def test_a_large_step_ramps_at_the_slew_rate(height, sr_p, sr_m):
    """The follower's output rises at sr_p (falls at sr_m) until it nears the new input."""

    class Slewing(Follower):
        opamp_modifiers = dict(sr_p=sr_p, sr_m=sr_m)

    Slewing.height = height
    rate = sr_p if height > 0 else -sr_m
    ramp = height / rate
    result = simulate(Slewing(), stop_time=1e-6 + 1.5 * ramp, interval=0.02e-6, rtol=1e-8, atol=1e-10,
                      method="LSODA")
    assert result.success, result.message
    # at the step, Cin couples the step to the output for a fraction of a nanosecond; then the ramp
    after = result.time > 1.01e-6
    t, v = result.time[after], result["opamp.v_out"][after]
    reached = np.abs(v) / abs(height)
    t20, t80 = t[np.argmax(reached > 0.2)], t[np.argmax(reached > 0.8)]
    inside = (t >= t20) & (t <= t80)
    slope = np.polyfit(t[inside], v[inside], 1)[0]
    assert slope == pytest.approx(rate, rel=1e-3)
    # the ramp starts at the step: 80 % reached at 1 us + 0.8*height/rate
    assert t80 == pytest.approx(1e-6 + 0.8 * ramp, abs=0.05e-6)
    # the internal source never moves faster than the slew rates, up or down (also while it rings in)
    dt = np.diff(result.time)
    slopes = np.diff(result["opamp.v_source"])[dt > 0] / dt[dt > 0]
    assert np.max(slopes) <= sr_p * (1 + 1e-6) and np.min(slopes) >= -sr_m * (1 + 1e-6)


def test_follower_settles_at_its_finite_gain_value():
    """v_out = (Avd + Avcm)*(vp - Vos)/(1 + Avd - Avcm), the pin currents through Rout negligible (1e-10)."""
    result = simulate(Follower(), stop_time=150e-6, interval=0.5e-6, rtol=1e-9, atol=1e-12, method="LSODA")
    assert result.success, result.message
    expected = (AVD + AVCM) * (Follower.height - VOS) / (1 + AVD - AVCM)
    assert result.final("opamp.v_out") == pytest.approx(expected, rel=1e-8)


def test_output_current_is_limited_to_imaxso():
    """5 V on 100 Ohm asks for 50 mA; the output delivers Imaxso = 25 mA, so about 2.5 V."""

    class Loaded(Follower):
        load = 100.0

    # BDF: the internal source sits at the rail (see the overdriven test)
    result = simulate(Loaded(), stop_time=50e-6, interval=0.1e-6, rtol=1e-9, atol=1e-12, method="BDF")
    assert result.success, result.message
    assert result.final("opamp.i_out") == pytest.approx(-25e-3, rel=1e-9)
    # the load also gets what flows from p through Rdm and leaves m (the loop is open, v_in = 2.5 V):
    # v/R = Imaxso - m.i with m.i = I2 + v/Rcm - (vp - Vos - v)/Rdm
    v = (25e-3 - I2 + (Follower.height - VOS) / RDM) / (1 / 100.0 + 1 / RCM + 1 / RDM)
    assert result.final("opamp.v_out") == pytest.approx(v, rel=1e-9)
    # the internal source ran into the rail
    assert result.final("opamp.v_source") == pytest.approx(SUPPLY, abs=1e-4)


# --------------------------------------------------------------------------
# M_Transformer


def _symmetric(upper_triangle: list[float], n: int) -> np.ndarray:
    """The symmetric n x n matrix whose upper triangle, row by row, is ``upper_triangle``."""
    matrix = np.zeros((n, n))
    rows, columns = np.triu_indices(n)
    matrix[rows, columns] = upper_triangle
    return matrix + np.triu(matrix, 1).T


class Coupled(Model):
    """Winding j of an M_Transformer fed by a sine source of amplitude V[j], frequency F[j] through R[j]."""

    inductances: list = [1.0, 0.1, 0.2, 2.0, 0.3, 3.0]
    V = [10.0, 0.0, 4.0]
    F = [1.0, 1.0, 3.0]
    R = [2.0, 5.0, 1.0]

    def build(self):
        n = len(self.V)
        self.transformer = M_Transformer(N=n, L=list(self.inductances))
        self.ground = Ground()
        self.source = [SineVoltage(V=self.V[j], f=self.F[j]) for j in range(n)]
        self.resistor = [Resistor(R=self.R[j]) for j in range(n)]
        for j in range(1, n + 1):
            self.connect(self.source[j].p, self.transformer.p[j])
            self.connect(self.transformer.n[j], self.resistor[j].p)
            self.connect(self.resistor[j].n, self.ground.p)
            self.connect(self.source[j].n, self.ground.p)


class CoupledTwo(Coupled):
    inductances = [1.0, 0.8, 2.0]  # coupling factor 0.8/sqrt(2) = 0.57
    V = [10.0, 0.0]
    F = [2.0, 2.0]
    R = [1.0, 4.0]


@pytest.mark.parametrize("model", [CoupledTwo, Coupled], ids=["N=2", "N=3"])
def test_m_transformer_solves_the_coupled_inductor_equations(model):
    """i(t) from Lm*di/dt = V*sin(2*pi*F*t) - R*i, i(0) = 0, solved by scipy."""
    n = len(model.V)
    lm = _symmetric(model.inductances, n)
    amplitude, frequency, resistance = np.array(model.V), np.array(model.F), np.array(model.R)

    def rhs(t, i):
        return np.linalg.solve(lm, amplitude * np.sin(2 * np.pi * frequency * t) - resistance * i)

    result = simulate(model(), stop_time=2.0, interval=0.002, rtol=1e-9, atol=1e-11)
    assert result.success, result.message
    t = result.time
    expected = solve_ivp(rhs, (0, 2.0), np.zeros(n), t_eval=t, rtol=1e-11, atol=1e-13).y
    for j in range(n):
        np.testing.assert_allclose(result[f"transformer.i[{j + 1}]"], expected[j], rtol=0, atol=1e-6)
    # Lm is filled from L at initialization, symmetric
    for row in range(n):
        for column in range(n):
            assert result.final(f"transformer.Lm[{row + 1},{column + 1}]") == pytest.approx(lm[row, column])
    # magnetic energy i'Lm i/2 = energy delivered to the windings (the integral of v'i)
    currents = np.column_stack([result[f"transformer.i[{j + 1}]"] for j in range(n)])
    power = sum(result[f"transformer.v[{j + 1}]"] * currents[:, j] for j in range(n))
    delivered = np.concatenate([[0], np.cumsum(np.diff(t) * (power[1:] + power[:-1]) / 2)])
    stored = 0.5 * np.einsum("ti,ij,tj->t", currents, lm, currents)
    np.testing.assert_allclose(stored, delivered, rtol=0, atol=1e-3 * np.max(stored))


# --------------------------------------------------------------------------
# LightningImpulse


def _crossing(t: np.ndarray, y: np.ndarray, level: float, rising: bool) -> float:
    """The first instant (linear interpolation) y crosses level upwards (rising) or downwards."""
    above = y >= level if rising else y <= level
    k = int(np.argmax(above))
    return float(t[k - 1] + (level - y[k - 1]) * (t[k] - t[k - 1]) / (y[k] - y[k - 1]))


@pytest.mark.parametrize("approximation", [ImpulseApproximation.Heidler, ImpulseApproximation.DoubleExp])
def test_lightning_impulse_meets_its_data_sheet_definition(approximation):
    """Peak offset + amplitude; 10 % to 90 % in 0.8*T1; 50 % on the tail at T2 after the virtual start."""
    amplitude, offset, start, t1, t2 = 3.0, 0.5, 20e-6, 1.2e-6, 50e-6

    class Impulse(Model):
        def build(self):
            self.lightning = LightningImpulse(approximation=approximation, amplitude=amplitude, offset=offset,
                                              startTime=start, T1=t1, T2=t2)

    result = simulate(Impulse(), stop_time=start + 3 * t2, interval=1e-9, rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    t, y = result.time, result["lightning.y"]
    assert np.all(y[t < start] == offset)
    assert y.max() == pytest.approx(offset + amplitude, rel=1e-6)
    impulse = (y - offset) / amplitude
    t10 = _crossing(t, impulse, 0.1, rising=True)
    t90 = _crossing(t, impulse, 0.9, rising=True)
    peak = t[np.argmax(impulse)]
    t50 = _crossing(t[t > peak], impulse[t > peak], 0.5, rising=False)
    assert t90 - t10 == pytest.approx(0.8 * t1, rel=1e-4)
    assert t50 - (t10 - 0.1 * t1) == pytest.approx(t2, rel=1e-5)
    # the shape between: the closed form with the parameters found at initialization
    eta, tau1, tau2 = (result.final(f"lightning.{name}") for name in ("eta", "tau1", "tau2"))
    s = np.clip(t - start, 0, None)
    if approximation == ImpulseApproximation.DoubleExp:
        shape = np.exp(-s / tau1) - np.exp(-s / tau2)
    else:
        shape = (s / tau1) ** 5 / (1 + (s / tau1) ** 5) * np.exp(-s / tau2)
    np.testing.assert_allclose(y[t >= start], offset + amplitude / eta * shape[t >= start], rtol=0, atol=1e-9)


def test_lightning_impulse_voltage_and_current_drive_a_resistor():
    """The sources hand V (I), T1, T2 to their LightningImpulse: v = R*i peaks at V (I)."""

    class Struck(Model):
        def build(self):
            self.voltage = LightningImpulseVoltage(V=100.0, T1=1.2e-6, T2=50e-6,
                                                   approximation=ImpulseApproximation.DoubleExp)
            self.current = LightningImpulseCurrent(I=2.0, T1=8e-6, T2=20e-6)  # the 8/20 us surge current
            self.r1 = Resistor(R=10.0)
            self.r2 = Resistor(R=5.0)
            self.ground = Ground()
            self.connect(self.voltage.p, self.r1.p)
            self.connect(self.r1.n, self.ground.p)
            self.connect(self.voltage.n, self.ground.p)
            self.connect(self.current.p, self.ground.p)
            self.connect(self.current.n, self.r2.p)
            self.connect(self.r2.n, self.ground.p)

    result = simulate(Struck(), stop_time=150e-6, interval=2e-9, rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    assert result["r1.v"].max() == pytest.approx(100.0, rel=1e-6)
    np.testing.assert_allclose(result["r1.i"], result["r1.v"] / 10.0, rtol=1e-12, atol=1e-12)
    assert result["r2.i"].max() == pytest.approx(2.0, rel=1e-6)
    assert result.final("voltage.signalSource.T1") == pytest.approx(1.2e-6)
    assert result.final("current.signalSource.T2") == pytest.approx(20e-6)


# --------------------------------------------------------------------------
# DCPowerSupply


class SupplySweep(Model):
    """The default supply (60 V, 50 A, 1200 W) loaded by a resistance falling from 10 to 0.1 Ohm in 1 s."""

    def build(self):
        self.supply = DCPowerSupply()
        self.load = VariableResistor()
        self.resistance = Ramp(height=-9.9, duration=1.0, offset=10.0)
        self.ground = Ground()
        self.connect(self.resistance.y, self.load.R)
        self.connect(self.supply.p, self.load.p)
        self.connect(self.load.n, self.supply.n)
        self.connect(self.supply.n, self.ground.p)


def test_dc_power_supply_follows_cv_cp_cc():
    """v(R) from the three laws, switching where the cv and cc lines deliver P0."""
    v0, i0, p0, rcv, gcc = 60.0, 50.0, 1200.0, 1e-3, 1e-3
    result = simulate(SupplySweep(), stop_time=1.0, interval=1e-3, rtol=1e-10, atol=1e-10)
    assert result.success, result.message
    # the corner of the cv and cc lines delivers more than P0: the limits are where each line delivers P0
    assert (v0 - rcv * i0) / (1 - rcv * gcc) * (i0 - gcc * v0) / (1 - gcc * rcv) > p0
    i_lim = (v0 - np.sqrt(v0 ** 2 - 4 * rcv * p0)) / (2 * rcv)
    v_lim = (i0 - np.sqrt(i0 ** 2 - 4 * gcc * p0)) / (2 * gcc)
    r = result["load.R"]
    cv = v0 / (1 + rcv / r)                         # v = V0 - Rcv*v/R
    cp = np.sqrt(p0 * r)                            # v^2/R = P0
    cc = i0 / (1 / r + gcc)                         # v/R = I0 - Gcc*v
    expected = np.where(cv / r <= i_lim, cv, np.where(cp <= v_lim, cc, cp))
    np.testing.assert_allclose(result["supply.v"], expected, rtol=1e-9)
    np.testing.assert_allclose(result["supply.P"], -result["supply.v"] ** 2 / r, rtol=1e-9)
    # the switching instants: cv ends at R = V0/iLim - Rcv, cc begins at R = v_lim^2/P0
    leave_cv = next(e.time for e in result.events if ("supply.cv", True, False) in e.changes)
    enter_cc = next(e.time for e in result.events if ("supply.cc", False, True) in e.changes)
    assert 10.0 - 9.9 * leave_cv == pytest.approx(v0 / i_lim - rcv, rel=1e-8)
    assert 10.0 - 9.9 * enter_cc == pytest.approx(v_lim ** 2 / p0, rel=1e-8)
