"""Signal sources (Modelica.Blocks.Sources).

The periodic sources (:class:`Pulse`, :class:`SawTooth`, :class:`Trapezoid`)
count their periods in a when-clause, at exact time events; the tables
(:class:`TimeTable` is a piecewise expression of ``time`` whose switching at
the table times are time events (values right-continuous at a repeated
time); :class:`CombiTimeTable` is MSL 4.1's: a held next time event and
the interpolations of :mod:`acausal.interpolation`.  The Boolean sources are in
:mod:`acausal.library.blocks.booleans`.

:class:`KinematicPTP` and :class:`KinematicPTP2` plan point-to-point
motions (piecewise polynomials of ``time`` whose switching instants are time
events); :class:`RealExpression` and :class:`IntegerExpression` bind their
output to an expression given as ``y=...``, as Modelica's modifier of the
output does.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Sequence

import sympy as sp

from acausal.arrays import Array
from acausal.components.blocks import SO, BooleanOutput, IntegerOutput, SignalSource
from acausal.components.declarations import DerivedDefaults, VectorBlock
from acausal.components.logic import is_initial
from acausal.components.tables import (Extrapolation, Smoothness, TableData, TimeEvents, default_columns,
                                       range_asserts)
from acausal.errors import ArraySizeError, ModifierError, ParameterError
from acausal.hybrid import When, noEvent, sample
from acausal.interpolation import TimeTable as NumericTimeTable
from acausal.language import (Component, Eq, If, Integer, Parameter, RealInput, RealOutput, Variable, der, initial,
                              pre, time)
from acausal.tables import time_table_functions

from .discrete import EPS, SMALL
from .math import RealToInteger

#: Modelica.Constants.inf: what the MSL holds as "no further time event"
MODELICA_INF = 1e60

__all__ = ["Constant", "ContinuousClock", "Step", "Ramp", "Sine", "Cosine", "ExpSine", "Pulse", "SawTooth", "Trapezoid",
           "TimeTable", "CombiTimeTable", "IntegerTable", "Smoothness", "Extrapolation", "TimeEvents",
           "IntegerConstant", "IntegerStep", "RealExpression", "IntegerExpression", "Sinc", "Exponentials",
           "LogFrequencySweep", "SineVariableFrequencyAndAmplitude", "CosineVariableFrequencyAndAmplitude",
           "KinematicPTP", "KinematicPTP2"]


class Constant(SO):
    """Generate a constant signal (Modelica.Blocks.Sources.Constant): ``y = k``."""

    modelica_name = "Modelica.Blocks.Sources.Constant"

    k = Parameter(1.0, description="Constant output value")

    def equations(self):
        return [Eq(self.y, self.k)]


class ContinuousClock(SignalSource):
    """Generate current time signal (Modelica.Blocks.Sources.ContinuousClock):
    ``y = offset + (0 if time < startTime else time - startTime)``."""

    modelica_name = "Modelica.Blocks.Sources.ContinuousClock"

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, time - self.startTime))]


class Step(SignalSource):
    """Generate a step signal (Modelica.Blocks.Sources.Step).

    ``y = offset + (0 if time < startTime else height)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Step"

    height = Parameter(1.0, description="Height of step")

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, self.height))]


class Ramp(SignalSource):
    """Generate a ramp signal (Modelica.Blocks.Sources.Ramp).

    ``offset`` before ``startTime``, then rising linearly by ``height`` over
    ``duration`` seconds, then ``offset + height``.
    """

    modelica_name = "Modelica.Blocks.Sources.Ramp"

    height = Parameter(1.0, description="Height of ramps")
    duration = Parameter(2.0, unit="s", min=0, description="Duration of ramp (= 0.0 gives a Step)")

    def equations(self):
        t0, dt = self.startTime, self.duration
        return [Eq(self.y, self.offset + sp.Piecewise(
            (0, time < t0),
            ((time - t0) * self.height / dt, time < t0 + dt),
            (self.height, True)))]


