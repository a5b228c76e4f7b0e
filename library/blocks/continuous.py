"""Continuous blocks (Modelica.Blocks.Continuous)."""

from __future__ import annotations

from typing import Any, Callable, Mapping

import numpy as np
import sympy as sp

from acausal.arrays import Array, transpose
from acausal.components.blocks import MIMO, SISO, BooleanInput
from acausal.components.declarations import DerivedDefaults
from acausal.errors import ArraySizeError, ModifierError
from acausal.hybrid import Assert, When, noEvent, reinit
from acausal.language import Component, Eq, If, Parameter, RealInput, RealOutput, Variable, der
from acausal.components.logic import is_initial

from .types import Init, SimpleController, _init_type, initial_equations_for, simple_controller
from .math import Add, Add3, Gain
from .nonlinear import Limiter, LimiterHomotopy
from .sources import Constant

__all__ = ["Init", "SimpleController", "Integrator", "LimIntegrator", "FirstOrder", "Der", "Derivative", "SecondOrder",
           "PI", "PID", "LimPID", "TransferFunction", "StateSpace"]

#: Modelica.Constants.eps: the difference between 1 and the next float.
EPS = 2.2204460492503131e-16
#: Modelica.Constants.small: the smallest positive normalized float.
SMALL = 2.2250738585072014e-308


class _InitializedOutput(SISO):
    """A block whose state is its output ``y``, initialized as ``initType`` says.

    ``InitialState``/``InitialOutput``: ``y(start=y_start, fixed=true)``;
    ``SteadyState``: the initial equation ``der(y) = 0``; ``NoInit``:
    ``y_start`` is a guess.  A modifier of ``y`` itself wins.
    """

    #: initType of the class (Modelica's default differs between blocks)
    default_init = Init.InitialState

    def __init__(self, **modifiers) -> None:
        super().__init__(**modifiers)
        attributes = self._attribute_modifiers.setdefault("y", {})
        attributes.setdefault("start", lambda block: block.y_start)
        init = _init_type(self.initType)
        attributes.setdefault("fixed", init in (Init.InitialState, Init.InitialOutput))

    def initial_equations(self):
        if _init_type(self.initType) is Init.SteadyState:
            return [Eq(der(self.y), 0)]
        return []


class _PartialIntegrator(_InitializedOutput):
    """What Integrator and LimIntegrator share: gain, initialization and the optional reset.

    With ``use_reset`` the Boolean input ``reset`` appears: where it becomes
    true (its rising edge), ``y`` is reinitialized (``reinit``) to
    :meth:`_reset_value`: ``y_start``, or with ``use_set`` the input ``set``.
    """

    k = Parameter(1.0, unit="1", description="Integrator gains")
    use_reset = Parameter(False, structural=True, description="= true, if reset port enabled")
    use_set = Parameter(False, structural=True,
                        description="= true, if set port enabled and used as reinitialization value when reset")
    initType = Parameter(Init.InitialState, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3,4: initial output)")
    y_start = Parameter(0.0, description="Initial or guess value of output (= state)")
    reset = BooleanInput(condition="use_reset", description="Optional connector of reset signal")
    set = RealInput(condition=lambda block: block.use_reset and block.use_set,
                    description="Optional connector of set signal")

    def _reset_value(self):
        return self.set if self.use_set else self.y_start

    def equations(self):
        if self.use_reset:
            return [When(self.reset, reinit(self.y, self._reset_value()))]
        return []


class Integrator(_PartialIntegrator):
    """Output the integral of the input (Modelica.Blocks.Continuous.Integrator).

    ``der(y) = k*u`` with ``y(start=y_start, fixed=true)`` (MSL's default
    ``initType = InitialState``).  Integrating a power signal gives the work
    done, which is how energy audits are written inside a model.

    With ``use_reset`` the Boolean input ``reset`` appears: where it becomes
    true (its rising edge), ``y`` is reinitialized to ``y_start``, or with
    ``use_set`` to the input ``set``.
    """

    modelica_name = "Modelica.Blocks.Continuous.Integrator"

    def equations(self):
        return [Eq(der(self.y), self.k * self.u)]


