"""Enumerations shared by blocks and components (Modelica.Blocks.Types)."""

from __future__ import annotations

import enum

__all__ = ["Regularization"]


class Regularization(enum.IntEnum):
    """How a sign function is smoothed around zero (Modelica.Blocks.Types.Regularization).

    Used by SignTorque, SignForce and RollingResistance; the values are
    Modelica's ordinals.
    """

    Exp = 1  #: exponential (smooth)
    Sine = 2  #: sinusoidal (continuous first derivative)
    Linear = 3  #: linear
    Cosine = 4  #: cosine