class _Harmonic(SignalSource):
    """Declarations and output equation shared by Sine and Cosine."""

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(1.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    continuous = Parameter(False, structural=True,
                           description="Make output continuous by starting at offset + amplitude*sin(phase)")

    def _output(self, g):
        wave = g(2 * sp.pi * self.f * (time - self.startTime) + self.phase)
        if self.continuous:
            return Eq(self.y, self.offset + self.amplitude * If(time < self.startTime, g(self.phase), wave))
        return Eq(self.y, self.offset + If(time < self.startTime, 0, self.amplitude * wave))


class Sine(_Harmonic):
    """Generate a sine signal (Modelica.Blocks.Sources.Sine).

    ``y = offset + amplitude*sin(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*sin(phase)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Sine"

    def equations(self):
        return [self._output(sp.sin)]


class Cosine(_Harmonic):
    """Generate a cosine signal (Modelica.Blocks.Sources.Cosine).

    ``y = offset + amplitude*cos(2*pi*f*(time - startTime) + phase)`` from
    ``startTime`` on; before it ``offset``, or with ``continuous`` the value
    ``offset + amplitude*cos(phase)``.
    """

    modelica_name = "Modelica.Blocks.Sources.Cosine"

    def equations(self):
        return [self._output(sp.cos)]


class ExpSine(SignalSource):
    """Generate an exponentially damped sine signal (Modelica.Blocks.Sources.ExpSine).

    ``y = offset + amplitude*exp(-(time - startTime)*damping)*sin(2*pi*f*(time
    - startTime) + phase)`` from ``startTime`` on, ``offset`` before.
    """

    modelica_name = "Modelica.Blocks.Sources.ExpSine"

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    f = Parameter(2.0, unit="Hz", description="Frequency of sine wave")
    phase = Parameter(0.0, unit="rad", description="Phase of sine wave")
    damping = Parameter(1.0, unit="1/s", description="Damping coefficient of sine wave")

    def equations(self):
        dt = time - self.startTime
        wave = self.amplitude * sp.exp(-dt * self.damping) * sp.sin(2 * sp.pi * self.f * dt + self.phase)
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, wave))]


class Sinc(SignalSource):
    """Generate sinc signal (Modelica.Blocks.Sources.Sinc).

    ``y = offset + amplitude*sin(x)/x`` with ``x = 2*pi*f*(time -
    startTime)`` from ``startTime`` on (1 instead of ``sin(x)/x`` within
    ``eps`` of it, where the quotient is 0/0); before it ``offset``, or with
    ``continuous`` the value ``offset + amplitude``.
    """

    modelica_name = "Modelica.Blocks.Sources.Sinc"

    amplitude = Parameter(1.0, description="Amplitude of sine wave")
    # the MSL gives f only a start value (1), which a tool proposes
    f = Parameter(1.0, unit="Hz", description="Frequency of sine wave")
    continuous = Parameter(False, structural=True,
                           description="Make output (continuously) differentiable by starting at offset + amplitude "
                                       "rather than just offset")
    x = Variable(unit="rad", description="Argument of the sinc function (protected)")

    def equations(self):
        elapsed = time - self.startTime
        # sin(x)/x is 0/0 at the start: its limit 1 there, decided without an event
        sinc = noEvent(sp.Piecewise((1, elapsed < EPS), (sp.sin(self.x) / self.x, True)))
        if self.continuous:
            output = self.offset + self.amplitude * If(time < self.startTime, 1, sinc)
        else:
            output = self.offset + If(time < self.startTime, 0, self.amplitude * sinc)
        return [Eq(self.x, 2 * sp.pi * self.f * elapsed), Eq(self.y, output)]


class Exponentials(DerivedDefaults, SignalSource):
    """Generate a rising and falling exponential signal (Modelica.Blocks.Sources.Exponentials).

    From ``startTime`` on, ``outMax*(1 - exp(-(time - startTime)/riseTimeConst))``
    for ``riseTime`` seconds, then the value reached, ``y_riseTime``,
    decaying as ``exp(-(time - startTime - riseTime)/fallTimeConst)``; all
    plus ``offset`` (``offset`` alone before ``startTime``).
    """

    modelica_name = "Modelica.Blocks.Sources.Exponentials"

    outMax = Parameter(1.0, description="Height of output for infinite riseTime")  # noqa: N815
    # the MSL gives riseTime only a start value (0.5), which a tool proposes
    riseTime = Parameter(0.5, unit="s", min=0, description="Rise time")  # noqa: N815
    riseTimeConst = Parameter(0.1, unit="s", min=SMALL,  # noqa: N815
                              description="Rise time constant; rising is defined as "
                                          "outMax*(1-exp(-riseTime/riseTimeConst))")
    fallTimeConst = Parameter(None, unit="s", min=SMALL,  # noqa: N815
                              description="Fall time constant (default riseTimeConst)")
    y_riseTime = Variable(description="Output reached at the end of the rise (protected)")  # noqa: N815

    derived_defaults = {"fallTimeConst": lambda block: block.riseTimeConst}

    def equations(self):
        elapsed = time - self.startTime
        rising = self.outMax * (1 - sp.exp(-elapsed / self.riseTimeConst))
        falling = self.y_riseTime * sp.exp(-(elapsed - self.riseTime) / self.fallTimeConst)
        return [Eq(self.y_riseTime, self.outMax * (1 - sp.exp(-self.riseTime / self.riseTimeConst))),
                Eq(self.y, self.offset + sp.Piecewise((0, time < self.startTime),
                                                      (rising, time < self.startTime + self.riseTime),
                                                      (falling, True)))]


class LogFrequencySweep(SO):
    """Logarithmic frequency sweep (Modelica.Blocks.Sources.LogFrequencySweep).

    ``y = wMin`` before ``startTime``, then ``wMin*(wMax/wMin)^((time -
    startTime)/duration)`` (a linear ramp of ``log10(y)``) for ``duration``
    seconds, then ``wMax``.  ``duration = 0`` gives a step (the MSL takes
    ``max(duration, eps)``).
    """

    modelica_name = "Modelica.Blocks.Sources.LogFrequencySweep"

    wMin = Parameter(None, min=EPS, description="Start frequency")  # noqa: N815
    wMax = Parameter(None, min=EPS, description="End frequency")  # noqa: N815
    startTime = Parameter(0.0, unit="s", description="Start time of frequency sweep")  # noqa: N815
    # the MSL gives duration only a start value (1), which a tool proposes
    duration = Parameter(1.0, unit="s", min=0.0, description="Duration of ramp (= 0.0 gives a Step)")

    def equations(self):
        duration = sp.Max(self.duration, EPS)
        fraction = sp.Min(1, (time - self.startTime) / duration)
        return [Eq(self.y, sp.Piecewise((self.wMin, time < self.startTime),
                                        (self.wMin * (self.wMax / self.wMin) ** fraction,
                                         time < self.startTime + duration),
                                        (self.wMax, True)))]


class _VariableHarmonic(SO):
    """What SineVariableFrequencyAndAmplitude and CosineVariableFrequencyAndAmplitude share.

    The phase is integrated from the frequency, ``der(phi) = 2*pi*f``; the
    amplitude and the frequency are inputs, or with
    ``useConstantAmplitude``/``useConstantFrequency`` the parameters
    ``constantAmplitude``/``constantFrequency`` (the MSL feeds those through
    a Constant block into a protected connector; here the parameter enters
    the equation directly).  ``phi`` starts at its start value 0 (not fixed,
    as in the MSL: it is the initial phase shift).
    """

    useConstantAmplitude = Parameter(False, structural=True, description="Enable constant amplitude")  # noqa: N815
    constantAmplitude = Parameter(1.0, description="Constant amplitude")  # noqa: N815
    useConstantFrequency = Parameter(False, structural=True, description="Enable constant frequency")  # noqa: N815
    constantFrequency = Parameter(1.0, unit="Hz", description="Constant frequency")  # noqa: N815
    offset = Parameter(0.0, description="Offset of the sine wave")
    phi = Variable(start=0.0, unit="rad", description="Phase of the sine wave")
    amplitude = RealInput(condition=lambda block: not block.useConstantAmplitude, description="Amplitude")
    f = RealInput(condition=lambda block: not block.useConstantFrequency, unit="Hz", description="Frequency")

    def _output(self, wave):
        amplitude = self.constantAmplitude if self.useConstantAmplitude else self.amplitude
        frequency = self.constantFrequency if self.useConstantFrequency else self.f
        return [Eq(der(self.phi), 2 * sp.pi * frequency), Eq(self.y, self.offset + amplitude * wave(self.phi))]


class SineVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Generate sine signal with variable frequency and amplitude
    (Modelica.Blocks.Sources.SineVariableFrequencyAndAmplitude).

    ``y = offset + amplitude*sin(phi)`` with ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Blocks.Sources.SineVariableFrequencyAndAmplitude"

    def equations(self):
        return self._output(sp.sin)


class CosineVariableFrequencyAndAmplitude(_VariableHarmonic):
    """Generate cosine signal with variable frequency and amplitude
    (Modelica.Blocks.Sources.CosineVariableFrequencyAndAmplitude).

    ``y = offset + amplitude*cos(phi)`` with ``der(phi) = 2*pi*f``.
    """

    modelica_name = "Modelica.Blocks.Sources.CosineVariableFrequencyAndAmplitude"

    def equations(self):
        return self._output(sp.cos)


# --------------------------------------------------------------------------
# point-to-point motion profiles
# --------------------------------------------------------------------------


class _PathPlanning(Component):
    """What KinematicPTP and KinematicPTP2 share: vector parameters of equal size or of size 1.

    The number of outputs ``nout`` is the largest size of the vectors
    :attr:`vectors` names (the MSL's ``final nout = max(size(...))``), and a
    vector of size 1 stands for ``nout`` equal elements (the MSL's
    protected ``p_deltaq = ones(nout)*deltaq[1]``).  Vector parameters are
    given their declared defaults when absent, so that every instance of a
    size has its own values (instances of one size share a sized class).
    """

    #: The vector parameters whose sizes give nout.
    vectors: tuple[str, ...] = ()

    nout = Parameter(1, structural=True, min=1, description="Number of output signals (set from the vectors)")
    qd_max = Parameter([1.0], min=SMALL, description="Maximum velocities der(q)")
    qdd_max = Parameter([1.0], min=SMALL, description="Maximum accelerations der(qd)")
    startTime = Parameter(0.0, unit="s", description="Time instant at which movement starts")  # noqa: N815

    @classmethod
    def _with_sizes(cls, modifiers: dict[str, Any]) -> dict[str, Any]:
        """``modifiers`` with every vector (its default if absent, a scalar as a vector of one) and ``nout``."""
        unsized = vars(cls).get("_unsized", cls)
        declarations = unsized.declarations()
        modifiers = dict(modifiers)
        sizes = []
        for name in cls.vectors:
            value = modifiers.get(name, declarations[name].default)
            if not isinstance(value, (list, tuple, Array)) and not hasattr(value, "shape"):
                value = [value]
            value = list(value)
            if not value:
                raise ArraySizeError(f"{cls.__name__}.{name} is empty", hint=f"give {name} at least one element")
            modifiers[name] = value
            sizes.append(len(value))
        nout = max(sizes)
        for name, size in zip(cls.vectors, sizes):
            if size not in (1, nout):
                raise ArraySizeError(f"{cls.__name__}.{name} has size {size}, but another vector has size {nout}",
                                     hint="give every vector nout elements, or one element for all")
        if "nout" in modifiers and modifiers["nout"] != nout:
            raise ArraySizeError(f"{cls.__name__}: nout = {modifiers['nout']!r}, but the vectors have size {nout}",
                                 hint="nout is set from the vectors; leave it out")
        modifiers["nout"] = nout
        return modifiers

    def __new__(cls, *args: Any, **modifiers: Any):
        return super().__new__(cls, *args, **cls._with_sizes(modifiers))

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**type(self)._with_sizes(modifiers))

    def per_output(self, name: str) -> list:
        """The vector parameter ``name`` with ``nout`` elements (a vector of one repeated)."""
        vector = list(getattr(self, name))
        return vector * self.nout if len(vector) == 1 else vector

    def path_limits(self, distance: list) -> tuple[Any, Any]:
        """``(1/sd_max, 1/sdd_max)``: the largest time needed per unit of velocity and of acceleration
        over the axes, ``max(abs(distance./qd_max))`` and ``max(abs(distance./qdd_max))``: the path
        parameter s runs from 0 to 1, the axis limiting each is the slowest one."""
        qd_max, qdd_max = self.per_output("qd_max"), self.per_output("qdd_max")
        return (sp.Max(*[sp.Abs(d / v) for d, v in zip(distance, qd_max)]),
                sp.Max(*[sp.Abs(d / a) for d, a in zip(distance, qdd_max)]))


def _ptp_phases(sd_max, sdd_max):
    """``(Ta1, Ta2, noWphase, Tv, Te)`` of a point-to-point motion of the path parameter over [0, 1].

    ``Ta1`` is the acceleration time of a motion without a phase at constant
    speed (bang-bang), ``Ta2`` the time to reach ``sd_max``; if ``Ta2 >=
    Ta1`` the speed limit is never reached (``noWphase``) and the motion
    ends at ``Te = 2*Ta1``, else it cruises from ``Ta2`` to ``Tv = 1/sd_max``
    and ends at ``Te = Tv + Ta2``.
    """
    Ta1 = sp.sqrt(1 / sdd_max)
    Ta2 = sd_max / sdd_max
    noWphase = Ta2 >= Ta1
    Tv = sp.Piecewise((Ta1, noWphase), (1 / sd_max, True))
    Te = sp.Piecewise((Ta1 + Ta1, noWphase), (Tv + Ta2, True))
    return Ta1, Ta2, noWphase, Tv, Te


class KinematicPTP(_PathPlanning):
    """Move as fast as possible along a distance within given kinematic constraints
    (Modelica.Blocks.Sources.KinematicPTP).

    The output is the acceleration ``y[i] = deltaq[i]*sdd`` of a
    point-to-point motion over ``deltaq`` starting at ``startTime``: the
    path acceleration ``sdd`` is ``sdd_max`` until ``Ta1`` (no phase at
    constant speed) or ``Ta2``, then 0 until ``Tv``, then ``-sdd_max``
    until ``Te``, then 0; integrated twice it moves every axis by its
    ``deltaq`` in the same time, with the slowest axis at its limits
    ``qd_max``/``qdd_max``.  Vectors of size 1 stand for all axes.
    """

    modelica_name = "Modelica.Blocks.Sources.KinematicPTP"

    vectors = ("deltaq", "qd_max", "qdd_max")

    deltaq = Parameter([1.0], description="Distance to move")
    y = RealOutput(shape="nout", description="Connector of Real output signals")
    sdd = Variable(description="Path acceleration (protected)")

    def equations(self):
        deltaq = self.per_output("deltaq")
        sd_max_inv, sdd_max_inv = self.path_limits(deltaq)
        sd_max, sdd_max = 1 / sd_max_inv, 1 / sdd_max_inv
        Ta1, Ta2, noWphase, Tv, Te = _ptp_phases(sd_max, sdd_max)
        start = self.startTime
        without_cruise = sp.Piecewise((sdd_max, time < Ta1 + start), (-sdd_max, time < Te + start), (0, True))
        with_cruise = sp.Piecewise((sdd_max, time < Ta2 + start), (0, time < Tv + start),
                                   (-sdd_max, time < Te + start), (0, True))
        return [Eq(self.sdd, sp.Piecewise((0, time < start), (without_cruise, noWphase), (with_cruise, True))),
                *[Eq(y, d * self.sdd) for y, d in zip(self.y, deltaq)]]


class KinematicPTP2(_PathPlanning):
    """Move as fast as possible from start to end position within given kinematic constraints with output
    signals q, qd=der(q), qdd=der(qd) (Modelica.Blocks.Sources.KinematicPTP2).

    The path parameter ``s`` runs from 0 to 1 as KinematicPTP's
    acceleration profile integrated twice: ``q = q_begin + (q_end -
    q_begin)*s``, ``qd`` and ``qdd`` its derivatives; ``moving[i]`` is true
    until ``endTime`` for an axis that moves at all.  Where no axis moves
    (every distance within ``10*eps``) everything is 0.

    The MSL writes ``sd = der(s)``, ``sdd = der(sd)`` and has the tool
    differentiate the piecewise polynomial ``s``; here ``sd`` and ``sdd``
    are its derivatives written piece by piece (the same polynomials,
    without an index reduction).
    """

    modelica_name = "Modelica.Blocks.Sources.KinematicPTP2"

    vectors = ("q_begin", "q_end", "qd_max", "qdd_max")

    q_begin = Parameter([0.0], description="Start position")
    q_end = Parameter([1.0], description="End position")
    q = RealOutput(shape="nout", description="Reference position of path planning")
    qd = RealOutput(shape="nout", description="Reference speed of path planning")
    qdd = RealOutput(shape="nout", description="Reference acceleration of path planning")
    moving = BooleanOutput(shape="nout", description="= true, if end position not yet reached; = false, if end "
                                                     "position reached or axis is completely at rest")
    endTime = Variable(unit="s", description="Time instant at which movement stops")  # noqa: N815
    s = Variable(description="Path parameter, 0 at the start, 1 at the end (protected)")
    sd = Variable(description="Path speed der(s) (protected)")
    sdd = Variable(description="Path acceleration der(sd) (protected)")

    #: The MSL's protected constant eps = 10*Modelica.Constants.eps: below it a distance is no motion.
    still = 10 * EPS

    def equations(self):
        q_begin, q_end = self.per_output("q_begin"), self.per_output("q_end")
        deltaq = [b - a for a, b in zip(q_begin, q_end)]
        sd_max_inv, sdd_max_inv = self.path_limits(deltaq)
        at_rest = sp.Or(sd_max_inv <= self.still, sdd_max_inv <= self.still)
        # at rest the profile is 0 and its expressions unused: bounded away from 0 there, they stay finite
        # (the relations of parameters are evaluated whichever branch holds)
        sd_max, sdd_max = 1 / sp.Max(sd_max_inv, self.still), 1 / sp.Max(sdd_max_inv, self.still)
        Ta1, Ta2, noWphase, Tv, Te = _ptp_phases(sd_max, sdd_max)
        start = self.startTime
        Ta1s, Ta2s, Tvs, Tes = Ta1 + start, Ta2 + start, Tv + start, Te + start
        sd_max2 = sdd_max * Ta1
        s1 = sdd_max * sp.Piecewise((Ta1 * Ta1, noWphase), (Ta2 * Ta2, True)) / 2
        s2 = s1 + sp.Piecewise((sd_max2 * (Te - Ta1) - (sdd_max / 2) * (Te - Ta1) ** 2, noWphase),
                               (sd_max * (Tv - Ta2), True))
        s3 = s2 + sd_max * (Te - Tv) - (sdd_max / 2) * (Te - Tv) * (Te - Tv)
        # each piece of s as (s, der(s), der(s, 2))
        since_start, since_a1, since_v = time - start, time - Ta1s, time - Tvs
        accelerating = ((sdd_max / 2) * since_start ** 2, sdd_max * since_start, sdd_max)
        without_cruise = [(accelerating, time < Ta1s),
                          ((s1 + sd_max2 * since_a1 - (sdd_max / 2) * since_a1 ** 2, sd_max2 - sdd_max * since_a1,
                            -sdd_max), time < Tes),
                          ((s2, 0, 0), True)]
        with_cruise = [(accelerating, time < Ta2s),
                       ((s1 + sd_max * (time - Ta2s), sd_max, 0), time < Tvs),
                       ((s2 + sd_max * since_v - (sdd_max / 2) * since_v ** 2, sd_max - sdd_max * since_v, -sdd_max),
                        time < Tes),
                       ((s3, 0, 0), True)]

        def profile(k: int):
            moving = sp.Piecewise((0, time < start),
                                  (sp.Piecewise(*[(piece[k], c) for piece, c in without_cruise]), noWphase),
                                  (sp.Piecewise(*[(piece[k], c) for piece, c in with_cruise]), True))
            return sp.Piecewise((0, at_rest), (moving, True))

        equations = [Eq(self.s, profile(0)), Eq(self.sd, profile(1)), Eq(self.sdd, profile(2)),
                     Eq(self.endTime, sp.Piecewise((0, at_rest), (Tes, True)))]
        # time < endTime with endTime's parameter expression: a time event, hit exactly
        motion_ref = time < sp.Piecewise((0, at_rest), (Tes, True))
        for i, d in enumerate(deltaq):
            equations += [Eq(self.qdd[i + 1], d * self.sdd), Eq(self.qd[i + 1], d * self.sd),
                          Eq(self.q[i + 1], q_begin[i] + d * self.s)]
            # the MSL compares the given vectors, q_begin[i] and q_end[i]: the same after the broadcast
            moves = sp.Abs(d) > self.still
            equations.append(Eq(self.moving[i + 1], sp.And(moves, motion_ref) | sp.false))
        return equations


# --------------------------------------------------------------------------
# expressions: an output bound to an expression given as a modifier
# --------------------------------------------------------------------------


class _BoundOutput(Component):
    """An output ``y`` bound to an expression given as ``y=...``, as Modelica's ``RealExpression(y=...)``.

    ``y`` may be a number, a sympy expression of ``time`` and of the
    model's variables (``y=self.inertia.w`` in ``build()``: the symbols of
    components attached before), or a callable taking the block and
    returning one (evaluated when the equations are written, so it may
    name components attached later).  A dict still modifies the output's
    attributes (``y=dict(start=1)``).
    """

    #: The value of the output when no expression is given (the MSL's binding).
    default_expression: Any = 0

    def __init__(self, **modifiers: Any) -> None:
        expression = self.default_expression
        if "y" in modifiers and not isinstance(modifiers["y"], dict):
            expression = modifiers.pop("y")
        super().__init__(**modifiers)
        object.__setattr__(self, "_expression", expression)

    def expression(self):
        """The bound expression, as sympy."""
        value = self._expression(self) if callable(self._expression) else self._expression
        if isinstance(value, bool):
            return sp.true if value else sp.false
        try:
            return sp.sympify(value)
        except (sp.SympifyError, TypeError) as exc:
            where = self.path or type(self).__name__
            raise ModifierError(f"{where}.y = {value!r} is not an expression",
                                hint="give a number, a sympy expression of time or of the model's variables, "
                                     "or a function of the block returning one") from exc

    def equations(self):
        return [Eq(self.y, self.expression())]


class RealExpression(_BoundOutput):
    """Set output signal to a time varying Real expression (Modelica.Blocks.Sources.RealExpression).

    ``RealExpression(y=expr)``: ``y = expr``, 0 by default; ``expr`` a number,
    a sympy expression of ``time`` and the model's variables, or a function
    of the block returning one (``RealExpression(y=If(time < 1, 0, 1))``).
    """

    modelica_name = "Modelica.Blocks.Sources.RealExpression"

    y = RealOutput(description="Value of Real output")
    default_expression = 0.0


class IntegerExpression(_BoundOutput):
    """Set output signal to a time varying Integer expression (Modelica.Blocks.Sources.IntegerExpression).

    ``IntegerExpression(y=expr)``: ``y = expr``, 0 by default; ``expr``
    Integer-valued (changing at events only), given as for
    :class:`RealExpression`.
    """

    modelica_name = "Modelica.Blocks.Sources.IntegerExpression"

    y = IntegerOutput(description="Value of Integer output")
    default_expression = 0


# --------------------------------------------------------------------------
# Integer sources
# --------------------------------------------------------------------------


class IntegerSO(Component):
    """Single Integer output block (Modelica.Blocks.Interfaces.IntegerSO): the output ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.IntegerSO"

    y = IntegerOutput(description="Connector of Integer output signal")


class IntegerSignalSource(IntegerSO):
    """Base of Integer signal sources (Modelica.Blocks.Interfaces.IntegerSignalSource): ``offset`` and
    ``startTime``."""

    modelica_name = "Modelica.Blocks.Interfaces.IntegerSignalSource"

    offset = Parameter(0, description="Offset of output signal y")
    startTime = Parameter(0.0, unit="s", description="Output y = offset for time < startTime")  # noqa: N815


class IntegerConstant(IntegerSO):
    """Generate constant signal of type Integer (Modelica.Blocks.Sources.IntegerConstant): ``y = k``."""

    modelica_name = "Modelica.Blocks.Sources.IntegerConstant"

    # the MSL gives k only a start value (1): it must be set, and 1 is what a tool proposes
    k = Parameter(1, description="Constant output value")

    def equations(self):
        return [Eq(self.y, self.k)]


class IntegerStep(IntegerSignalSource):
    """Generate step signal of type Integer (Modelica.Blocks.Sources.IntegerStep).

    ``y = offset + (0 if time < startTime else height)``; the step is a time
    event (at ``time = startTime`` the new value holds).
    """

    modelica_name = "Modelica.Blocks.Sources.IntegerStep"

    height = Parameter(1, description="Height of step")

    def equations(self):
        return [Eq(self.y, self.offset + If(time < self.startTime, 0, self.height))]


# --------------------------------------------------------------------------
# periodic and table sources (hybrid: when-clauses, time events)
# --------------------------------------------------------------------------


class _Periodic(SignalSource):
    """The period counting shared by Pulse, SawTooth and Trapezoid.

    ``count`` is the number of the current period and ``T_start`` its start:
    at initialization ``count = integer((time - startTime)/period)`` and
    ``T_start = startTime + count*period``; at each period boundary
    ``startTime + i*period`` (a time event) ``count`` becomes ``i`` and
    ``T_start`` the event time.

    MSL 4.1 detects the boundary with the relation ``time >= (pre(count) +
    1)*period + startTime``; the engine locates relations of ``time`` with
    discrete variables as state events (to about 1e-10 s), so the boundary
    is written here as ``sample(startTime, period)``, whose ticks are exact
    time events.  ``count = integer((time - startTime)/period + 0.5)`` at a
    tick is ``i``, also at a tick on the start time.
    """

    period = Parameter(1.0, unit="s", min=SMALL, description="Time for one period")
    nperiod = Parameter(-1, structural=True,
                        description="Number of periods (< 0 means infinite number of periods)")
    T_start = Variable(unit="s", discrete=True, description="Start time of current period")  # noqa: N815
    count = Integer(description="Period count")

    def _counting(self):
        periods = (time - self.startTime) / self.period
        first = noEvent(sp.floor(periods))
        return When(initial(), Eq(self.count, first),
                    Eq(self.T_start, self.startTime + first * self.period)) \
            .elsewhen(sample(self.startTime, self.period),
                      Eq(self.count, noEvent(sp.floor(periods + sp.Rational(1, 2)))), Eq(self.T_start, time))

    def _inactive(self):
        """Where the output is ``offset``: before startTime, or after nperiod periods."""
        nperiod = int(self.nperiod)
        if nperiod == 0:
            return sp.true
        if nperiod > 0:
            return sp.Or(time < self.startTime, self.count >= nperiod)
        return time < self.startTime


class Pulse(_Periodic):
    """Generate a pulse signal of type Real (Modelica.Blocks.Sources.Pulse).

    ``offset + amplitude`` during the first ``width`` percent of every period
    from ``startTime`` on, ``offset`` otherwise (and after ``nperiod``
    periods, if ``nperiod >= 0``).
    """

    modelica_name = "Modelica.Blocks.Sources.Pulse"

    amplitude = Parameter(1.0, description="Amplitude of pulse")
    width = Parameter(50.0, min=SMALL, max=100, description="Width of pulse in % of period")

    def equations(self):
        T_width = self.period * self.width / 100
        return [self._counting(),
                Eq(self.y, sp.Piecewise((self.offset, self._inactive()),
                                        (self.offset + self.amplitude, time < self.T_start + T_width),
                                        (self.offset, True)))]


class SawTooth(_Periodic):
    """Generate a saw tooth signal (Modelica.Blocks.Sources.SawTooth).

    ``offset + amplitude*(time - T_start)/period`` in every period from
    ``startTime`` on, ``offset`` before (and after ``nperiod`` periods).
    """

    modelica_name = "Modelica.Blocks.Sources.SawTooth"

    amplitude = Parameter(1.0, description="Amplitude of saw tooth")

    def equations(self):
        return [self._counting(),
                Eq(self.y, sp.Piecewise((self.offset, self._inactive()),
                                        (self.offset + self.amplitude * (time - self.T_start) / self.period,
                                         True)))]


class Trapezoid(_Periodic):
    """Generate trapezoidal signal of type Real (Modelica.Blocks.Sources.Trapezoid).

    In every period: a linear rise by ``amplitude`` over ``rising`` seconds,
    ``width`` seconds at ``offset + amplitude``, a linear fall over
    ``falling`` seconds, then ``offset`` for the rest of the period.
    """

    modelica_name = "Modelica.Blocks.Sources.Trapezoid"

    amplitude = Parameter(1.0, description="Amplitude of trapezoid")
    rising = Parameter(0.0, unit="s", min=0, description="Rising duration of trapezoid")
    width = Parameter(0.5, unit="s", min=0, description="Width duration of trapezoid")
    falling = Parameter(0.0, unit="s", min=0, description="Falling duration of trapezoid")

    def equations(self):
        T_rising = self.rising
        T_width = T_rising + self.width
        T_falling = T_width + self.falling
        tau = time - self.T_start
        # the branches dividing by rising/falling are selected only where those are > 0
        return [self._counting(),
                Eq(self.y, sp.Piecewise(
                    (self.offset, self._inactive()),
                    (self.offset + self.amplitude * tau / self.rising, tau < T_rising),
                    (self.offset + self.amplitude, tau < T_width),
                    (self.offset + self.amplitude * (self.T_start + T_falling - time) / self.falling,
                     tau < T_falling),
                    (self.offset, True), evaluate=False))]



def _rows(table: Any, where: str, columns: int | None = None) -> list[list[float]]:
    """A structural table as rows of floats, the first column non-decreasing."""
    try:
        rows = [[float(v) for v in row] for row in table]
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{where}.table must be a matrix of numbers, not {table!r}",
                             hint="e.g. table=[[0, 0], [1, 2], [3, 2]] (time in the first column)") from exc
    if not rows:
        raise ParameterError(f"{where}.table is empty", hint="give at least one row [time, value, ...]")
    widths = {len(r) for r in rows}
    if len(widths) != 1 or min(widths) < 2:
        raise ParameterError(f"{where}.table must have rows of equal length >= 2 (time, values)",
                             hint="e.g. table=[[0, 0], [1, 2]]")
    if not all(math.isfinite(v) for r in rows for v in r):
        raise ParameterError(f"{where}.table has non-finite entries", hint="give finite numbers")
    for i in range(1, len(rows)):
        if rows[i][0] < rows[i - 1][0]:
            raise ParameterError(
                f"{where}.table: the time column must not decrease, but row {i + 1} ({rows[i][0]:g}) "
                f"follows row {i} ({rows[i - 1][0]:g})",
                hint="sort the rows by time; a repeated time gives a jump")
    return rows


