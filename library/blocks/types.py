"""Enumerations shared by blocks and components (Modelica.Blocks.Types), and what they mean."""

from __future__ import annotations

import enum
from typing import Any

import sympy as sp

from acausal.components.checks import where
from acausal.errors import ParameterError
from acausal.hybrid import smooth
from acausal.language import If

__all__ = ["Init", "SimpleController", "Regularization", "regularization", "regularized_sign"]


class Init(enum.IntEnum):
    """Type of initialization (Modelica.Blocks.Types.Init); the values are Modelica's ordinals."""

    NoInit = 1  #: no initialization (start values are guesses)
    SteadyState = 2  #: steady state initialization (derivatives of states are zero)
    InitialState = 3  #: initialization with initial states
    InitialOutput = 4  #: initialization with initial outputs (and steady state of the states if possible)


# set after the body: in an IntEnum's body a str would become a member
Init.modelica_name = "Modelica.Blocks.Types.Init"


def _init_type(value: Any) -> Init:
    """``value`` as an :class:`Init` (also accepts its name)."""
    if isinstance(value, str):
        return Init[value]
    return Init(value)


def initial_equations_for(init_type: Any, steady_state: list, initial_state: list,
                          initial_output: list) -> list:
    """The initial equations a block's ``initType`` selects (``NoInit``: none).

    Parameters
    ----------
    init_type : Init or its name
    steady_state, initial_state, initial_output : list
        The block's equations for ``SteadyState`` (its states' derivatives zero),
        ``InitialState`` (its states at their start values) and ``InitialOutput``.
    """
    return {Init.SteadyState: steady_state, Init.InitialState: initial_state,
            Init.InitialOutput: initial_output}.get(_init_type(init_type), [])


class SimpleController(enum.IntEnum):
    """Type of a simple controller (Modelica.Blocks.Types.SimpleController): which of P, I, D it has.

    The values are Modelica's ordinals.
    """

    P = 1  #: proportional only
    PI = 2  #: proportional and integral
    PD = 3  #: proportional and derivative
    PID = 4  #: proportional, integral and derivative

    @property
    def has_integral(self) -> bool:
        """Whether the controller has an integral part (PI, PID)."""
        return self in (SimpleController.PI, SimpleController.PID)

    @property
    def has_derivative(self) -> bool:
        """Whether the controller has a derivative part (PD, PID)."""
        return self in (SimpleController.PD, SimpleController.PID)


SimpleController.modelica_name = "Modelica.Blocks.Types.SimpleController"


def simple_controller(value: Any) -> SimpleController:
    """``value`` as a :class:`SimpleController` (also accepts its name, ``"PI"``)."""
    if isinstance(value, str):
        return SimpleController[value]
    return SimpleController(value)


class Regularization(enum.IntEnum):
    """How a sign function is smoothed around zero (Modelica.Blocks.Types.Regularization).

    Used by SignTorque, SignForce and RollingResistance (see
    :func:`regularized_sign`); the values are Modelica's ordinals.
    """

    Exp = 1  #: exponential (smooth)
    Sine = 2  #: sinusoidal (continuous first derivative)
    Linear = 3  #: linear
    Cosine = 4  #: cosine


# set after the body: in an IntEnum's body a str would become a member
Regularization.modelica_name = "Modelica.Blocks.Types.Regularization"


def regularization(component: Any, reg: Any) -> Regularization:
    """``reg`` as a :class:`Regularization`; a ParameterError naming ``component.reg`` if it is none."""
    try:
        return Regularization(reg)
    except ValueError:
        raise ParameterError(f"{where(component)}.reg = {reg!r} is not a Regularization",
                             hint="use Regularization.Exp, .Sine, .Linear or .Cosine",
                             components=(component.path,)) from None


def regularized_sign(component: Any, v: Any, v0: Any, reg: Any) -> sp.Basic:
    """sign(v) smoothed for ``|v| < v0`` by the regularization ``reg``.

    The expression SignTorque, SignForce and RollingResistance multiply
    their nominal torque or force with (the MSL writes it out in each):

    * Exp: ``2/(1 + exp(-v/(0.01*v0))) - 1`` (no events);
    * Sine: ``sign(v)`` if ``|v| >= v0`` else ``sin(pi/2*v/v0)``, inside
      ``smooth(1, ...)`` (no events);
    * Linear: ``sign(v)`` if ``|v| >= v0`` else ``v/v0`` (events at ``|v| = v0``);
    * Cosine: ``sign(v)`` if ``|v| >= v0`` else ``sign(v)*(1 - cos(pi/2*v/v0))``
      (events at ``|v| = v0``).

    ``component`` is used only to name it in the error for an unknown ``reg``
    (see :func:`regularization`).
    """
    kind = regularization(component, reg)
    outside = sp.Abs(v) >= v0
    if kind is Regularization.Exp:
        return 2 / (1 + sp.exp(-v / (0.01 * v0))) - 1
    if kind is Regularization.Sine:
        return smooth(1, If(outside, sp.sign(v), sp.sin(sp.pi / 2 * v / v0)))
    if kind is Regularization.Linear:
        return If(outside, sp.sign(v), v / v0)
    return If(outside, sp.sign(v), sp.sign(v) * (1 - sp.cos(sp.pi / 2 * v / v0)))