class LimIntegrator(DerivedDefaults, _PartialIntegrator):
    """Integrator with limited value of the output and optional reset (Modelica.Blocks.Continuous.LimIntegrator).

    ``der(y) = k*u`` while ``outMin <= y <= outMax``; at a limit the
    integration stops as long as ``k*u`` drives ``y`` further out (without
    ``strict``, the switching instants are state events).  A reset
    reinitializes ``y`` to the reset value clamped to the limits.
    """

    modelica_name = "Modelica.Blocks.Continuous.LimIntegrator"

    outMax = Parameter(1.0, description="Upper limit of output")  # noqa: N815
    outMin = Parameter(None, description="Lower limit of output (default -outMax)")  # noqa: N815
    limitsAtInit = Parameter(True, structural=True,  # noqa: N815
                             description="= false, if limits are ignored during initialization "
                                         "(i.e., der(y)=k*u)")
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")

    derived_defaults = {"outMin": lambda block: -block.outMax}

    def _reset_value(self):
        value = super()._reset_value()
        return sp.Piecewise((self.outMax, value > self.outMax), (self.outMin, value < self.outMin),
                            (value, True))

    def equations(self):
        rate = self.k * self.u
        limited = sp.Piecewise(
            (0, sp.Or(sp.And(self.y < self.outMin, rate < 0), sp.And(self.y > self.outMax, rate > 0))),
            (rate, True))
        if self.strict:
            limited = noEvent(limited)
        if self.limitsAtInit:
            return [Eq(der(self.y), limited)]
        spread = 0.001 * sp.Abs(self.outMax - self.outMin)
        return [Eq(der(self.y), If(is_initial(), rate, limited)),
                Assert(sp.Or(sp.Not(is_initial()),
                             sp.And(self.y >= self.outMin - spread, self.y <= self.outMax + spread)),
                       "LimIntegrator: during initialization the limits have been ignored, "
                       "but the initial output is outside of the limits outMin..outMax")]


class FirstOrder(_InitializedOutput):
    """First order transfer function block (Modelica.Blocks.Continuous.FirstOrder).

    ``T*der(y) + y = k*u``; by default (``initType = NoInit``) ``y_start`` is
    only a guess of the initial output.
    """

    modelica_name = "Modelica.Blocks.Continuous.FirstOrder"

    k = Parameter(1.0, description="Gain")
    T = Parameter(1.0, unit="s", min=0, description="Time Constant")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, "
                                     "3/4: initial output)")
    y_start = Parameter(0.0, description="Initial or guess value of output (= state)")

    def equations(self):
        return [Eq(der(self.y), (self.k * self.u - self.y) / self.T)]


class Der(SISO):
    """Derivative of input (= analytic differentiations) (Modelica.Blocks.Continuous.Der): ``y = der(u)``.

    The derivative is symbolic: what drives ``u`` is differentiated (index
    reduction), not differenced numerically.
    """

    modelica_name = "Modelica.Blocks.Continuous.Der"

    def equations(self):
        return [Eq(self.y, der(self.u))]


class Derivative(SISO):
    """Approximated derivative block (Modelica.Blocks.Continuous.Derivative).

    The transfer function ``k*s/(T*s + 1)``, written with the state ``x``
    of a first order lag on ``u``: ``der(x) = (u - x)/T`` and
    ``y = (k/T)*(u - x)``.  A gain ``|k| < eps`` makes the block the zero
    output (the state then stays put).

    ``initType`` (``NoInit`` by default, as in the MSL): ``SteadyState``:
    ``der(x) = 0``; ``InitialState``: ``x = x_start``; ``InitialOutput``:
    ``y = y_start`` (with a zero gain, ``x = u``).
    """

    modelica_name = "Modelica.Blocks.Continuous.Derivative"

    k = Parameter(1.0, unit="1", description="Gains")
    T = Parameter(0.01, unit="s", min=SMALL,
                  description="Time constants (T>0 required; T=0 is ideal derivative block)")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x_start = Parameter(0.0, description="Initial or guess value of state")
    y_start = Parameter(0.0, description="Initial value of output (= state)")
    x = RealOutput(start=lambda block: block.x_start, description="State of block")

    def _zero_gain(self) -> sp.Basic:
        """MSL's protected ``zeroGain``: the gain is too small to divide by."""
        return sp.Abs(self.k) < EPS

    def equations(self) -> list:
        zero_gain = self._zero_gain()
        return [Eq(der(self.x), If(zero_gain, 0, (self.u - self.x) / self.T)),
                Eq(self.y, If(zero_gain, 0, (self.k / self.T) * (self.u - self.x)))]

    def initial_equations(self) -> list:
        # InitialOutput: with a zero gain y = 0 whatever x is: start the lag on its input instead
        return initial_equations_for(self.initType, [Eq(der(self.x), 0)], [Eq(self.x, self.x_start)],
                                     [Eq(If(self._zero_gain(), self.x - self.u, self.y - self.y_start), 0)])


