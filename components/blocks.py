"""Partial signal blocks (Modelica.Blocks.Interfaces)."""

from __future__ import annotations

from acausal.language import Boolean, Component, Integer, Parameter, RealInput, RealOutput

__all__ = ["SO", "SignalSource", "SI2SO", "SISO", "MO", "MISO", "SIMO", "MIMO", "MIMOs", "MI2MO",
           "PartialRealMISO", "BooleanInput", "BooleanOutput", "IntegerInput", "IntegerOutput",
           "PartialBooleanSISO", "PartialBooleanSI2SO", "PartialBooleanSI3SO"]


def BooleanInput(**kw) -> Boolean:  # noqa: N802 - Modelica's connector name
    """A Boolean signal input (Modelica.Blocks.Interfaces.BooleanInput)."""
    return Boolean(causality="input", **kw)


def BooleanOutput(**kw) -> Boolean:  # noqa: N802
    """A Boolean signal output (Modelica.Blocks.Interfaces.BooleanOutput)."""
    return Boolean(causality="output", **kw)


def IntegerInput(**kw) -> Integer:  # noqa: N802
    """An Integer signal input (Modelica.Blocks.Interfaces.IntegerInput)."""
    return Integer(causality="input", **kw)


def IntegerOutput(**kw) -> Integer:  # noqa: N802
    """An Integer signal output (Modelica.Blocks.Interfaces.IntegerOutput)."""
    return Integer(causality="output", **kw)


class SO(Component):
    """Single output block (Modelica.Blocks.Interfaces.SO): the output ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.SO"

    y = RealOutput(description="Connector of Real output signal")


class SignalSource(SO):
    """Base of signal sources (Modelica.Blocks.Interfaces.SignalSource): ``offset`` and ``startTime``."""

    modelica_name = "Modelica.Blocks.Interfaces.SignalSource"

    offset = Parameter(0.0, description="Offset of output signal y")
    startTime = Parameter(0.0, unit="s", description="Output y = offset for time < startTime")  # noqa: N815


class SI2SO(Component):
    """Two inputs, one output (Modelica.Blocks.Interfaces.SI2SO): ``u1``, ``u2`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.SI2SO"

    u1 = RealInput(description="Connector of Real input signal 1")
    u2 = RealInput(description="Connector of Real input signal 2")
    y = RealOutput(description="Connector of Real output signal")


class SISO(Component):
    """Single input, single output (Modelica.Blocks.Interfaces.SISO): ``u`` and ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.SISO"

    u = RealInput(description="Connector of Real input signal")
    y = RealOutput(description="Connector of Real output signal")


class MO(Component):
    """Multiple output continuous control block (Modelica.Blocks.Interfaces.MO): the output vector ``y[nout]``."""

    modelica_name = "Modelica.Blocks.Interfaces.MO"

    nout = Parameter(1, structural=True, min=1, description="Number of outputs")
    y = RealOutput("nout", description="Connector of Real output signals")


class MISO(Component):
    """Multiple input single output continuous control block (Modelica.Blocks.Interfaces.MISO):
    the input vector ``u[nin]`` and the output ``y``."""

    modelica_name = "Modelica.Blocks.Interfaces.MISO"

    nin = Parameter(1, structural=True, description="Number of inputs")
    u = RealInput("nin", description="Connector of Real input signals")
    y = RealOutput(description="Connector of Real output signal")


class SIMO(Component):
    """Single input multiple output continuous control block (Modelica.Blocks.Interfaces.SIMO):
    the input ``u`` and the output vector ``y[nout]``."""

    modelica_name = "Modelica.Blocks.Interfaces.SIMO"

    nout = Parameter(1, structural=True, description="Number of outputs")
    u = RealInput(description="Connector of Real input signal")
    y = RealOutput("nout", description="Connector of Real output signals")


class MIMO(Component):
    """Multiple input multiple output continuous control block (Modelica.Blocks.Interfaces.MIMO):
    the input vector ``u[nin]`` and the output vector ``y[nout]``."""

    modelica_name = "Modelica.Blocks.Interfaces.MIMO"

    nin = Parameter(1, structural=True, description="Number of inputs")
    nout = Parameter(1, structural=True, description="Number of outputs")
    u = RealInput("nin", description="Connector of Real input signals")
    y = RealOutput("nout", description="Connector of Real output signals")


class MIMOs(Component):
    """Multiple input multiple output continuous control block with as many inputs as outputs
    (Modelica.Blocks.Interfaces.MIMOs): ``u[n]`` and ``y[n]``."""

    modelica_name = "Modelica.Blocks.Interfaces.MIMOs"

    n = Parameter(1, structural=True, description="Number of inputs (= number of outputs)")
    u = RealInput("n", description="Connector of Real input signals")
    y = RealOutput("n", description="Connector of Real output signals")


class MI2MO(Component):
    """Two multiple inputs, one multiple output continuous control block
    (Modelica.Blocks.Interfaces.MI2MO): ``u1[n]``, ``u2[n]`` and ``y[n]``."""

    modelica_name = "Modelica.Blocks.Interfaces.MI2MO"

    n = Parameter(1, structural=True, description="Dimension of input and output vectors")
    u1 = RealInput("n", description="Connector 1 of Real input signals")
    u2 = RealInput("n", description="Connector 2 of Real input signals")
    y = RealOutput("n", description="Connector of Real output signals")


class PartialRealMISO(Component):
    """Partial block with a RealVectorInput and a RealOutput signal (Modelica.Blocks.Interfaces.PartialRealMISO):
    the input vector ``u[nu]`` and the output ``y``.

    The MSL sizes ``u`` by connecting to it (``connectorSizing``); acausal
    needs ``nu`` given.
    """

    modelica_name = "Modelica.Blocks.Interfaces.PartialRealMISO"

    significantDigits = Parameter(3, structural=True, min=1,  # noqa: N815 - Modelica's name
                                  description="Number of significant digits to be shown in dynamic diagram "
                                              "layer for y")
    nu = Parameter(0, structural=True, min=0, description="Number of input connections")
    u = RealInput("nu", description="Connector of Real input signals")
    y = RealOutput(description="Connector of Real output signal")


class PartialBooleanSISO(Component):
    """One Boolean input, one Boolean output (Modelica.Blocks.Interfaces.partialBooleanSISO)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanSISO"

    u = BooleanInput(description="Connector of Boolean input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")


class PartialBooleanSI2SO(Component):
    """Two Boolean inputs, one Boolean output (Modelica.Blocks.Interfaces.partialBooleanSI2SO)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanSI2SO"

    u1 = BooleanInput(description="Connector of first Boolean input signal")
    u2 = BooleanInput(description="Connector of second Boolean input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")


class PartialBooleanSI3SO(Component):
    """Three Boolean inputs, one Boolean output (Modelica.Blocks.Interfaces.partialBooleanSI3SO)."""

    modelica_name = "Modelica.Blocks.Interfaces.partialBooleanSI3SO"

    u1 = BooleanInput(description="Connector of first Boolean input signal")
    u2 = BooleanInput(description="Connector of second Boolean input signal")
    u3 = BooleanInput(description="Connector of third Boolean input signal")
    y = BooleanOutput(description="Connector of Boolean output signal")
