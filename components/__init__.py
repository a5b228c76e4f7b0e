"""Connectors and partial models shared by the component libraries.

Mirrors the ``Interfaces`` packages of the Modelica Standard Library:
:mod:`acausal.components.rotational` (flanges and rotational partials),
:mod:`acausal.components.translational` (translational flanges and partials),
:mod:`acausal.components.thermal` (heat ports and conditional heat ports),
:mod:`acausal.components.blocks` (signal block partials) and
:mod:`acausal.components.friction` (the friction state machine and the
friction tables of both mechanical domains).

Helpers the libraries share: :mod:`acausal.components.declarations` (array
declarations sized by structural parameters, parameters defaulting to
expressions of others), :mod:`acausal.components.checks` (parameter checks
naming the component) and :mod:`acausal.components.logic` (``initial()`` and
``pre(b)`` as sympy Booleans).
"""

from .blocks import SI2SO, SISO, SO, SignalSource
from .friction import PartialFriction
from .rotational import (
    Flange,
    Flange_a,
    Flange_b,
    PartialAbsoluteSensor,
    PartialCompliant,
    PartialCompliantWithRelativeStates,
    PartialElementaryOneFlangeAndSupport2,
    PartialElementaryRotationalToTranslational,
    PartialElementaryTwoFlangesAndSupport2,
    PartialRelativeSensor,
    PartialTorque,
    PartialTwoFlanges,
    Support,
)
from .thermal import (
    Element1D,
    HeatPort,
    HeatPort_a,
    HeatPort_b,
    PartialElementaryConditionalHeatPort,
    PartialElementaryConditionalHeatPortWithoutT,
)

__all__ = [
    "Flange", "Flange_a", "Flange_b", "Support",
    "PartialTwoFlanges", "PartialCompliant", "PartialCompliantWithRelativeStates",
    "PartialElementaryOneFlangeAndSupport2", "PartialElementaryTwoFlangesAndSupport2",
    "PartialElementaryRotationalToTranslational", "PartialTorque", "PartialAbsoluteSensor", "PartialRelativeSensor",
    "HeatPort", "HeatPort_a", "HeatPort_b", "Element1D",
    "PartialElementaryConditionalHeatPortWithoutT", "PartialElementaryConditionalHeatPort",
    "SO", "SignalSource", "SI2SO", "SISO",
    "PartialFriction",
]