class SecondOrder(SISO):
    """Second order transfer function block (= 2 poles) (Modelica.Blocks.Continuous.SecondOrder).

    ``k/((s/w)^2 + 2*D*(s/w) + 1)``: ``der(y) = yd`` and
    ``der(yd) = w*(w*(k*u - y) - 2*D*yd)``.

    ``initType`` (``NoInit`` by default, as in the MSL): ``SteadyState``:
    ``der(y) = der(yd) = 0``; ``InitialState`` and ``InitialOutput``:
    ``y = y_start``, ``yd = yd_start``.
    """

    modelica_name = "Modelica.Blocks.Continuous.SecondOrder"

    k = Parameter(1.0, unit="1", description="Gain")
    w = Parameter(1.0, description="Angular frequency")
    D = Parameter(1.0, description="Damping")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3/4: initial output)")
    y_start = Parameter(0.0, description="Initial or guess value of output (= state)")
    yd_start = Parameter(0.0, description="Initial or guess value of derivative of output (= state)")
    yd = RealOutput(start=lambda block: block.yd_start, description="Derivative of y")

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**modifiers)
        # Modelica's y(start=y_start); a modifier of y itself wins
        self._attribute_modifiers.setdefault("y", {}).setdefault("start", lambda block: block.y_start)

    def equations(self) -> list:
        return [Eq(der(self.y), self.yd),
                Eq(der(self.yd), self.w * (self.w * (self.k * self.u - self.y) - 2 * self.D * self.yd))]

    def initial_equations(self) -> list:
        at_start = [Eq(self.y, self.y_start), Eq(self.yd, self.yd_start)]
        return initial_equations_for(self.initType, [Eq(der(self.y), 0), Eq(der(self.yd), 0)], at_start, at_start)


class PI(SISO):
    """Proportional-Integral controller (Modelica.Blocks.Continuous.PI).

    ``k*(1 + 1/(T*s))``: ``der(x) = u/T`` and ``y = k*(x + u)``.

    ``initType`` (``NoInit`` by default, as in the MSL): ``SteadyState``:
    ``der(x) = 0``; ``InitialState``: ``x = x_start``; ``InitialOutput``:
    ``y = y_start``.
    """

    modelica_name = "Modelica.Blocks.Continuous.PI"

    k = Parameter(1.0, unit="1", description="Gain")
    T = Parameter(1.0, unit="s", min=SMALL, description="Time Constant (T>0 required)")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x_start = Parameter(0.0, description="Initial or guess value of state")
    y_start = Parameter(0.0, description="Initial value of output")
    x = RealOutput(start=lambda block: block.x_start, description="State of block")

    def equations(self) -> list:
        return [Eq(der(self.x), self.u / self.T), Eq(self.y, self.k * (self.x + self.u))]

    def initial_equations(self) -> list:
        return initial_equations_for(self.initType, [Eq(der(self.x), 0)], [Eq(self.x, self.x_start)],
                                     [Eq(self.y, self.y_start)])


def _integrator_init(init: Any) -> Init:
    """The initType of a controller's integrator: SteadyState and InitialState pass, the others are NoInit."""
    init = _init_type(init)
    return init if init in (Init.SteadyState, Init.InitialState) else Init.NoInit


def _derivative_init(init: Any) -> Init:
    """The initType of a controller's derivative block.

    InitialOutput puts it in steady state (the controller's output alone is
    given), InitialState passes, the others are NoInit.
    """
    init = _init_type(init)
    if init in (Init.SteadyState, Init.InitialOutput):
        return Init.SteadyState
    return init if init is Init.InitialState else Init.NoInit