def _table_value(times: Sequence[float], values: Sequence[float], scaled: Any, at: Callable[[float], Any],
                 *, constant: bool, extrapolation: Extrapolation, nearly: Callable[[float, float], bool]):
    """The table's value at scaled table time ``scaled`` as a Piecewise.

    ``at(t)`` is the relation "the scaled time is before table time t" (a
    time event).  Between rows linear (or constant) interpolation; at a
    repeated time the later row holds (right-continuous); outside the rows
    the extrapolation given.
    """
    n = len(times)
    if n == 1:
        return sp.Float(values[0])

    def line(i: int, j: int):
        slope = (values[j] - values[i]) / (times[j] - times[i])
        return values[i] + slope * (scaled - times[i])

    def outside(first: int, second: int, left: bool):
        if extrapolation is Extrapolation.HoldLastPoint:
            return sp.Float(values[first] if left else values[second])
        # LastTwoPoints (also the values NoExtrapolation reports with its assertion)
        if nearly(times[first], times[second]):
            return sp.Float(values[first] if left else values[second])
        return line(first, second)

    pieces = [(outside(0, 1, True), at(times[0]))]
    for j in range(n - 1):
        if nearly(times[j], times[j + 1]):
            continue  # a jump: the later row holds from this time on
        pieces.append((sp.Float(values[j]) if constant else line(j, j + 1), at(times[j + 1])))
    pieces.append((outside(n - 2, n - 1, False), sp.true))
    return sp.Piecewise(*pieces, evaluate=False)


