"""Translational components (Modelica.Mechanics.Translational.Components).

The basic elements of 1D translational mechanics in MSL 4.1.0: the housing
(:class:`Fixed`), rigid bodies (:class:`Mass`, :class:`Rod`), the compliant
elements (:class:`Spring`, :class:`Damper`, :class:`SpringDamper`,
:class:`ElastoGap`), helpers for states and initialization
(:class:`RelativeStates`, :class:`InitializeFlange`) and the signal adaptors
for FMU-like input/output wrappers (:class:`GeneralForceToPositionAdaptor`,
:class:`GeneralPositionToForceAdaptor`).

Sign convention: a flange's force ``f`` is the cut force acting *on* the
component the flange belongs to; ``s_rel = flange_b.s - flange_a.s`` and a
compliant element's force ``f = flange_b.f = -flange_a.f``.
"""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import noEvent, smooth
from acausal.language import (
    Boolean,
    Component,
    Eq,
    If,
    Parameter,
    RealInput,
    RealOutput,
    StateSelect,
    Variable,
    der,
)
from acausal.components.adaptors import FlowToPotentialAdaptor, PotentialToFlowAdaptor
from acausal.components.declarations import DerivedDefaults
from acausal.components.thermal import PartialElementaryConditionalHeatPortWithoutT
from acausal.library.rotational import components as rotational_components
from acausal.components.translational import (
    Flange_a,
    Flange_b,
    PartialCompliant,
    PartialCompliantWithRelativeStates,
    PartialRigid,
    PartialTwoFlanges,
)

__all__ = [
    "Fixed",
    "Mass",
    "Rod",
    "Spring",
    "Damper",
    "SpringDamper",
    "ElastoGap",
    "RelativeStates",
    "InitializeFlange",
    "GeneralForceToPositionAdaptor",
    "GeneralPositionToForceAdaptor",
    "IdealGearR2T",
    "IdealRollingWheel",
]

#: Modelica.Constants.eps, the smallest admissible reference compression of ElastoGap.
EPS = 1e-15