class PID(SISO):
    """PID controller in additive description form (Modelica.Blocks.Continuous.PID).

    ``y = k*(u + I.y + D.y)``: the sum (``Add``) of the proportional part
    ``P`` (a unit gain), the integrator ``I`` (gain ``1/Ti``) and the
    approximated derivative ``D`` (gain ``Td``, time constant
    ``max(Td/Nd, 100*eps)``), times the gain ``Gain`` (``k``); the parts are
    sub-components named as in the MSL (``pid.I.y``, ``pid.D.x``).

    ``initType`` (``InitialState`` by default, as in the MSL) is passed on:
    ``InitialState`` starts ``I`` at ``xi_start`` and ``D`` at
    ``xd_start``; ``SteadyState`` puts both in steady state;
    ``InitialOutput`` gives ``y = y_start`` with ``D`` in steady state;
    ``NoInit`` leaves the start values as guesses.
    """

    modelica_name = "Modelica.Blocks.Continuous.PID"

    k = Parameter(1.0, unit="1", description="Gain")
    Ti = Parameter(0.5, unit="s", min=SMALL, description="Time Constant of Integrator")
    Td = Parameter(0.1, unit="s", min=0, description="Time Constant of Derivative block")
    Nd = Parameter(10.0, min=SMALL, description="The higher Nd, the more ideal the derivative block")
    initType = Parameter(Init.InitialState, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    xi_start = Parameter(0.0, description="Initial or guess value for integrator output (= integrator state)")
    xd_start = Parameter(0.0, description="Initial or guess value for state of derivative block")
    y_start = Parameter(0.0, description="Initial value of output")

    def build(self) -> None:
        self.P = Gain(k=1.0)
        # MSL's k = unitTime/Ti and Td/unitTime, with the constant unitTime = 1 s
        self.I = Integrator(k=1 / self.Ti, y_start=self.xi_start, initType=_integrator_init(self.initType))
        self.D = Derivative(k=self.Td, T=sp.Max(self.Td / self.Nd, 100 * EPS), x_start=self.xd_start,
                            initType=_derivative_init(self.initType))
        self.Gain = Gain(k=self.k)
        self.Add = Add3()
        for part in (self.P, self.I, self.D):
            self.connect(self.u, part.u)
        self.connect(self.P.y, self.Add.u1)
        self.connect(self.I.y, self.Add.u2)
        self.connect(self.D.y, self.Add.u3)
        self.connect(self.Add.y, self.Gain.u)
        self.connect(self.Gain.y, self.y)

    def initial_equations(self) -> list:
        if _init_type(self.initType) is Init.InitialOutput:
            return [Eq(self.y, self.y_start)]
        return []


class LimPID(DerivedDefaults, Component):
    """P, PI, PD, and PID controller with limited output, anti-windup compensation, setpoint weighting and
    optional feed-forward (Modelica.Blocks.Continuous.LimPID).

    ``controllerType`` (:class:`~acausal.library.blocks.types.SimpleController`,
    PID by default) says which parts exist; they are sub-components named as
    in the MSL::

        y = limiter(k*(P + I + D) + kFF*u_ff)
        P = wp*u_s - u_m
        D = Td*s/(Td/Nd*s + 1) * (wd*u_s - u_m)
        I = 1/(Ti*s) * (u_s - u_m + (y - (k*(P + I + D) + kFF*u_ff))/(k*Ni))

    The last term is the anti-windup compensation: while the limiter holds
    the output, the difference it cuts off drives the integrator back with
    the time constant ``Ni*Ti``.  The limiter's switching is a state event
    unless ``strict``.

    ``initType`` (``InitialState`` by default): ``InitialState`` starts the
    integrator at ``xi_start`` and the derivative block at ``xd_start``;
    ``SteadyState`` puts both in steady state; ``InitialOutput`` gives the
    controller's output before the limiter, ``gainPID.y = y_start``, with
    the derivative block in steady state (``y_start`` must lie within the
    limits); ``NoInit`` leaves the start values as guesses.

    ``homotopyType`` is passed to the limiter; the engine has no
    homotopy-based initialization, so it has no effect.
    """

    modelica_name = "Modelica.Blocks.Continuous.LimPID"

    controllerType = Parameter(SimpleController.PID, structural=True,  # noqa: N815
                               description="Type of controller")
    k = Parameter(1.0, unit="1", description="Gain of controller, must be non-zero")
    Ti = Parameter(0.5, unit="s", min=SMALL, description="Time constant of Integrator block")
    Td = Parameter(0.1, unit="s", min=0, description="Time constant of Derivative block")
    yMax = Parameter(1.0, description="Upper limit of output")  # noqa: N815
    yMin = Parameter(None, description="Lower limit of output (default -yMax)")  # noqa: N815
    wp = Parameter(1.0, min=0, description="Set-point weight for Proportional block (0..1)")
    wd = Parameter(0.0, min=0, description="Set-point weight for Derivative block (0..1)")
    Ni = Parameter(0.9, min=100 * EPS, description="Ni*Ti is time constant of anti-windup compensation")
    Nd = Parameter(10.0, min=100 * EPS, description="The higher Nd, the more ideal the derivative block")
    withFeedForward = Parameter(False, structural=True,  # noqa: N815
                                description="Use feed-forward input?")
    kFF = Parameter(1.0, description="Gain of feed-forward input")  # noqa: N815
    initType = Parameter(Init.InitialState, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    xi_start = Parameter(0.0, description="Initial or guess value for integrator output (= integrator state)")
    xd_start = Parameter(0.0, description="Initial or guess value for state of derivative block")
    y_start = Parameter(0.0, description="Initial value of output")
    homotopyType = Parameter(LimiterHomotopy.Linear, structural=True,  # noqa: N815
                             description="Simplified model for homotopy-based initialization (no effect here)")
    strict = Parameter(False, structural=True, description="= true, if strict limits with noEvent(..)")

    u_s = RealInput(description="Connector of setpoint input signal")
    u_m = RealInput(description="Connector of measurement input signal")
    y = RealOutput(description="Connector of actuator output signal")
    u_ff = RealInput(condition="withFeedForward", description="Optional connector of feed-forward input signal")
    controlError = Variable(description="Control error (set point - measurement)")  # noqa: N815

    derived_defaults = {"yMin": lambda block: -block.yMax}

    def build(self) -> None:
        kind = simple_controller(self.controllerType)
        self.addP = Add(k1=self.wp, k2=-1.0)
        self.P = Gain(k=1.0)
        self.gainPID = Gain(k=self.k)
        self.addPID = Add3()
        self.limiter = Limiter(uMax=self.yMax, uMin=self.yMin, strict=self.strict, homotopyType=self.homotopyType)
        self.addFF = Add(k1=1.0, k2=self.kFF)
        self.connect(self.u_s, self.addP.u1)
        self.connect(self.u_m, self.addP.u2)
        self.connect(self.addP.y, self.P.u)
        self.connect(self.P.y, self.addPID.u1)
        self.connect(self.addPID.y, self.gainPID.u)
        self.connect(self.gainPID.y, self.addFF.u1)
        self.connect(self.addFF.y, self.limiter.u)
        self.connect(self.limiter.y, self.y)

        if kind.has_derivative:
            self.addD = Add(k1=self.wd, k2=-1.0)
            # MSL's k = Td/unitTime with the constant unitTime = 1 s
            self.D = Derivative(k=self.Td, T=sp.Max(self.Td / self.Nd, 1.0e-14), x_start=self.xd_start,
                                initType=_derivative_init(self.initType))
            self.connect(self.u_s, self.addD.u1)
            self.connect(self.u_m, self.addD.u2)
            self.connect(self.addD.y, self.D.u)
            self.connect(self.D.y, self.addPID.u2)
        else:
            self.Dzero = Constant(k=0.0)
            self.connect(self.Dzero.y, self.addPID.u2)

        if kind.has_integral:
            self.addI = Add3(k2=-1.0)
            self.I = Integrator(k=1 / self.Ti, y_start=self.xi_start, initType=_integrator_init(self.initType))
            self.addSat = Add(k1=1.0, k2=-1.0)
            self.gainTrack = Gain(k=1 / (self.k * self.Ni))
            self.connect(self.u_s, self.addI.u1)
            self.connect(self.u_m, self.addI.u2)
            self.connect(self.addI.y, self.I.u)
            self.connect(self.I.y, self.addPID.u3)
            # anti-windup: what the limiter cuts off, fed back to the integrator's input
            self.connect(self.limiter.y, self.addSat.u1)
            self.connect(self.addFF.y, self.addSat.u2)
            self.connect(self.addSat.y, self.gainTrack.u)
            self.connect(self.gainTrack.y, self.addI.u3)
        else:
            self.Izero = Constant(k=0.0)
            self.connect(self.Izero.y, self.addPID.u3)

        if self.withFeedForward:
            self.connect(self.u_ff, self.addFF.u2)
        else:
            self.FFzero = Constant(k=0.0)
            self.connect(self.FFzero.y, self.addFF.u2)

    def equations(self) -> list:
        equations = [Eq(self.controlError, self.u_s - self.u_m),
                     Assert(sp.Abs(self.k) >= SMALL, "Controller gain must be non-zero.")]
        if _init_type(self.initType) is Init.InitialOutput:
            equations.append(Assert(sp.And(self.y_start >= self.yMin, self.y_start <= self.yMax),
                                    "LimPID: Start value y_start is outside of the limits of yMin and yMax"))
        return equations

    def initial_equations(self) -> list:
        if _init_type(self.initType) is Init.InitialOutput:
            return [Eq(self.gainPID.y, self.y_start)]
        return []


# --------------------------------------------------------------------------
# Linear systems: sizes from the coefficient arrays
# --------------------------------------------------------------------------


def _array_shape(value: Any, what: str) -> tuple[int, ...]:
    """The shape of a parameter value given as nested lists, a numpy array or an :class:`Array`.

    Raises
    ------
    ArraySizeError
        For rows of different lengths.
    """
    data = value.data if isinstance(value, Array) else value
    try:
        array = np.asarray(data, dtype=object)
    except ValueError as exc:  # numpy refuses some ragged nestings outright
        raise ArraySizeError(f"{what} has rows of different lengths",
                             hint="give a matrix as a list of equally long rows") from exc
    if array.ndim and any(isinstance(item, (list, tuple, np.ndarray, Array)) for item in array.reshape(-1)):
        raise ArraySizeError(f"{what} has rows of different lengths",
                             hint="give a matrix as a list of equally long rows")
    return tuple(array.shape)


def _matrix_shape(value: Any, what: str) -> tuple[int, int]:
    """``(rows, columns)`` of a matrix parameter value (an error for anything but a matrix)."""
    shape = _array_shape(value, what)
    if len(shape) != 2:
        raise ArraySizeError(f"{what} is a matrix, the value given has size [{', '.join(map(str, shape))}]",
                             hint="give a matrix as a list of rows: a column is [[1], [1]], a row [[1, 1]]")
    return shape[0], shape[1]


def _vector_length(value: Any, what: str) -> int:
    """The length of a vector parameter value (an error for anything but a non-empty vector)."""
    shape = _array_shape(value, what)
    if len(shape) != 1:
        raise ArraySizeError(f"{what} is a vector, the value given has size [{', '.join(map(str, shape))}]",
                             hint="give the coefficients as a list, e.g. [1, 1] for s + 1")
    if shape[0] == 0:
        raise ArraySizeError(f"{what} is empty", hint="give at least one coefficient")
    return shape[0]


class _SizedByValues(Component):
    """A block whose array sizes follow from the values of its array parameters.

    Modelica's ``parameter Integer nx = size(A, 1)`` and ``MIMO(final
    nin = size(B, 2))``: :meth:`derived_sizes` computes the structural
    Integer parameters from the values given at construction (or the
    declared defaults), and they are set as modifiers before the arrays are
    sized.  A modifier giving one of them another value is an error (they
    are ``final`` in Modelica).

    The core sizes arrays by structural parameters that a modifier or a
    declared default gives; it has no derived structural defaults, so this
    class supplies them in ``__new__`` and ``__init__``.
    """

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """``{structural parameter: (size, what it is)}``; ``value(p)`` reads parameter ``p``'s value.

        Raises
        ------
        ArraySizeError
            For values whose sizes do not fit together.
        """
        return {}

    def __new__(cls, *args: Any, **modifiers: Any):
        return super().__new__(cls, *args, **cls._with_derived_sizes(modifiers))

    def __init__(self, **modifiers: Any) -> None:
        modifiers = type(self)._with_derived_sizes(modifiers)
        # Every array parameter gets its value as a modifier: the core's sized class (one per
        # base class and shapes) takes its elements' defaults from the values given to the
        # first instance of those shapes, which a later instance would otherwise inherit.
        base = vars(type(self)).get("_unsized", type(self))
        for name in type(self)._array_shapes:
            declaration = base.declarations().get(name)
            if isinstance(declaration, Parameter) and name not in modifiers:
                modifiers[name] = declaration.default
        super().__init__(**modifiers)

    @classmethod
    def _with_derived_sizes(cls, modifiers: Mapping[str, Any]) -> dict[str, Any]:
        """``modifiers`` with the derived sizes added (checking those given against them)."""
        base = vars(cls).get("_unsized", cls)
        declarations = base.declarations()

        def value(name: str) -> Any:
            return modifiers[name] if name in modifiers else declarations[name].default

        sizes = base.derived_sizes(value)
        for name, (size, source) in sizes.items():
            if name in modifiers and modifiers[name] != size:
                raise ModifierError(f"{base.__name__}.{name} = {modifiers[name]!r}, but {source} is {size}",
                                    hint=f"leave {name} out: {base.__name__} takes it from {source}")
        return {**modifiers, **{name: size for name, (size, _) in sizes.items()}}


_SIZES_HINT = "A is nx x nx, B nx x nin, C nout x nx and D nout x nin"


def _is_init(block: Component, init: Init) -> bool:
    """Whether ``block.initType`` is ``init``."""
    return _init_type(block.initType) is init


class StateSpace(_SizedByValues, MIMO):
    """Linear state space system (Modelica.Blocks.Continuous.StateSpace).

    ``der(x) = A*x + B*u`` and ``y = C*x + D*u``, with ``nx = size(A, 1)``
    states, ``nin = size(B, 2)`` inputs and ``nout = size(C, 1)`` outputs.
    The sizes follow from the matrices given, as nested lists of rows::

        StateSpace(A=[[0, 1], [-4, -0.4]], B=[[0], [1]], C=[[1, 0]])

    ``D`` defaults to zeros.  The elements are named as in Modelica
    (``x[1]``, ``u[1]``, ``A[2,1]``): the matrix elements are tunable
    parameters, their sizes structural.  Matrices whose sizes do not fit
    together are an :class:`~acausal.errors.ArraySizeError` naming both
    sizes.

    ``initType`` (``NoInit`` by default, as in the MSL):

    * ``NoInit``: ``x_start`` is only the guess of the states.
    * ``SteadyState``: ``der(x) = 0`` at the start.
    * ``InitialState``: ``x = x_start``.
    * ``InitialOutput``: as in MSL 4.1.0, ``x`` is
      ``Modelica.Math.Matrices.equalityLeastSquares(A, -B*u, C, y_start - D*u)``:
      among the states with ``y = y_start``, those of least ``|der(x)|``.
      It is written as its optimality conditions,
      ``transpose(A)*(A*x + B*u) + transpose(C)*multiplier = 0`` and
      ``y = y_start``, with the Lagrange multipliers ``multiplier[1..nout]``:
      constants (``der(multiplier) = 0``) that the initialization
      determines and that exist with this initType only (Modelica would
      declare them ``parameter Real multiplier[nout](each fixed=false)``;
      here a parameter cannot be conditional).  The states are unique when
      ``C`` has full row rank and ``[A; C]`` full column rank, which
      equalityLeastSquares requires too.
    """

    modelica_name = "Modelica.Blocks.Continuous.StateSpace"

    A = Parameter([[1.0, 0.0], [0.0, 1.0]], description="Matrix A of state space model (e.g., A=[[1, 0], [0, 1]])")
    B = Parameter([[1.0], [1.0]], description="Matrix B of state space model (e.g., B=[[1], [1]])")
    C = Parameter([[1.0, 1.0]], description="Matrix C of state space model (e.g., C=[[1, 1]])")
    D = Parameter(0.0, shape=("nout", "nin"), description="Matrix D of state space model (default zeros)")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x_start = Parameter(0.0, shape="nx", description="Initial or guess values of states")
    y_start = Parameter(0.0, shape="nout",
                        description="Initial values of outputs (remaining states are in steady state if possible)")
    nx = Parameter(2, structural=True, description="Number of states (= size(A, 1), set from A)")
    x = RealOutput("nx", start=lambda block: block.x_start, description="State vector")
    multiplier = Variable(shape="nout", condition=lambda block: _is_init(block, Init.InitialOutput),
                          description="Lagrange multipliers of the least-squares initialization, constant "
                                      "(initType = InitialOutput only)")

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """``nx``, ``nin`` and ``nout`` from the shapes of ``A``, ``B`` and ``C``, checked with ``D``'s."""
        name = cls.__name__
        a_rows, a_cols = _matrix_shape(value("A"), f"{name}.A")
        b_rows, b_cols = _matrix_shape(value("B"), f"{name}.B")
        c_rows, c_cols = _matrix_shape(value("C"), f"{name}.C")
        if a_cols != a_rows:
            raise ArraySizeError(f"{name}: A is {a_rows} x {a_cols}, it must be square (nx x nx)", hint=_SIZES_HINT)
        if b_rows != a_rows:
            raise ArraySizeError(f"{name}: B has {b_rows} rows, A has {a_rows} (both are nx, the number of states)",
                                 hint=_SIZES_HINT)
        if c_cols != a_rows:
            raise ArraySizeError(f"{name}: C has {c_cols} columns, A has {a_rows} rows (both are nx, the number "
                                 f"of states)", hint=_SIZES_HINT)
        d = value("D")
        if isinstance(d, (list, tuple, np.ndarray, Array)):
            d_rows, d_cols = _matrix_shape(d, f"{name}.D")
            if (d_rows, d_cols) != (c_rows, b_cols):
                raise ArraySizeError(f"{name}: D is {d_rows} x {d_cols}, but nout x nin is {c_rows} x {b_cols} "
                                     f"(the rows of C, the columns of B)", hint=_SIZES_HINT)
        return {"nx": (a_rows, "the number of rows of A"),
                "nin": (b_cols, "the number of columns of B"),
                "nout": (c_rows, "the number of rows of C")}

    def equations(self) -> list:
        equations = [Eq(der(self.x), self.A @ self.x + self.B @ self.u),
                     Eq(self.y, self.C @ self.x + self.D @ self.u)]
        if _is_init(self, Init.InitialOutput):
            equations.append(Eq(der(self.multiplier), 0))
        return equations

    def initial_equations(self) -> list:
        init = _init_type(self.initType)
        if init is Init.SteadyState:
            return [Eq(der(self.x), 0)]
        if init is Init.InitialState:
            return [Eq(self.x, self.x_start)]
        if init is Init.InitialOutput:
            derivative = self.A @ self.x + self.B @ self.u
            return [Eq(transpose(self.A) @ derivative + transpose(self.C) @ self.multiplier, 0),
                    Eq(self.y, self.y_start)]
        return []


def _a_end(block: Component) -> sp.Expr:
    """MSL's ``a_end``: ``a[end]``, or 1 when it is (almost) zero or negative (scaling of ``x``)."""
    a = block.a.flat
    last = a[-1]
    return sp.Piecewise((last, last > 100 * EPS * sp.sqrt(sp.Add(*[c**2 for c in a]))), (1.0, True))


def _padded_numerator(block: Component) -> list[Any]:
    """MSL's ``bb``: the numerator coefficients padded with leading zeros to the length of ``a``."""
    b = block.b.flat
    return [sp.Integer(0)] * (block.na - block.nb) + b


class TransferFunction(_SizedByValues, DerivedDefaults, SISO):
    """Linear transfer function (Modelica.Blocks.Continuous.TransferFunction).

    ::

               b[1]*s^(nb-1) + b[2]*s^(nb-2) + ... + b[nb]
        y(s) = ------------------------------------------- * u(s)
               a[1]*s^(na-1) + a[2]*s^(na-2) + ... + a[na]

    ``TransferFunction(b=[2, 4], a=[1, 3])`` is ``(2*s + 4)/(s + 3)``.  The
    ``nx = na - 1`` states ``x`` are those of the controller canonical form;
    as in the MSL the block integrates the scaled states ``x_scaled = x*a_end``
    (``a_end = a[na]`` unless that is almost zero) and ``x_start`` is given
    for ``x``.  With ``nx = 0`` the block is the gain ``y = b[1]/a[1]*u``.
    ``b`` may not have more coefficients than ``a`` (a proper transfer
    function).  The coefficients are tunable parameters ``a[1]`` ...; their
    numbers structural.

    ``initType`` (``NoInit`` by default, as in the MSL): ``SteadyState``:
    ``der(x_scaled) = 0``; ``InitialState``: ``x = x_start``;
    ``InitialOutput``: ``y = y_start`` and the derivatives of ``y`` up to
    the ``nx-1``-th are zero (``der(x_scaled[2:nx]) = 0``); without states
    (``nx = 0``) that over-determines the initialization, as in Modelica.
    """

    modelica_name = "Modelica.Blocks.Continuous.TransferFunction"

    b = Parameter([1.0], description="Numerator coefficients of transfer function (e.g., 2*s+3 is specified "
                                     "as [2, 3])")
    a = Parameter([1.0], description="Denominator coefficients of transfer function (e.g., 5*s+6 is "
                                     "specified as [5, 6])")
    initType = Parameter(Init.NoInit, structural=True,  # noqa: N815
                         description="Type of initialization (1: no init, 2: steady state, 3: initial state, "
                                     "4: initial output)")
    x_start = Parameter(0.0, shape="nx", description="Initial or guess values of states")
    y_start = Parameter(0.0, description="Initial value of output (derivatives of y are zero up to nx-1-th "
                                         "derivative)")
    na = Parameter(1, structural=True, description="Size of Denominator of transfer function (set from a)")
    nb = Parameter(1, structural=True, description="Size of Numerator of transfer function (set from b)")
    nx = Parameter(0, structural=True, description="Number of states, na - 1 (set from a)")
    a_end = Parameter(None, description="a[na], or 1 if that is (almost) zero: the scaling of x_scaled")
    d = Parameter(None, description="Direct feed-through of u to y, bb[1]/a[1]")
    x = RealOutput("nx", start=lambda block: block.x_start,
                   description="State of transfer function from controller canonical form")
    x_scaled = Variable(shape="nx", start=lambda block: block.x_start * block.a_end,
                        description="Scaled vector x")

    derived_defaults = {"a_end": _a_end, "d": lambda block: _padded_numerator(block)[0] / block.a[1]}

    @classmethod
    def derived_sizes(cls, value: Callable[[str], Any]) -> dict[str, tuple[int, str]]:
        """``na``, ``nb`` and ``nx`` from the lengths of ``a`` and ``b`` (at most as many in ``b`` as in ``a``)."""
        name = cls.__name__
        na = _vector_length(value("a"), f"{name}.a")
        nb = _vector_length(value("b"), f"{name}.b")
        if nb > na:
            raise ArraySizeError(f"{name}: the transfer function is not proper: b has {nb} coefficients, "
                                 f"a has {na}", hint="give a at least as many coefficients as b")
        return {"na": (na, "the number of coefficients of a"), "nb": (nb, "the number of coefficients of b"),
                "nx": (na - 1, "the number of coefficients of a minus 1")}

    def equations(self) -> list:
        nx, na = self.nx, self.na
        if nx == 0:
            return [Eq(self.y, self.d * self.u)]
        a, x_scaled = self.a, self.x_scaled
        bb = Array(_padded_numerator(self))
        equations = [Eq(der(x_scaled[1]), (-(a[2:na] @ x_scaled) + self.a_end * self.u) / a[1])]
        if nx > 1:  # the chain of integrators; Modelica's x_scaled[2:nx] is empty for nx = 1
            equations.append(Eq(der(x_scaled[2:nx]), x_scaled[1:nx - 1]))
        equations += [Eq(self.y, ((bb[2:na] - self.d * a[2:na]) @ x_scaled) / self.a_end + self.d * self.u),
                      Eq(self.x, x_scaled / self.a_end)]
        return equations

    def initial_equations(self) -> list:
        init = _init_type(self.initType)
        if init is Init.SteadyState and self.nx > 0:
            return [Eq(der(self.x_scaled), 0)]
        if init is Init.InitialState and self.nx > 0:
            return [Eq(self.x_scaled, self.x_start * self.a_end)]
        if init is Init.InitialOutput:
            equations = [Eq(self.y, self.y_start)]
            if self.nx > 1:
                equations.append(Eq(der(self.x_scaled[2:self.nx]), 0))
            return equations
        return []