class TimeTable(DerivedDefaults, SignalSource):
    """Generate a (possibly discontinuous) signal by linear interpolation in a table (Modelica.Blocks.Sources.TimeTable).

    ``table`` rows are ``[time, value]`` (the first time 0, times not
    decreasing; a repeated time is a jump, the later value holding from that
    time on).  The output is ``offset`` before ``startTime``, then
    ``offset`` plus the table interpolated linearly at
    ``(time - shiftTime)/timeScale``, extrapolated through the last two rows
    after the table.  Every table time is a time event.
    """

    modelica_name = "Modelica.Blocks.Sources.TimeTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column; e.g., table=[0, 0; 1, 1; 2, 4])")
    timeScale = Parameter(1.0, unit="s", min=EPS, description="Time scale of first table column")  # noqa: N815
    shiftTime = Parameter(None, unit="s", description="Shift time of first table column (default startTime)")  # noqa: N815

    derived_defaults = {"shiftTime": lambda block: block.startTime}

    def equations(self):
        where = self.path or type(self).__name__
        rows = _rows(self.table, where)
        if len(rows[0]) != 2:
            raise ParameterError(f"{where}.table must have 2 columns (time, value), not {len(rows[0])}",
                                 hint="use CombiTimeTable for several columns")
        if len(rows) > 1 and rows[0][0] != 0:
            raise ParameterError(f"{where}.table: the first time must be 0, not {rows[0][0]:g}",
                                 hint="shift the table with shiftTime instead")
        times = [r[0] for r in rows]
        scaled = (time - self.shiftTime) / self.timeScale
        value = _table_value(times, [r[1] for r in rows], scaled,
                             lambda t: time < self.shiftTime + t * self.timeScale,
                             constant=False, extrapolation=Extrapolation.LastTwoPoints,
                             nearly=lambda a, b: b - a <= 100 * EPS * abs(b))
        return [Eq(self.y, self.offset + sp.Piecewise((0, time < self.startTime), (value, True),
                                                      evaluate=False))]