class Fixed(Component):
    """Flange fixed in the housing at a position (Modelica.Mechanics.Translational.Components.Fixed).

    ``flange.s = s0``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Fixed"

    s0 = Parameter(0.0, unit="m", description="Fixed offset position of housing")
    flange = Flange_b(description="Flange fixed in housing at a given position")

    def equations(self):
        return [Eq(self.flange.s, self.s0)]


class Mass(PartialRigid):
    """Sliding mass with inertia (Modelica.Mechanics.Translational.Components.Mass).

    A rigid body of length ``L`` (default 0) and mass ``m`` whose centre is
    at ``s``: ``v = der(s)``, ``a = der(v)``, ``m*a = flange_a.f + flange_b.f``.
    ``s`` and ``v`` carry the ``stateSelect`` hint (default StateSelect.default).
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Mass"

    m = Parameter(1.0, unit="kg", min=0, description="Mass of the sliding mass")
    stateSelect = Parameter(StateSelect.default, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use s and v as states")
    s = Variable(start=0.0, unit="m", state_select=lambda c: c.stateSelect,
                 description="Absolute position of center of component (s = flange_a.s + L/2 = flange_b.s - L/2)")
    v = Variable(start=0.0, unit="m/s", state_select=lambda c: c.stateSelect,
                 description="Absolute velocity of component")
    a = Variable(start=0.0, unit="m/s2", description="Absolute acceleration of component")

    def equations(self):
        return [
            Eq(self.v, der(self.s)),
            Eq(self.a, der(self.v)),
            Eq(self.m * self.a, self.flange_a.f + self.flange_b.f),
        ]


class Rod(PartialRigid):
    """Rod without inertia (Modelica.Mechanics.Translational.Components.Rod).

    Two flanges a fixed distance ``L`` apart (``flange_b.s - flange_a.s =
    L``, from PartialRigid) and no mass, so the forces balance:
    ``0 = flange_a.f + flange_b.f``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Rod"

    def equations(self):
        return [Eq(0, self.flange_a.f + self.flange_b.f)]


class Spring(PartialCompliant):
    """Linear 1D translational spring (Modelica.Mechanics.Translational.Components.Spring).

    ``f = c*(s_rel - s_rel0)``: the spring pushes the flanges apart when it
    is compressed below its unstretched length ``s_rel0``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Spring"

    c = Parameter(1.0, unit="N/m", min=0, description="Spring constant")
    s_rel0 = Parameter(0.0, unit="m", description="Unstretched spring length")

    def equations(self):
        return [Eq(self.f, self.c * (self.s_rel - self.s_rel0))]


class Damper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D translational damper (Modelica.Mechanics.Translational.Components.Damper).

    ``f = d*v_rel``; the dissipated power ``lossPower = f*v_rel`` (never
    negative for ``d >= 0``) goes to the optional heat port.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.Damper"

    d = Parameter(0.0, unit="N.s/m", min=0, description="Damping constant")

    def equations(self):
        return [Eq(self.f, self.d * self.v_rel), Eq(self.lossPower, self.f * self.v_rel)]


class SpringDamper(PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """Linear 1D translational spring and damper in parallel (Modelica.Mechanics.Translational.Components.SpringDamper).

    ``f = c*(s_rel - s_rel0) + d*v_rel``; only the damper part dissipates
    (``lossPower = f_d*v_rel``, ``f_d = d*v_rel``).
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.SpringDamper"

    c = Parameter(1.0, unit="N/m", min=0, description="Spring constant")
    d = Parameter(1.0, unit="N.s/m", min=0, description="Damping constant")
    s_rel0 = Parameter(0.0, unit="m", description="Unstretched spring length")
    f_c = Variable(unit="N", description="Spring force (protected)")
    f_d = Variable(unit="N", description="Damping force (protected)")

    def equations(self):
        return [
            Eq(self.f_c, self.c * (self.s_rel - self.s_rel0)),
            Eq(self.f_d, self.d * self.v_rel),
            Eq(self.f, self.f_c + self.f_d),
            Eq(self.lossPower, self.f_d * self.v_rel),
        ]


class ElastoGap(DerivedDefaults, PartialCompliantWithRelativeStates, PartialElementaryConditionalHeatPortWithoutT):
    """1D translational spring damper combination with gap (Modelica.Mechanics.Translational.Components.ElastoGap).

    A contact that can lift off.  With ``ratio = (s_rel - s_rel0)/s_ref``
    and ``contact = s_rel < s_rel0`` (a relation that generates events):

    * spring force ``f_c = -f_ref*|ratio|**n`` in contact, else 0;
    * linear damper force ``f_d2 = d*v_rel`` in contact, else 0;
    * bounded damper force ``f_d = min(max(f_d2, f_c), -f_c)`` in contact,
      else 0, so that ``|f_d| <= |f_c|``;
    * ``f = f_c + f_d`` and ``lossPower = f_d*v_rel``.

    The bound on the damper force makes the contact force continuous at
    ``s_rel = s_rel0`` (where ``f_c = 0``) and keeps it pushing: ``f <= 0``
    always, i.e. the flanges are never pulled together.  ``f_ref`` defaults
    to ``c*s_ref`` (with the default ``s_ref = 1``: ``f_c = -c*|s_rel -
    s_rel0|**n``); ``n = 1`` is a linear contact, ``n = 1.5`` Hertzian
    contact of two spheres.  As in the MSL, ``f_c`` and ``f_d`` are wrapped
    in ``smooth(.., noEvent(..))``; their switch on the Boolean ``contact``
    happens at the events of ``contact``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.ElastoGap"

    c = Parameter(1.0, unit="N/m", min=0, description="Spring constant")
    d = Parameter(1.0, unit="N.s/m", min=0, description="Damping constant")
    s_rel0 = Parameter(0.0, unit="m", description="Unstretched spring length")
    f_ref = Parameter(None, unit="N", min=0, description="Reference spring force at s_ref (default c*s_ref)")
    s_ref = Parameter(1.0, unit="m", min=EPS, description="Reference relative compression at which f_c = f_ref")
    n = Parameter(1.0, min=1, description="Exponent of spring force ( f_c = -f_ref*|(s_rel-s_rel0)/s_ref|^n )")
    contact = Boolean(description="= true, if contact, otherwise no contact")
    f_c = Variable(unit="N", description="Spring force (protected)")
    f_d2 = Variable(unit="N", description="Linear damping force (protected)")
    f_d = Variable(unit="N", description="Linear damping force which is limited by spring force (|f_d| <= |f_c|) "
                                         "(protected)")
    ratio = Variable(unit="1", description="Scaling ratio of relative compression to s_ref (protected)")

    derived_defaults = {"f_ref": lambda gap: gap.c * gap.s_ref}

    def equations(self):
        contact = self.contact
        spring = smooth(1, noEvent(If(contact, -self.f_ref * sp.Abs(self.ratio) ** self.n, 0)))
        bounded = smooth(0, noEvent(If(contact, sp.Min(sp.Max(self.f_d2, self.f_c), -self.f_c), 0)))
        return [
            Eq(contact, self.s_rel < self.s_rel0),
            Eq(self.ratio, (self.s_rel - self.s_rel0) / self.s_ref),
            Eq(self.f_c, spring),
            Eq(self.f_d2, If(contact, self.d * self.v_rel, 0)),
            Eq(self.f_d, bounded),
            Eq(self.f, self.f_c + self.f_d),
            Eq(self.lossPower, self.f_d * self.v_rel),
        ]


class RelativeStates(PartialTwoFlanges):
    """Definition of relative state variables (Modelica.Mechanics.Translational.Components.RelativeStates).

    Connected between two flanges, it transmits no force (``flange_a.f =
    flange_b.f = 0``) and offers the relative position ``s_rel =
    flange_b.s - flange_a.s`` and velocity ``v_rel = der(s_rel)`` as
    preferred states (``a_rel = der(v_rel)``).

    As in MSL 4.1.0, ``s_rel`` and ``v_rel`` always carry
    ``StateSelect.prefer``: the parameter ``stateSelect`` is declared but
    not used by the MSL equations.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.RelativeStates"

    stateSelect = Parameter(StateSelect.prefer, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use the relative angle and relative speed as states")
    s_rel = Variable(start=0.0, unit="m", state_select=StateSelect.prefer,
                     description="Relative position used as state variable")
    v_rel = Variable(start=0.0, unit="m/s", state_select=StateSelect.prefer,
                     description="Relative velocity used as state variable")
    a_rel = Variable(start=0.0, unit="m/s2", description="Relative angular acceleration")

    def equations(self):
        return [
            Eq(self.s_rel, self.flange_b.s - self.flange_a.s),
            Eq(self.v_rel, der(self.s_rel)),
            Eq(self.a_rel, der(self.v_rel)),
            Eq(self.flange_a.f, 0),
            Eq(self.flange_b.f, 0),
        ]


class InitializeFlange(Component):
    """Initialize a flange with given position, speed and acceleration (Modelica.Mechanics.Translational.Components.InitializeFlange).

    The flange transmits no force (``flange.f = 0``); ``s_flange =
    flange.s`` and ``v_flange = der(s_flange)`` carry the ``stateSelect``
    hint.  Each enabled input fixes one initial value at the start time:

    * ``use_s_start``: ``flange.s = s_start``;
    * ``use_v_start``: ``der(flange.s) = v_start``;
    * ``use_a_start``: ``der(der(flange.s)) = a_start``.

    The MSL builds this from protected helper models (Set_s_start,
    Set_v_start, Set_a_start and Set_flange_f), each holding one of these
    initial equations and ``flange.f = 0`` on a flange connected to
    ``flange``; their equations are merged here, which gives the same flat
    system (the zero forces of the connected helpers sum to ``flange.f =
    0``).  The derivatives are named by variables: ``v_flange`` for the
    speed and, with ``use_a_start``, the protected ``a_flange =
    der(v_flange)`` for the acceleration (the MSL's Set_a_start likewise
    adds ``v = der(flange.s)``).  The MSL's ``StateSelect.avoid`` hint on
    the position inside Set_a_start is not reproduced: ``s_flange`` carries
    ``stateSelect``.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.InitializeFlange"

    use_s_start = Parameter(True, structural=True,
                            description="= true, if initial position is defined by input s_start, "
                                        "otherwise not initialized")
    use_v_start = Parameter(True, structural=True,
                            description="= true, if initial speed is defined by input v_start, "
                                        "otherwise not initialized")
    use_a_start = Parameter(True, structural=True,
                            description="= true, if initial acceleration is defined by input a_start, "
                                        "otherwise not initialized")
    stateSelect = Parameter(StateSelect.default, structural=True,  # noqa: N815 - Modelica name
                            description="Priority to use flange angle and speed as states")
    s_start = RealInput(unit="m", condition="use_s_start", description="Initial position of flange")
    v_start = RealInput(unit="m/s", condition="use_v_start", description="Initial speed of flange")
    a_start = RealInput(unit="m/s2", condition="use_a_start", description="Initial angular acceleration of flange")
    flange = Flange_b(description="Flange that is initialized")
    s_flange = Variable(unit="m", state_select=lambda c: c.stateSelect, description="Flange position")
    v_flange = Variable(unit="m/s", state_select=lambda c: c.stateSelect, description="= der(s_flange)")
    a_flange = Variable(unit="m/s2", condition="use_a_start", description="= der(v_flange) (protected)")

    def equations(self):
        equations = [
            Eq(self.s_flange, self.flange.s),
            Eq(self.v_flange, der(self.s_flange)),
            Eq(self.flange.f, 0),
        ]
        if self.use_a_start:
            equations.append(Eq(self.a_flange, der(self.v_flange)))
        return equations

    def initial_equations(self):
        # Written with the variables v_flange and a_flange rather than der(...) of the
        # flange position: the engine cannot yet resolve der() of a variable that alias
        # elimination removes (e.g. der(flange.s) when the mass's position is the state)
        # inside an initial equation.
        equations = []
        if self.use_s_start:
            equations.append(Eq(self.s_flange, self.s_start))
        if self.use_v_start:
            equations.append(Eq(self.v_flange, self.v_start))
        if self.use_a_start:
            equations.append(Eq(self.a_flange, self.a_start))
        return equations


# --------------------------------------------------------------------------
# Signal adaptors (Modelica.Blocks.Interfaces.Adaptors in translational units)


class GeneralForceToPositionAdaptor(FlowToPotentialAdaptor):
    """Signal adaptor with force input and position, speed, acceleration outputs (Modelica.Mechanics.Translational.Components.GeneralForceToPositionAdaptor).

    For wrapping a translational model as an input/output block (e.g. an
    FMU): the force input ``f`` acts on the model's flange (``flange.f =
    f``), and the flange position ``p = flange.s``, its speed ``pder =
    der(p)`` (if ``use_pder``) and acceleration ``pder2 = der(pder)`` (if
    ``use_pder`` and ``use_pder2``) are outputs.

    This is Modelica.Blocks.Interfaces.Adaptors.FlowToPotentialAdaptor
    (:class:`acausal.components.adaptors.FlowToPotentialAdaptor`) with the
    MSL's final settings ``use_fder = use_fder2 = false`` (no force
    derivative inputs), so its protected ``u = f``; the icon-only name
    strings are left out.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.GeneralForceToPositionAdaptor"

    p = RealOutput(unit="m", description="Output for potential")
    pder = RealOutput(unit="m/s", condition="use_pder", description="Optional output for der(potential)")
    pder2 = RealOutput(unit="m/s2", condition=lambda c: c.use_pder and c.use_pder2,
                       description="Optional output for der2(potential)")
    f = RealInput(unit="N", description="Input for flow")
    flange = Flange_a(description="Flange whose position is output and whose force is input")

    def equations(self):
        return [
            Eq(self.y, self.flange.s),  # output = potential = position
            Eq(self.u, self.flange.f),  # input = flow = force
        ]


class GeneralPositionToForceAdaptor(PotentialToFlowAdaptor):
    """Signal adaptor with position, speed, acceleration inputs and force output (Modelica.Mechanics.Translational.Components.GeneralPositionToForceAdaptor).

    For wrapping a translational model as an input/output block (e.g. an
    FMU): the flange follows the position input (``flange.s = p``) and the
    force the flange exerts on the model is the output ``f = -flange.f``.
    The optional inputs ``pder`` (if ``use_pder``) and ``pder2`` (if
    ``use_pder`` and ``use_pder2``) must be the first and second time
    derivatives of ``p``; they replace the derivatives of ``p`` when the
    model needs them (a mass on the flange needs both), so ``p`` itself is
    never differentiated (:func:`acausal.prescribed`, the MSL functions
    state1 and state2); a model that needs a derivative the inputs do not
    give is refused with a StructuralError.  Disabled derivative inputs are
    zero; without ``use_pder`` the position ``p`` is used directly.

    This is Modelica.Blocks.Interfaces.Adaptors.PotentialToFlowAdaptor
    (:class:`acausal.components.adaptors.PotentialToFlowAdaptor`) with the
    MSL's final settings ``use_fder = use_fder2 = false`` (no force
    derivative outputs); the icon-only name strings are left out.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.GeneralPositionToForceAdaptor"

    p = RealInput(unit="m", description="Input for potential")
    pder = RealInput(unit="m/s", condition="use_pder", description="Optional input for der(potential)")
    pder2 = RealInput(unit="m/s2", condition=lambda c: c.use_pder and c.use_pder2,
                      description="Optional input for der2(potential)")
    f = RealOutput(unit="N", description="Output for flow")
    flange = Flange_b(description="Flange that follows the position input")

    def equations(self):
        return [
            Eq(self.y, self.flange.f),  # output = flow = force
            Eq(self.u, self.flange.s),  # input = potential = position
        ]


# --------------------------------------------------------------------------
# rotation <-> translation: the rotational classes, listed in this package as in the MSL


class IdealGearR2T(rotational_components.IdealGearR2T):
    """Gearbox transforming rotational into translational motion (Modelica.Mechanics.Translational.Components.IdealGearR2T).

    The MSL class extends Modelica.Mechanics.Rotational.Components.IdealGearR2T
    and adds nothing: see :class:`acausal.library.rotational.IdealGearR2T`.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.IdealGearR2T"


class IdealRollingWheel(rotational_components.IdealRollingWheel):
    """Ideal wheel rolling without slip (Modelica.Mechanics.Translational.Components.IdealRollingWheel).

    The MSL class extends Modelica.Mechanics.Rotational.Components.IdealRollingWheel
    and adds nothing: see :class:`acausal.library.rotational.IdealRollingWheel`.
    """

    modelica_name = "Modelica.Mechanics.Translational.Components.IdealRollingWheel"
