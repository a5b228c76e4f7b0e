"""Continuous blocks (Modelica.Blocks.Continuous)."""

from __future__ import annotations

import enum

import sympy as sp

from acausal.components.blocks import SISO, BooleanInput
from acausal.components.declarations import DerivedDefaults
from acausal.hybrid import Assert, When, noEvent, reinit
from acausal.language import Eq, If, Parameter, RealInput, der
from acausal.components.logic import is_initial

__all__ = ["Init", "Integrator", "LimIntegrator", "FirstOrder", "Der"]


class Init(enum.IntEnum):
    """Type of initialization (Modelica.Blocks.Types.Init); the values are Modelica's ordinals."""

    NoInit = 1  #: no initialization (start values are guesses)
    SteadyState = 2  #: steady state initialization (derivatives of states are zero)
    InitialState = 3  #: initialization with initial states
    InitialOutput = 4  #: initialization with initial outputs (and steady state of the states if possible)


def _init_type(value) -> Init:
    """``value`` as an :class:`Init` (also accepts its name)."""
    if isinstance(value, str):
        return Init[value]
    return Init(value)


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

    def equations(self):
        return [Eq(der(self.y), self.k * self.u)]


class LimIntegrator(DerivedDefaults, _PartialIntegrator):
    """Integrator with limited value of the output and optional reset (Modelica.Blocks.Continuous.LimIntegrator).

    ``der(y) = k*u`` while ``outMin <= y <= outMax``; at a limit the
    integration stops as long as ``k*u`` drives ``y`` further out (without
    ``strict``, the switching instants are state events).  A reset
    reinitializes ``y`` to the reset value clamped to the limits.
    """

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

    def equations(self):
        return [Eq(self.y, der(self.u))]