class CombiTimeTable(DerivedDefaults, TableData, VectorBlock):
    """Table look-up with respect to time and various interpolation and extrapolation methods (data from matrix/file) (Modelica.Blocks.Sources.CombiTimeTable).

    ``table`` rows are ``[time, value_2, value_3, ...]`` (times not
    decreasing; a repeated time is a jump, the later row holding from that
    time on), from the model or from a file (``tableOnFile``, ``tableName``,
    ``fileName``, ``delimiter``, ``nHeaderLines``).  Output ``y[i]`` is
    ``offset[i]`` plus column ``columns[i]`` at ``time/timeScale`` shifted
    by ``shiftTime`` (``offset`` alone before ``startTime``), with every
    ``smoothness`` and ``extrapolation`` of Modelica.Blocks.Types
    (:mod:`acausal.interpolation`).

    As in the MSL, a when-clause holds the next time event,
    ``when {time >= pre(nextTimeEvent), initial()} then nextTimeEventScaled
    = next event after time/timeScale``, and the outputs interpolate within
    the event interval that ends there: a time event at each table time
    (``timeEvents = Always``, LinearSegments), at the jumps only
    (``AtDiscontinuities``) or none (``NoTimeEvents``; the smooth
    interpolations always), plus the table's start and end, the periods of
    ``Periodic`` and ``startTime``.  One relation whatever the number of
    rows, and a look-up of O(log n).  The outputs' time derivatives are the
    table's own (a Der block after it, or index reduction, differentiates
    the interpolation).
    """

    modelica_name = "Modelica.Blocks.Sources.CombiTimeTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column; e.g., table=[0, 0; 1, 1; 2, 4])")
    columns = Parameter(None, structural=True,
                        description="Columns of table to be interpolated (default 2, ..., number of columns)")
    smoothness = Parameter(Smoothness.LinearSegments, structural=True,
                           description="Smoothness of table interpolation")
    extrapolation = Parameter(Extrapolation.LastTwoPoints, structural=True,
                              description="Extrapolation of data outside the definition range")
    timeScale = Parameter(1.0, unit="s", min=EPS, description="Time scale of first table column")  # noqa: N815
    offset = Parameter((0.0,), structural=True, description="Offsets of output signals")
    startTime = Parameter(0.0, unit="s", finite=False,  # noqa: N815
                          description="Output = offset for time < startTime")
    shiftTime = Parameter(None, unit="s", description="Shift time of first table column (default startTime)")  # noqa: N815
    timeEvents = Parameter(TimeEvents.Always, structural=True,  # noqa: N815
                           description="Time event handling of table interpolation")
    verboseExtrapolation = Parameter(False, structural=True,  # noqa: N815
                                     description="= true, if warning messages are to be printed if time is "
                                                 "outside the table definition range")
    nextTimeEvent = Variable(start=0.0, fixed=True, unit="s", discrete=True,  # noqa: N815
                             description="Next time event instant (protected)")
    nextTimeEventScaled = Variable(start=0.0, fixed=True, discrete=True,  # noqa: N815
                                   description="Next scaled time event instant (protected)")

    derived_defaults = {"shiftTime": lambda block: block.startTime}

    @classmethod
    def arrays(cls, value):
        offset = value("offset")
        n_offset = len(offset) if isinstance(offset, (list, tuple)) else 1
        matrix = cls.read_matrix(value, cls.__name__)
        nout = max(len(default_columns(matrix, value("columns"))), n_offset)
        return {"y": (nout, lambda i: RealOutput(description="Connector of Real output signals"))}

    def numeric_table(self) -> NumericTimeTable:
        where = self.path or type(self).__name__
        matrix = self.matrix()
        columns = default_columns(matrix, self.columns)
        y = self.vector("y")
        if len(columns) == 1:
            columns = columns * len(y)
        return NumericTimeTable(matrix, columns, Smoothness(self.smoothness), Extrapolation(self.extrapolation),
                                TimeEvents(self.timeEvents), name=where)

    def equations(self):
        where = self.path or type(self).__name__
        table = self.numeric_table()
        y = self.vector("y")
        offset = list(self.offset) if isinstance(self.offset, (list, tuple)) else [self.offset]
        if len(offset) == 1:
            offset = offset * len(y)
        if len(offset) != len(y) or table.n_outputs != len(y):
            raise ParameterError(f"{where}: columns ({table.n_outputs}) and offset ({len(offset)}) have different "
                                 f"sizes", hint="give one offset per column, or a single offset")
        scaled = time / self.timeScale
        start, shift = self.startTime / self.timeScale, self.shiftTime / self.timeScale
        equations = []
        for i, (yi, off) in enumerate(zip(y, offset)):
            value, following = time_table_functions(table, i, f"{where}.table")
            equations.append(Eq(yi, off + value(scaled, self.nextTimeEventScaled, start, shift)))
        # the next event after the one being processed: from the instant that fired (time/timeScale
        # may round below it), from time itself at initialization
        after = If(is_initial(), scaled, sp.Max(scaled, pre(self.nextTimeEventScaled)))
        # no further event: Modelica.Constants.inf (1e60), a finite number, as the MSL holds it
        equations.append(When([time >= pre(self.nextTimeEvent), initial()],
                              Eq(self.nextTimeEventScaled, sp.Min(following(after, start, shift), MODELICA_INF)),
                              Eq(self.nextTimeEvent, self.nextTimeEventScaled * self.timeScale)))
        if len(table.data) > 1:
            inside = sp.Or(time < self.startTime,
                           sp.And(time >= self.shiftTime + table.t_min * self.timeScale,
                                  time <= self.shiftTime + table.t_max * self.timeScale))
            equations += range_asserts(where, Extrapolation(self.extrapolation), bool(self.verboseExtrapolation),
                                       inside, "the time")
        return equations


