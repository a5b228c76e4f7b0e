"""Signal adaptors between a flange and signals (Modelica.Blocks.Interfaces.Adaptors).

The generic halves of the General...Adaptor components of both mechanical
domains (Rotational GeneralTorqueToAngleAdaptor and
GeneralAngleToTorqueAdaptor, Translational GeneralForceToPositionAdaptor and
GeneralPositionToForceAdaptor), which wrap a model as an input/output block
(e.g. an FMU).  The MSL's mechanical adaptors set ``use_fder = use_fder2 =
false`` (final), so the flow derivatives are left out here: their signals
are 0.  A subclass declares its flange and the signals ``p``, ``pder`` (if
``use_pder``), ``pder2`` (if ``use_pder`` and ``use_pder2``) and ``f`` in
its domain's units, and ties ``y`` and ``u`` to its flange.
"""

from __future__ import annotations

from acausal.functions import prescribed
from acausal.language import Component, Eq, Parameter, Variable, der

from .checks import where

__all__ = ["FlowToPotentialAdaptor", "PotentialToFlowAdaptor"]


def _derivative_switches(signal: str) -> tuple[Parameter, Parameter]:
    """``use_pder`` and ``use_pder2``: whether the ``signal`` (input or output) of each derivative is used."""
    return (Parameter(True, structural=True, description=f"Use {signal} for 1st derivative of potential"),
            Parameter(True, structural=True, description=f"Use {signal} for 2nd derivative of potential "
                                                         f"(only if 1st derivative is used, too)"))


class _Adaptor(Component):
    """The protected signals both adaptors declare: ``y`` (output), ``u`` (input) and their derivatives."""

    y = Variable(description="Output signal (protected)")
    y1 = Variable(description="Optional 1st derivative of output (protected)")
    y2 = Variable(description="Optional 2nd derivative of output (protected)")
    u = Variable(description="Input signal (protected)")
    u1 = Variable(description="Optional 1st derivative of input (protected)")
    u2 = Variable(description="Optional 2nd derivative of input (protected)")


class FlowToPotentialAdaptor(_Adaptor):
    """Flow in, potential and its derivatives out (Modelica.Blocks.Interfaces.Adaptors.FlowToPotentialAdaptor).

    ``u = f`` (``u1 = u2 = 0``: no flow derivatives); ``y = p``, ``y1 =
    der(y)`` if ``use_pder``, else 0; ``y2 = der(y1)`` if ``use_pder`` and
    ``use_pder2``, else 0; the enabled outputs ``pder = y1``, ``pder2 = y2``.
    The subclass sets ``y`` to its flange's potential and ``u`` to its flow.
    """

    modelica_name = "Modelica.Blocks.Interfaces.Adaptors.FlowToPotentialAdaptor"

    use_pder, use_pder2 = _derivative_switches("output")

    def equations(self):
        second = self.use_pder and self.use_pder2
        equations = [
            Eq(self.y, self.p),
            Eq(self.y1, der(self.y) if self.use_pder else 0),
            Eq(self.y2, der(self.y1) if second else 0),
            Eq(self.u1, 0),
            Eq(self.u2, 0),
            Eq(self.u, self.f),
        ]
        if self.use_pder:
            equations.append(Eq(self.pder, self.y1))
        if second:
            equations.append(Eq(self.pder2, self.y2))
        return equations


class PotentialToFlowAdaptor(_Adaptor):
    """Potential and its derivatives in, flow out (Modelica.Blocks.Interfaces.Adaptors.PotentialToFlowAdaptor).

    ``y = -f`` (``y1 = y2 = 0``: no flow derivatives); ``u1 = pder`` if
    ``use_pder``, else 0; ``u2 = pder2`` if ``use_pder`` and ``use_pder2``,
    else 0; and

    * both: ``u = prescribed(p, u1, u2)``
    * ``use_pder`` only: ``u = prescribed(p, u1)``
    * neither: ``u = p``

    :func:`acausal.prescribed` stands for the MSL functions state2 and
    state1: where the model needs derivatives of the potential, the given
    ones replace differentiation of ``p``.  A derivative beyond them is that
    of the last input if the class sets ``differentiate_last`` (as a Modelica
    tool differentiates the body of the last derivative function); otherwise
    the model is refused with a StructuralError whose hint is ``pder_hint``.
    The subclass sets ``y`` to its flange's flow and ``u`` to its potential.
    """

    modelica_name = "Modelica.Blocks.Interfaces.Adaptors.PotentialToFlowAdaptor"

    #: Whether a derivative beyond pder (pder2) is der() of that input (see prescribed()).
    differentiate_last = False
    #: The hint when the model needs more derivatives of p than the inputs give.
    pder_hint = "enable use_pder (and use_pder2) and connect the derivatives of p to pder (and pder2)"

    use_pder, use_pder2 = _derivative_switches("input")

    def equations(self):
        second = self.use_pder and self.use_pder2
        given = (self.u1, self.u2) if second else (self.u1,) if self.use_pder else ()
        potential = prescribed(self.p, *given, name=f"{where(self)}.p", hint=self.pder_hint,
                               differentiate_last=self.differentiate_last) if given else self.p
        return [
            Eq(self.y, -self.f),
            Eq(self.y1, 0),
            Eq(self.y2, 0),
            Eq(self.u1, self.pder if self.use_pder else 0),
            Eq(self.u2, self.pder2 if second else 0),
            Eq(self.u, potential),
        ]
