"""A simple vehicle and the rolling resistance of its wheels (Modelica.Mechanics.Translational.Components).

:class:`Vehicle` is a composite: a mass driven through an ideal rolling
wheel (with the drive-train inertia on its rotational side), braked by air
drag (relative to an optional wind speed), rolling resistance and the
grade force of an inclination.  :class:`RollingResistance` is the element
for the rolling resistance.  The vehicle turns the inclination (tan of the
angle) into the grade force with the Modelica.Blocks.Math blocks Atan and
Sin.  :data:`G_N` is Modelica.Constants.g_n.
"""

from __future__ import annotations

import sympy as sp

from acausal.components import rotational
from acausal.components.translational import Flange_b, PartialForce
from acausal.language import Component, Eq, Parameter, RealInput, Variable, der
from acausal.library.blocks.math import Atan, Gain, Sin
from acausal.library.blocks.sources import Constant
from acausal.library.blocks.types import regularized_sign
from acausal.library.rotational.components import IdealRollingWheel, Inertia

from .components import Mass
from .sources import EPS, Force, QuadraticSpeedDependentForce, Regularization, Speed

__all__ = ["RollingResistance", "Vehicle", "G_N"]

#: Modelica.Constants.g_n, standard acceleration of gravity on earth (m/s2).
G_N = 9.80665