class _StepTable(Component):
    """What BooleanTable and IntegerTable share: MSL 4.1 builds each from a CombiTimeTable
    with constant segments (``combiTimeTable``) and a conversion of its output."""

    extrapolation = Parameter(Extrapolation.HoldLastPoint, structural=True,
                              description="Extrapolation of data outside the definition range")
    startTime = Parameter(-math.inf, unit="s", finite=False,  # noqa: N815
                          description="Output = 0 (false) for time < startTime")
    shiftTime = Parameter(0.0, unit="s", description="Shift time of table")  # noqa: N815

    def check_extrapolation(self) -> None:
        if Extrapolation(self.extrapolation) is Extrapolation.LastTwoPoints:
            where = self.path or type(self).__name__
            raise ParameterError(f"{where}: unsuitable extrapolation setting LastTwoPoints",
                                 hint="use HoldLastPoint (the default), Periodic or NoExtrapolation")

    def build_steps(self, rows: list, conversion: Component, name: str) -> None:
        """``combiTimeTable`` of ``rows`` (constant segments) feeding ``conversion`` (as ``name``),
        whose output is this block's ``y``."""
        self.combiTimeTable = CombiTimeTable(table=rows, smoothness=Smoothness.ConstantSegments, columns=[2],
                                             extrapolation=self.extrapolation, startTime=self.startTime,
                                             shiftTime=self.shiftTime)
        setattr(self, name, conversion)
        self.connect(getattr(self.combiTimeTable, "y[1]"), conversion.u)
        self.connect(conversion.y, self.y)


