"""Sources of Modelica.Blocks.Sources against closed forms.

KinematicPTP and KinematicPTP2 against the bang-bang (or
accelerate-cruise-decelerate) profile written out here from the limits;
Sinc against sin(x)/x; Exponentials, LogFrequencySweep and the sines of
variable frequency and amplitude against their formulas; the Integer sources
and the Real/Integer/Boolean expressions against the values they are given.
ModelicaTest.Blocks.KinematicPTP and Modelica.Blocks.Examples.CompareSincExpSine
lie in the csv-compare tube of the MSL references (tests/test_reference.py).

The test marked xfail(strict=True) names an engine limitation found while
writing the blocks: it starts passing (and must lose its mark) when it is fixed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Experiment, If, Model, simulate, time
from acausal.errors import ArraySizeError
from acausal.library.blocks import Constant, Integrator, Ramp
from acausal.library.blocks.booleans import BooleanExpression, RadioButtonSource
from acausal.library.blocks.sources import (CosineVariableFrequencyAndAmplitude, Exponentials, IntegerConstant,
                                            IntegerExpression, IntegerStep, KinematicPTP, KinematicPTP2,
                                            LogFrequencySweep, RealExpression, Sinc,
                                            SineVariableFrequencyAndAmplitude)


def _model(build, stop_time: float = 3.0, interval: float = 0.001) -> Model:
    """A model whose build() is ``build(self)``."""
    klass = type("Harness", (Model,), {"experiment": Experiment(stop_time=stop_time, interval=interval),
                                       "build": build})
    return klass()


def ptp_profile(t: np.ndarray, distance: float, v_max: float, a_max: float, t0: float):
    """Position, speed, acceleration and end time of the fastest motion over ``distance``
    with |speed| <= v_max and |acceleration| <= a_max, starting at rest at t0.

    Without a cruise (distance < v_max^2/a_max) it accelerates for sqrt(d/a) and
    decelerates as long; otherwise it accelerates for v/a, cruises for d/v - v/a and
    decelerates for v/a.
    """
    d, sign = abs(distance), math.copysign(1.0, distance)
    if d < v_max ** 2 / a_max:
        t_acc, t_cruise = math.sqrt(d / a_max), 0.0
    else:
        t_acc, t_cruise = v_max / a_max, d / v_max - v_max / a_max
    v_top = a_max * t_acc
    t_end = 2 * t_acc + t_cruise
    tau = np.clip(t - t0, 0.0, t_end)
    in_acc = tau < t_acc
    in_cruise = (tau >= t_acc) & (tau < t_acc + t_cruise)
    dec = np.maximum(tau - t_acc - t_cruise, 0.0)
    position = np.where(in_acc, a_max * tau ** 2 / 2,
                        np.where(in_cruise, a_max * t_acc ** 2 / 2 + v_top * (tau - t_acc),
                                 a_max * t_acc ** 2 / 2 + v_top * t_cruise + v_top * dec - a_max * dec ** 2 / 2))
    speed = np.where(in_acc, a_max * tau, np.where(in_cruise, v_top, v_top - a_max * dec))
    moving = (t >= t0) & (t - t0 < t_end)
    acceleration = np.where(~moving, 0.0, np.where(in_acc, a_max, np.where(in_cruise, 0.0, -a_max)))
    return sign * position, sign * speed, sign * acceleration, t0 + t_end


def _away_from(t: np.ndarray, instants, width: float = 1e-9) -> np.ndarray:
    """Mask of the times not at a switching instant (where the left and right values differ)."""
    mask = np.ones_like(t, dtype=bool)
    for instant in instants:
        mask &= np.abs(t - instant) > width
    return mask


# --------------------------------------------------------------------------
# KinematicPTP / KinematicPTP2


@pytest.mark.parametrize("distance", [1.0, 4.0, -2.5])
def test_kinematic_ptp_integrates_to_the_bang_bang_profile(distance):
    """qd_max = 3, qdd_max = 4: d = 1 never reaches qd_max (d < 9/4), d = 4 and -2.5 cruise."""
    def build(self):
        self.ptp = KinematicPTP(deltaq=[distance], qd_max=[3], qdd_max=[4], startTime=0.5)
        self.speed = Integrator()
        self.position = Integrator()
        self.connect(self.ptp.y[1], self.speed.u)
        self.connect(self.speed.y, self.position.u)

    result = simulate(_model(build), rtol=1e-10, atol=1e-12)
    t = result.time
    q, qd, qdd, t_end = ptp_profile(t, distance, 3.0, 4.0, 0.5)
    np.testing.assert_allclose(result["position.y"], q, atol=1e-8)
    np.testing.assert_allclose(result["speed.y"], qd, atol=1e-8)
    smooth = _away_from(t, [0.5, t_end, 0.5 + min(0.75, math.sqrt(abs(distance) / 4)),
                            t_end - min(0.75, math.sqrt(abs(distance) / 4))])
    np.testing.assert_allclose(result["ptp.y[1]"][smooth], qdd[smooth], atol=1e-12)
    assert result.at(3.0, "position.y") == pytest.approx(distance, abs=1e-8)


@pytest.mark.parametrize("q_begin, q_end", [(1.0, 2.0), (1.0, 5.0), (3.0, -1.0)])
def test_kinematic_ptp2_outputs_position_speed_acceleration(q_begin, q_end):
    def build(self):
        self.ptp = KinematicPTP2(q_begin=[q_begin], q_end=[q_end], qd_max=[3], qdd_max=[4], startTime=0.5)

    result = simulate(_model(build), rtol=1e-10, atol=1e-12)
    t = result.time
    q, qd, qdd, t_end = ptp_profile(t, q_end - q_begin, 3.0, 4.0, 0.5)
    np.testing.assert_allclose(result["ptp.q[1]"], q_begin + q, atol=1e-10)
    np.testing.assert_allclose(result["ptp.qd[1]"], qd, atol=1e-10)
    t_acc = min(0.75, math.sqrt(abs(q_end - q_begin) / 4))
    smooth = _away_from(t, [0.5, 0.5 + t_acc, t_end - t_acc, t_end])
    np.testing.assert_allclose(result["ptp.qdd[1]"][smooth], qdd[smooth], atol=1e-10)
    assert result.at(1.0, "ptp.endTime") == pytest.approx(t_end, rel=1e-12)
    moving = result["ptp.moving[1]"]
    np.testing.assert_array_equal(moving[_away_from(t, [t_end])], (t < t_end)[_away_from(t, [t_end])])


def test_kinematic_ptp2_synchronizes_the_axes():
    """Three axes (one standing still) arrive together; the slowest one is at its limits, none beyond."""
    q_begin, q_end = [0.0, 1.0, 2.0], [2.0, -1.0, 2.0]
    qd_max, qdd_max = [1.0, 3.0, 1.0], [4.0, 1.0, 1.0]

    def build(self):
        self.ptp = KinematicPTP2(q_begin=q_begin, q_end=q_end, qd_max=qd_max, qdd_max=qdd_max)

    result = simulate(_model(build, stop_time=4.0), rtol=1e-10, atol=1e-12)
    distances = np.subtract(q_end, q_begin)
    # the path parameter's limits are those of the slowest axis
    sd_max = min(v / abs(d) for v, d in zip(qd_max, distances) if d)
    sdd_max = min(a / abs(d) for a, d in zip(qdd_max, distances) if d)
    _, _, _, t_end = ptp_profile(result.time, 1.0, sd_max, sdd_max, 0.0)
    assert result.at(1.0, "ptp.endTime") == pytest.approx(t_end, rel=1e-12)
    for i in range(3):
        q, qd, _, _ = ptp_profile(result.time, distances[i], sd_max * abs(distances[i]) or 1.0,
                                  sdd_max * abs(distances[i]) or 1.0, 0.0)
        np.testing.assert_allclose(result[f"ptp.q[{i + 1}]"], q_begin[i] + (q if distances[i] else 0.0), atol=1e-10)
        assert np.max(np.abs(result[f"ptp.qd[{i + 1}]"])) <= qd_max[i] * (1 + 1e-12)
        assert np.max(np.abs(result[f"ptp.qdd[{i + 1}]"])) <= qdd_max[i] * (1 + 1e-12)
    assert not np.any(result["ptp.moving[3]"])                     # the axis that does not move
    assert np.max(np.abs(result["ptp.qdd[2]"])) == pytest.approx(qdd_max[1])   # axis 2 limits the acceleration


def test_kinematic_ptp2_without_motion_is_at_rest():
    def build(self):
        self.ptp = KinematicPTP2(q_begin=[1.5], q_end=[1.5])

    result = simulate(_model(build, stop_time=1.0, interval=0.1))
    np.testing.assert_array_equal(result["ptp.q[1]"], 1.5)
    np.testing.assert_array_equal(result["ptp.qd[1]"], 0.0)
    assert not np.any(result["ptp.moving[1]"])


def test_kinematic_ptp_vectors_broadcast_and_sizes_are_checked():
    ptp = KinematicPTP(deltaq=[1.0, 2.0, 3.0], qd_max=[2.0])
    assert ptp.nout == 3 and len(ptp.y) == 3
    assert KinematicPTP().nout == 1 and list(KinematicPTP().deltaq)  # the defaults, {1}
    with pytest.raises(ArraySizeError, match="size 2"):
        KinematicPTP(deltaq=[1.0, 2.0, 3.0], qd_max=[1.0, 2.0])


# --------------------------------------------------------------------------
# Sinc, Exponentials, LogFrequencySweep, variable sines


def test_sinc_is_sin_x_over_x():
    def build(self):
        self.sinc = Sinc(f=5, amplitude=2, offset=0.5, startTime=0.2)
        self.smooth = Sinc(f=5, continuous=True, startTime=0.2)

    result = simulate(_model(build, stop_time=1.0, interval=0.0005))
    t = result.time
    x = 2 * np.pi * 5 * (t - 0.2)
    with np.errstate(invalid="ignore", divide="ignore"):
        sinc = np.where(x == 0, 1.0, np.sin(x) / x)
    after = t > 0.2 + 1e-12
    np.testing.assert_allclose(result["sinc.y"][after], 0.5 + 2 * sinc[after], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result["sinc.y"][t < 0.2], 0.5)
    np.testing.assert_allclose(result["smooth.y"][t < 0.2], 1.0)       # continuous: starts at offset + amplitude
    np.testing.assert_allclose(result["smooth.y"][after], sinc[after], rtol=1e-12, atol=1e-12)
    assert result.at(0.2, "sinc.y") == pytest.approx(2.5)              # the limit 1 of sin(x)/x at x = 0


def test_exponentials_rise_and_fall():
    def build(self):
        self.e = Exponentials(outMax=2, riseTime=0.5, riseTimeConst=0.1, fallTimeConst=0.3, startTime=0.25,
                              offset=1)
        self.default_fall = Exponentials()

    result = simulate(_model(build, stop_time=2.0))
    t = result.time
    tau = t - 0.25
    peak = 2 * (1 - math.exp(-0.5 / 0.1))
    expected = 1 + np.where(tau < 0, 0, np.where(tau < 0.5, 2 * (1 - np.exp(-tau / 0.1)),
                                                 peak * np.exp(-(tau - 0.5) / 0.3)))
    np.testing.assert_allclose(result["e.y"], expected, rtol=1e-12, atol=1e-12)
    assert result.at(1.5, "default_fall.y") == pytest.approx((1 - math.exp(-5)) * math.exp(-1.0 / 0.1))


def test_log_frequency_sweep_is_a_ramp_of_the_logarithm():
    def build(self):
        self.sweep = LogFrequencySweep(wMin=0.1, wMax=1000, startTime=0.5, duration=2)

    result = simulate(_model(build))
    t = result.time
    during = (t > 0.5) & (t < 2.5)
    np.testing.assert_allclose(np.log10(result["sweep.y"][during]), -1 + 4 * (t[during] - 0.5) / 2, atol=1e-12)
    np.testing.assert_allclose(result["sweep.y"][t < 0.5], 0.1)
    np.testing.assert_allclose(result["sweep.y"][t > 2.5], 1000.0)


def test_sine_and_cosine_of_variable_frequency_and_amplitude():
    """f = 1 + 2*t (a ramp) gives phi = 2*pi*(t + t^2); the amplitude is an input or a parameter."""
    def build(self):
        self.f = Ramp(height=4, duration=2, offset=1)
        self.amplitude = Constant(k=0.5)
        self.sine = SineVariableFrequencyAndAmplitude(offset=0.25)
        self.cosine = CosineVariableFrequencyAndAmplitude(useConstantAmplitude=True, constantAmplitude=3)
        self.fixed = SineVariableFrequencyAndAmplitude(useConstantAmplitude=True, useConstantFrequency=True,
                                                       constantFrequency=2)
        self.connect(self.f.y, self.sine.f)
        self.connect(self.f.y, self.cosine.f)
        self.connect(self.amplitude.y, self.sine.amplitude)

    with pytest.warns(UserWarning, match="start values"):   # phi starts at its start value, as in the MSL
        result = simulate(_model(build, stop_time=2.0), rtol=1e-10, atol=1e-12)
    t = result.time
    phi = 2 * np.pi * (t + t ** 2)
    np.testing.assert_allclose(result["sine.y"], 0.25 + 0.5 * np.sin(phi), atol=1e-7)
    np.testing.assert_allclose(result["cosine.y"], 3 * np.cos(phi), atol=1e-7)
    np.testing.assert_allclose(result["fixed.y"], np.sin(2 * np.pi * 2 * t), atol=1e-7)
    assert "cosine.amplitude" not in result.names


# --------------------------------------------------------------------------
# Integer sources and expressions


def test_integer_constant_and_step():
    def build(self):
        self.k = IntegerConstant(k=-3)
        self.step = IntegerStep(height=4, offset=2, startTime=0.55)
        self.default_step = IntegerStep()

    result = simulate(_model(build, stop_time=1.0, interval=0.05))
    t = result.time
    np.testing.assert_array_equal(result["k.y"], -3)
    np.testing.assert_array_equal(result["step.y"][t < 0.55], 2)
    np.testing.assert_array_equal(result["step.y"][t > 0.55], 6)
    assert result["step.y"].dtype.kind == "i"
    assert [e.time for e in result.events if e.kind == "time"] == [pytest.approx(0.55)]
    np.testing.assert_array_equal(result["default_step.y"][t > 0], 1)


def test_expressions_bind_their_outputs():
    def build(self):
        self.source = Ramp(height=2, duration=1)
        self.real = RealExpression(y=If(time < 0.5, 0, 1) + 3 * self.source.y)
        self.late = RealExpression(y=lambda block: sp.sin(time))
        self.zero = RealExpression()
        self.integer = IntegerExpression(y=If(time < 0.25, 2, 7))
        self.boolean = BooleanExpression(y=sp.And(time >= 0.25, time < 0.75))
        self.false = BooleanExpression()
        self.later = RealExpression(y=lambda block: 2 * self.attached_after.y)
        self.attached_after = Constant(k=1.5)

    result = simulate(_model(build, stop_time=1.0, interval=0.05))
    t = result.time
    smooth = _away_from(t, [0.25, 0.5, 0.75])
    ramp = np.clip(t, 0, 1) * 2
    np.testing.assert_allclose(result["real.y"][smooth], (np.where(t < 0.5, 0, 1) + 3 * ramp)[smooth], atol=1e-12)
    np.testing.assert_allclose(result["late.y"], np.sin(t), atol=1e-12)
    np.testing.assert_array_equal(result["zero.y"], 0.0)
    np.testing.assert_array_equal(result["integer.y"][smooth], np.where(t < 0.25, 2, 7)[smooth])
    np.testing.assert_array_equal(result["boolean.y"][smooth], ((t >= 0.25) & (t < 0.75))[smooth])
    assert not np.any(result["false.y"])
    np.testing.assert_array_equal(result["later.y"], 3.0)


def test_expression_attributes_and_bad_values():
    block = RealExpression(y=dict(unit="m"))
    assert block.attribute("y", "unit") == "m"
    with pytest.raises(Exception, match="not an expression"):
        def build(self):
            self.bad = RealExpression(y=object())
        simulate(_model(build, stop_time=0.1, interval=0.05))


def test_radio_buttons_release_each_other():
    """The MSL's documented example: start pressed at 1 and 3, stop at 2 and 4, each releasing the other."""
    def build(self):
        self.start = RadioButtonSource(buttonTimeTable=[1, 3], reset=[lambda block: self.stop.on])
        self.stop = RadioButtonSource(buttonTimeTable=[2, 4], reset=[lambda block: self.start.on])
        self.alone = RadioButtonSource(buttonTimeTable=[0.5, 1.5], reset=[])

    result = simulate(_model(build, stop_time=5.0, interval=0.25))
    t = result.time
    smooth = _away_from(t, [0.5, 1, 1.5, 2, 3, 4])
    start_on = ((t >= 1) & (t < 2)) | ((t >= 3) & (t < 4))
    stop_on = ((t >= 2) & (t < 3)) | (t >= 4)
    np.testing.assert_array_equal(result["start.on"][smooth], start_on[smooth])
    np.testing.assert_array_equal(result["stop.on"][smooth], stop_on[smooth])
    # without resets a button stays pressed
    np.testing.assert_array_equal(result["alone.on"][smooth], (t >= 0.5)[smooth])


def test_non_strict_relations_of_time_switch_after_their_instant():
    def build(self):
        self.until = BooleanExpression(y=time <= 0.5)
        self.after = BooleanExpression(y=time > 0.5)

    result = simulate(_model(build, stop_time=1.0, interval=0.25))
    t = result.time
    np.testing.assert_array_equal(result["until.y"][t > 0.5], False)
    np.testing.assert_array_equal(result["after.y"][t > 0.5], True)