class RollingResistance(PartialForce):
    """Resistance of a rolling wheel (Modelica.Mechanics.Translational.Components.RollingResistance).

    The wheel load on a slope of inclination ``tan(angle)`` is
    ``fWeight*cos(angle)``; the rolling resistance opposes the motion::

        f_nominal = -Cr*fWeight*cos(atan(inclination))
        f = -f_nominal*sign_reg(v),  v = der(s)

    where ``sign_reg`` is sign(v) smoothed below ``v0`` by ``reg`` (see
    :func:`acausal.library.blocks.types.regularized_sign`).  ``f =
    flange.f``, so the flange is pushed by ``-f``, against its motion.
    ``Cr`` is the input ``cr`` (``useCrInput``) or ``CrConstant``;
    the inclination is the input ``inclination`` (``useInclinationInput``)
    or ``inclinationConstant``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.RollingResistance"

    fWeight = Parameter(0.0, unit="N", description="Wheel load due to gravity")  # noqa: N815 - Modelica name
    useCrInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="Enable signal input for Cr")
    CrConstant = Parameter(0.01, description="Constant rolling resistance coefficient")  # noqa: N815
    useInclinationInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                    description="Enable signal input for inclination")
    inclinationConstant = Parameter(0.0, description="Constant inclination = tan(angle)")  # noqa: N815
    reg = Parameter(Regularization.Exp, structural=True, description="Type of regularization")
    v0 = Parameter(0.1, unit="m/s", min=EPS, description="Regularization below v0")
    v = Variable(unit="m/s", description="Velocity of flange with respect to support (= der(s))")
    f_nominal = Variable(unit="N", description="Nominal rolling resistance without regularization")
    inclination = RealInput(condition="useInclinationInput", description="Inclination=tan(angle)")
    cr = RealInput(condition="useCrInput", description="Rolling resistance coefficient")
    Cr_internal = Variable(description="Rolling resistance coefficient (protected)")  # noqa: N815
    inclination_internal = Variable(description="Inclination (protected)")

    def equations(self):
        return [
            Eq(self.Cr_internal, self.cr if self.useCrInput else self.CrConstant),
            Eq(self.inclination_internal,
               self.inclination if self.useInclinationInput else self.inclinationConstant),
            Eq(self.v, der(self.s)),
            Eq(self.f_nominal, -self.Cr_internal * self.fWeight * sp.cos(sp.atan(self.inclination_internal))),
            Eq(self.f, -self.f_nominal * regularized_sign(self, self.v, self.v0, self.reg)),
        ]


class Vehicle(Component):
    """Simple vehicle model (Modelica.Mechanics.Translational.Components.Vehicle).

    A mass ``m`` (``s``, ``v``, ``a`` are its position, speed and
    acceleration) driven by the rotational flange ``flangeR`` through the
    drive-train inertia ``J`` and an ideal rolling wheel of radius ``R``,
    against three resistances acting on the mass:

    * air drag ``Cd*A*rho*(v - vWind)*|v - vWind|/2``: a quadratic
      speed-dependent force whose support moves at the wind speed (input
      ``vWind`` or ``vWindConstant``, through a Speed source with a 50 Hz
      filter starting at s = 0);
    * rolling resistance ``CrConstant*m*g*cos(atan(inclination))`` (or the
      input ``cr``) against the motion, linearly regularized below ``vReg``;
    * grade force ``m*g*sin(atan(inclination))`` downhill, the inclination
      (tan of the slope angle) being the input ``inclination`` or
      ``inclinationConstant``.

    The translational flange ``flangeT`` is the vehicle body (to couple
    a trailer).  With all resistances zero, ``(m + J/R^2)*a`` is the
    driving force ``flangeR.tau/R``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Vehicle"

    #: Reference velocity for the air drag (the MSL's protected constant vRef, m/s).
    vRef = 1.0

    m = Parameter(None, unit="kg", description="Total mass of vehicle")
    g = Parameter(G_N, unit="m/s2", description="Constant gravity acceleration")
    J = Parameter(None, unit="kg.m2", description="Total rotational inertia of drive train")
    R = Parameter(None, unit="m", description="Wheel radius")
    A = Parameter(1.0, unit="m2", description="Cross section of vehicle")
    Cd = Parameter(0.5, description="Drag resistance coefficient")
    rho = Parameter(1.2, unit="kg/m3", description="Density of air")
    useWindInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                             description="Enable signal input for wind velocity")
    vWindConstant = Parameter(0.0, unit="m/s", description="Constant wind velocity")  # noqa: N815
    useCrInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="Enable signal input for Cr")
    CrConstant = Parameter(0.015, description="Constant rolling resistance coefficient")  # noqa: N815
    vReg = Parameter(1e-3, unit="m/s", description="Velocity for regularization around 0")  # noqa: N815
    useInclinationInput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                    description="Enable signal input for inclination")
    inclinationConstant = Parameter(0.0, description="Constant inclination = tan(angle)")  # noqa: N815

    s = Variable(start=0.0, unit="m", description="Position of vehicle")
    v = Variable(start=0.0, unit="m/s", description="Velocity of vehicle")
    a = Variable(unit="m/s2", description="Acceleration of vehicle")

    flangeT = Flange_b(description="Translational flange")  # noqa: N815 - Modelica name
    flangeR = rotational.Flange_a(description="Rotational flange")  # noqa: N815 - Modelica name
    inclination = RealInput(condition="useInclinationInput", description="Inclination=tan(angle)")
    cr = RealInput(condition="useCrInput", description="Rolling resistance coefficient")
    vWind = RealInput(unit="m/s", condition="useWindInput", description="Wind velocity")  # noqa: N815

    def build(self):
        weight = self.m * self.g
        self.fDrag = QuadraticSpeedDependentForce(useSupport=True, f_nominal=-self.Cd * self.A * self.rho
                                                  * self.vRef ** 2 / 2,
                                                  ForceDirection=False, v_nominal=self.vRef)
        self.fRoll = RollingResistance(fWeight=weight, useCrInput=self.useCrInput, CrConstant=self.CrConstant,
                                       useInclinationInput=self.useInclinationInput,
                                       inclinationConstant=self.inclinationConstant,
                                       reg=Regularization.Linear, v0=self.vReg)
        self.fGrav = Force()
        self.inertia = Inertia(J=self.J)
        self.idealRollingWheel = IdealRollingWheel(radius=self.R)
        self.mass = Mass(m=self.m)
        self.windSpeed = Speed(s=dict(fixed=True))
        self.gravForceGain = Gain(k=-weight)
        self.atan = Atan()
        self.sin = Sin()

        self.connect(self.idealRollingWheel.flangeT, self.mass.flange_a)
        if self.useWindInput:
            self.connect(self.vWind, self.windSpeed.v_ref)
        else:
            self.constWindSpeed = Constant(k=self.vWindConstant)
            self.connect(self.constWindSpeed.y, self.windSpeed.v_ref)
        self.connect(self.fDrag.support, self.windSpeed.flange)
        self.connect(self.mass.flange_b, self.flangeT)
        self.connect(self.sin.u, self.atan.y)
        self.connect(self.gravForceGain.u, self.sin.y)
        self.connect(self.gravForceGain.y, self.fGrav.f)
        self.connect(self.mass.flange_b, self.fDrag.flange)
        self.connect(self.mass.flange_b, self.fRoll.flange)
        self.connect(self.mass.flange_b, self.fGrav.flange)
        self.connect(self.inertia.flange_b, self.idealRollingWheel.flangeR)
        self.connect(self.flangeR, self.inertia.flange_a)
        if self.useCrInput:
            self.connect(self.cr, self.fRoll.cr)
        if self.useInclinationInput:
            self.connect(self.inclination, self.fRoll.inclination)
            self.connect(self.inclination, self.atan.u)
        else:
            self.constInclination = Constant(k=self.inclinationConstant)
            self.connect(self.atan.u, self.constInclination.y)

    def equations(self):
        return [Eq(self.s, self.mass.s), Eq(self.v, self.mass.v), Eq(self.a, self.mass.a)]
