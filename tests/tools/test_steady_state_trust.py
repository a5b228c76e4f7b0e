"""Whether a steady state can be trusted (issue 24, item 2): acausal.tools.linearize.steady_state.

The model is a drive with a linear load: a constant motor torque on a rotor
in a bearing with Coulomb friction whose heat goes to a housing that loses it
through a thermal conductor to ambient (or, in two tests, has no way out).
Its steady states have closed forms:

* sliding (``|tau_motor|`` above the static limit ``peak * tau_f(0)``):
  ``tau_motor = d*w + tau_f(w)*sign(w)`` with ``tau_f(w) = tau_f0 + b*|w|``,
  so ``w = (tau_motor - sign*tau_f0) / (d + b)``, and the housing at
  ``T = T_amb + P_loss/G`` with ``P_loss = tau_f(w)*|w|``;
* below the static limit, started from rest: stuck at ``w = 0`` (the
  friction holds the motor torque), ``T = T_amb``.

The other tests pin down what a steady state must not be: a bearing stuck
while its speed, left at a guess, is not 0; a "steady state" whose housing
temperature still changes; a state no equation determines, passed over in
silence.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from acausal import Model, translate
from acausal.errors import InitializationError, SolverError
from acausal.library.blocks import Constant
from acausal.library.rotational import (BearingFriction, ConstantTorque, Fixed, Inertia,
                                        LinearSpeedDependentTorque, Spring, Torque)
from acausal.library.thermal import FixedTemperature, HeatCapacitor, ThermalConductor
from acausal.runtime.events import evaluator_for
from acausal.tools.linearize import (SteadyState, UndeterminedStateWarning, _check_relations, linearize,
                                     steady_state)
from acausal.tools.report_html import StateNamer

pytestmark = pytest.mark.filterwarnings("ignore::acausal.errors.StartValueWarning")

TAU_F0, PEAK = 1.0, 1.2        # sliding friction at rest [N.m], static limit = PEAK * TAU_F0
D = 0.2                        # load torque per speed [N.m.s/rad]
C_HOUSING, G, T_AMB = 50.0, 2.0, 293.15


class HeatedDrive(Model):
    """Motor torque, rotor in a bearing (heat to the housing), linear load, housing cooled to ambient."""

    def __init__(self, tau: float, slope: float = 0.0, cooled: bool = True, **modifiers) -> None:
        self.tau, self.slope, self.cooled = tau, slope, cooled
        super().__init__(**modifiers)

    def table(self) -> list[list[float]]:
        """The sliding friction against speed; one row when it is constant (then the loss tau*w is
        linear in w)."""
        if self.slope == 0.0:
            return [[0.0, TAU_F0]]
        return [[0.0, TAU_F0], [10.0, TAU_F0 + 10.0 * self.slope]]

    def build(self):
        self.source = Constant(k=self.tau)
        self.motor = Torque()
        self.rotor = Inertia(J=0.2, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.bearing = BearingFriction(tau_pos=self.table(), peak=PEAK, useHeatPort=True)
        # tau = tau_nominal * w / w_nominal = -D * w in both directions
        self.load = LinearSpeedDependentTorque(tau_nominal=-D * 10.0, w_nominal=10.0, TorqueDirection=False)
        self.housing = HeatCapacitor(C=C_HOUSING, T=dict(start=T_AMB, fixed=True))
        self.connect(self.source.y, self.motor.tau)
        self.connect(self.motor.flange, self.rotor.flange_a)
        self.connect(self.rotor.flange_b, self.bearing.flange_a)
        self.connect(self.rotor.flange_b, self.load.flange)
        self.connect(self.bearing.heatPort, self.housing.port)
        if self.cooled:
            self.conductor = ThermalConductor(G=G)
            self.ambient = FixedTemperature(T=T_AMB)
            self.connect(self.housing.port, self.conductor.port_a)
            self.connect(self.conductor.port_b, self.ambient.port)


def sliding_closed_form(tau: float, slope: float) -> tuple[float, float]:
    """``(w, T)`` of the sliding steady state."""
    sign = math.copysign(1.0, tau)
    w = (tau - sign * TAU_F0) / (D + slope)
    loss = (TAU_F0 + slope * abs(w)) * abs(w)
    return w, T_AMB + loss / G


# -- closed forms ------------------------------------------------------------------------------


@pytest.mark.parametrize("tau, slope, mode", [(5.0, 0.0, "Forward"), (-5.0, 0.0, "Backward"),
                                              (3.0, 0.1, "Forward"), (-3.0, 0.1, "Backward")])
def test_a_sliding_drive_turns_at_the_closed_form_speed_and_heats_its_housing(tau, slope, mode):
    w, T = sliding_closed_form(tau, slope)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UndeterminedStateWarning)  # every state is determined here
        found = steady_state(HeatedDrive(tau, slope))
    assert isinstance(found, SteadyState)
    assert found["rotor.w"] == pytest.approx(w, rel=1e-10)
    assert found["housing.T"] == pytest.approx(T, rel=1e-12)
    assert found["bearing.lossPower"] == pytest.approx(G * (T - T_AMB), rel=1e-10)
    assert found.discrete_state == f"bearing: {mode}"
    assert found.discrete_values["bearing.mode"] == (1 if mode == "Forward" else -1)
    assert found.discrete_values["bearing.locked"] is False
    # the angle turns at the speed; every other derivative is checked and at rest
    assert found.free == ("rotor.phi",) and found.moving == ("rotor.phi",) and found.undetermined == ()
    assert found.derivatives["der(rotor.phi)"] == pytest.approx(w, rel=1e-10)
    assert set(found.residuals) == {"rotor.w", "housing.T"}
    assert found.residual == max(found.residuals.values()) <= found.tolerance


def test_the_linearization_at_the_sliding_steady_state_is_the_closed_form():
    """d der(w)/dw = -(d + b)/J; d der(T)/dw = dP/dw / C = (tau_f0 + 2 b w)/C; d der(T)/dT = -G/C."""
    slope, J = 0.1, 0.2
    found = steady_state(HeatedDrive(3.0, slope))
    w = found["rotor.w"]
    lin = linearize(HeatedDrive(3.0, slope), at=found.states, outputs=["housing.T"])
    assert lin.discrete_state == "bearing: Forward"
    i, k = lin.state_names.index("rotor.w"), lin.state_names.index("housing.T")
    assert lin.A[i, i] == pytest.approx(-(D + slope) / J, rel=1e-12)
    assert lin.A[k, i] == pytest.approx((TAU_F0 + 2 * slope * w) / C_HOUSING, rel=1e-12)
    assert lin.A[k, k] == pytest.approx(-G / C_HOUSING, rel=1e-12)


@pytest.mark.parametrize("tau", [0.5, 1.1, -1.1])
def test_below_the_static_limit_the_drive_sticks_at_rest_and_the_speed_is_reported_undetermined(tau):
    """1.1 N.m is above the sliding friction but below the static limit 1.2 N.m: from rest the bearing holds."""
    with pytest.warns(UndeterminedStateWarning, match=r"determines rotor\.w; kept at rotor\.w = 0 \(the "
                                                      r"model's start\)"):
        found = steady_state(HeatedDrive(tau))
    assert found["rotor.w"] == 0.0
    assert found["housing.T"] == pytest.approx(T_AMB, rel=1e-14)
    # the bearing holds the motor against the load, which is 0 at rest
    assert found["bearing.sa"] == pytest.approx(tau, rel=1e-12)
    assert found.discrete_state == "bearing: Stuck (locked)"
    assert found.discrete_values["bearing.mode"] == 0 and found.discrete_values["bearing.locked"] is True
    # stuck: der(w) = 0 whatever w is, so no equation determines the speed; it is listed
    assert found.undetermined == ("rotor.w",)
    assert "rotor.w" in found.free and "rotor.w" not in found.moving
    assert set(found.residuals) == {"rotor.w", "housing.T"} and found.residual <= found.tolerance


# -- what a steady state must not be ---------------------------------------------------------------


@pytest.mark.parametrize("w_guess, chosen", [(1.0, "bearing: Forward"), (-1.0, "bearing: Backward")])
def test_a_stuck_bearing_turning_at_its_guess_is_refused(w_guess, chosen):
    """Below the static limit the bearing is stuck, where der(w) = 0 holds for any w: a guessed
    speed would stay, and a stuck bearing would turn (and heat its housing).  Refused."""
    with pytest.raises(InitializationError) as raised:
        steady_state(HeatedDrive(0.5), guess={"rotor.w": w_guess})
    assert isinstance(raised.value, ValueError)
    message = str(raised.value)
    assert "[bearing: Stuck (locked)] is not consistent with that discrete state" in message
    assert f"no equation of it determines rotor.w, kept at rotor.w = {w_guess:g} (its guess)" in message
    assert f"initialization chooses [{chosen}]" in message
    assert "free=" in raised.value.hint


def test_a_guess_at_a_simulations_accuracy_of_zero_is_zero_to_the_check():
    """A stuck speed taken from a simulation (-1.000011e-10 rad/s, just past the runtime's relation
    margin of 1e-10) belongs to the stuck bearing: guesses are judged to GUESS_RTOL = 1e-6.  A
    guess of 1e-3 rad/s does not."""
    with pytest.warns(UndeterminedStateWarning):
        found = steady_state(HeatedDrive(0.5), guess={"rotor.w": -1.000011e-10})
    assert found.discrete_state == "bearing: Stuck (locked)" and found["rotor.w"] == -1.000011e-10
    with pytest.raises(InitializationError, match=r"initialization chooses \[bearing: Forward\]"):
        steady_state(HeatedDrive(0.5), guess={"rotor.w": 1e-3})


def test_a_state_named_free_is_kept_without_the_consistency_check():
    """The way out of the refusal: hold the speed at 1 rad/s explicitly.  Stuck, the bearing takes
    the motor torque less the load, sa = tau - d*w, and dissipates sa*w into the housing."""
    tau, w = 0.5, 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", UndeterminedStateWarning)
        found = steady_state(HeatedDrive(tau), guess={"rotor.w": w}, free=["rotor.w"])
    assert found.discrete_state == "bearing: Stuck (locked)"
    assert found["rotor.w"] == w and found.undetermined == ()
    assert found["housing.T"] == pytest.approx(T_AMB + (tau - D * w) * w / G, rel=1e-12)


def test_the_reported_case_no_longer_returns_the_guess_with_a_housing_that_cools():
    """Issue 24: motor off, housing with no heat path out (C = 20 J/K), guess w = 1.  It returned
    rotor.w = 1.0 (the guess), 'bearing: Stuck (locked)', residual 0 and der(housing.T) = -0.01 K/s.

    The housing temperature is what no equation determines here (no heat leaves): it is kept and
    reported; the speed is solved from der(housing.T) = sa*w/C = 0 and the bearing rests."""
    model = HeatedDrive(0.0, cooled=False, housing=dict(C=20.0))
    with pytest.warns(UndeterminedStateWarning, match=r"determines housing\.T"):
        found = steady_state(model, guess={"rotor.w": 1.0})
    assert found["rotor.w"] == pytest.approx(0.0, abs=1e-12)
    assert found.discrete_state == "bearing: Stuck (locked)"
    assert found.undetermined == ("housing.T",) and found["housing.T"] == T_AMB
    for name, rate in found.derivatives.items():
        assert abs(rate) <= found.tolerance, name
    assert "housing.T" in found.residuals


@pytest.mark.parametrize("model, rate", [
    (lambda: HeatedDrive(5.0, cooled=False), "0.4"),
    # a conductor of G = 0 is no heat path: the term drops out structurally
    (lambda: HeatedDrive(5.0, conductor=dict(G=0.0)), "0.4"),
    # a rising friction: w = (4 - 1)/(0.2 + 0.1) = 10 rad/s, der(T) = (1 + 0.1 w) w / C = 0.4 K/s
    (lambda: HeatedDrive(4.0, 0.1, cooled=False), "0.4")], ids=["no-heat-path", "G=0", "rising-friction"])
def test_a_temperature_that_still_changes_is_no_steady_state(model, rate):
    """Sliding into a housing with no heat path out: der(housing.T) = tau_f(w)*w/C, at 20 rad/s
    1*20/50 = 0.4 K/s.  It was returned as a steady state with the temperature "moving at a
    constant rate" like the angle; now it is an error.  With a constant friction torque der(T) =
    w/50 is as linear in w as der(phi) = w, and only its unit, K/s, says it is no speed."""
    with pytest.raises(SolverError, match=r"no steady state of HeatedDrive found in \[bearing: Forward\]: "
                                          rf"at the point reached der\(housing\.T\) = {rate} K/s") as raised:
        steady_state(model())
    assert "der(housing.T) depends on no state left to solve for" in raised.value.hint


def test_a_drive_without_loss_names_the_derivative_nothing_balances():
    class Accelerating(Model):
        def build(self):
            self.drive = ConstantTorque(tau_constant=1.0)
            self.J = Inertia(J=1.0)
            self.connect(self.drive.flange, self.J.flange_a)

    with pytest.raises(SolverError, match=r"der\(J\.w\) = 1 rad/s2") as raised:
        steady_state(Accelerating())
    assert "der(J.w) depends on no state left to solve for" in raised.value.hint


class SpringBack(Model):
    """A rotor at -5 rad/s in a bearing (sliding friction 1 N.m, static 1.2 N.m), held by a spring
    of 10 N.m/rad to ground: it slides back and sticks."""

    def build(self):
        self.rotor = Inertia(J=0.2, phi=dict(start=0, fixed=True), w=dict(start=-5, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, TAU_F0]], peak=PEAK)
        self.spring = Spring(c=10.0)
        self.fixed = Fixed()
        self.connect(self.rotor.flange_b, self.bearing.flange_a)
        self.connect(self.rotor.flange_a, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.fixed.flange)


def test_a_bearing_does_not_slide_backward_at_zero_speed():
    """The model starts sliding backward; the first round solves that state's der(x) = 0: w = 0 and
    the spring holding the sliding friction, phi = tau_f/c = 0.1 rad.  The event iteration judged
    w < 0 against the relations of the start (w = -5), within its margin of them, and kept
    'bearing: Backward' at w = 0.  Judged against the solution, w < 0 is false: the bearing sticks
    (the spring's 1 N.m is below the static 1.2 N.m) and the angle, which the stuck state's
    equations leave open, is kept and reported."""
    with pytest.warns(UndeterminedStateWarning, match=r"rotor\.phi = 0\.1 \(solved in \[bearing: Backward\]\)"):
        found = steady_state(SpringBack())
    assert found.discrete_state == "bearing: Stuck (locked)" and found.rounds == 2
    assert found["rotor.w"] == 0.0
    assert found["rotor.phi"] == pytest.approx(TAU_F0 / 10.0, rel=1e-12)
    holding = abs(found["bearing.sa"])
    assert holding == pytest.approx(TAU_F0, rel=1e-12) and holding < PEAK * TAU_F0
    assert found.undetermined == ("rotor.phi",)


def test_relation_values_must_agree_with_the_solution():
    """The guard after the event iteration: a relation whose value contradicts the continuous
    solution beyond its margin (w_relfric > 0 false at w = 20 rad/s) is refused."""
    translation = translate(HeatedDrive(5.0))
    found = steady_state(translation)
    evaluator = evaluator_for(translation)
    system = translation.system(found.discrete_key)
    x = np.array([found.states[s] for s in system.states])
    n = len(translation.partitioned.relations)
    exact = evaluator.relation_values(system, found.t, x, (False,) * n, exact=True)
    namer = StateNamer(translation)
    _check_relations(translation, evaluator, namer, found.discrete_key, system, found.t, x, exact)  # agrees
    k = next(i for i, r in enumerate(translation.partitioned.relations) if r.text == "bearing.w_relfric > 0")
    assert exact[k]
    flipped = tuple(not v if i == k else v for i, v in enumerate(exact))
    with pytest.raises(InitializationError, match=r"bearing\.w_relfric > 0 is false \(20 against 0\)"):
        _check_relations(translation, evaluator, namer, found.discrete_key, system, found.t, x, flipped)