class IntegerTable(_StepTable):
    """Generate an Integer output signal based on a table matrix with [time, yi] values
    (Modelica.Blocks.Sources.IntegerTable).

    As MSL 4.1 builds it: a CombiTimeTable with constant segments (times
    strictly increasing, values Integers) and a RealToInteger.  The output
    holds ``table[i, 2]`` from ``table[i, 1]`` on; ``extrapolation``
    (HoldLastPoint by default; LastTwoPoints is refused, as in the MSL),
    ``startTime`` and ``shiftTime`` act as in the CombiTimeTable.
    """

    modelica_name = "Modelica.Blocks.Sources.IntegerTable"

    table = Parameter(((0.0, 0.0),), structural=True,
                      description="Table matrix (time = first column, integer output = second column)")
    y = IntegerOutput(description="Connector of Integer output signal")

    def build(self) -> None:
        where = self.path or type(self).__name__
        self.check_extrapolation()
        rows = _rows(self.table, where, 2)
        if len(rows[0]) != 2:
            raise ParameterError(f"{where}.table must have 2 columns (time, value), not {len(rows[0])}")
        for i in range(1, len(rows)):
            if not rows[i][0] > rows[i - 1][0]:
                raise ParameterError(
                    f"{where}.table: time values of table not strictly increasing: table[{i},1] = "
                    f"{rows[i - 1][0]:g}, table[{i + 1},1] = {rows[i][0]:g}",
                    hint="list each switching instant once, in increasing order")
        for i, (_t, v) in enumerate(rows, start=1):
            if v != int(v):
                raise ParameterError(f"{where}.table: table value is not an Integer: table[{i},2] = {v:g}")
        self.build_steps(rows, RealToInteger(), "realToInteger")
