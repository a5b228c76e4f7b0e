"""LossyGear: declarations, parameter errors and behaviour against closed-form solutions.

Every expected value is derived by hand from the gear's equations and
Newton's law for the inertias on its flanges (constant torques and constant
loss tables give constant accelerations), or from a conservation law (the
heat stored equals the work of the sources minus the kinetic energy gained).

Sign conventions (MSL): ``flange.tau`` is the cut torque acting *on the
gear*; ``ratio = flange_a.phi/flange_b.phi``; the torque balance is ``0 =
flange_b.tau + ratio*(flange_a.tau - tauLoss)``.  So with flange_a driving
and rolling forward, ``flange_b.tau = -ratio*(eta_mf1*flange_a.tau -
tau_bf1)``, and with flange_b driving, ``flange_b.tau =
-ratio*(flange_a.tau/eta_mf2 - tau_bf2)``.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Eq, Model, Variable, der, simulate
from acausal.errors import ParameterError
from acausal.library.blocks import Sine
from acausal.library.rotational import ConstantTorque, Fixed, IdealGear, Inertia, SpringDamper, Torque
from acausal.library.rotational.lossy_gear import Gearbox, LossyGear
from acausal.library.thermal import HeatCapacitor
from library_checks import attach, check_declarations

REST = dict(start=0, fixed=True)
FORWARD, STUCK, BACKWARD, FREE = 1, 0, -1, 2


def changes_of(result, name):
    """(time, old, new) of every event that changed ``name``."""
    return [(e.time, old, new) for e in result.events for (n, old, new) in e.changes if n == name]


# --------------------------------------------------------------------------
# declarations and parameter checks


@pytest.mark.parametrize("modifiers", [
    {},
    {"useSupport": True},
    {"useHeatPort": True},
    {"useSupport": True, "useHeatPort": True, "ratio": -3.0},
    {"lossTable": [[0, 0.5, 0.5, 0, 0]]},
    {"lossTable": [[0, 0.95, 0.9, 0.4, 0.5], [10, 0.9, 0.8, 0.6, 0.7], [100, 0.85, 0.75, 1.0, 1.1]]},
    {"lossTable": [[0, 1, 1, 0.5, 0.5]]},
])
def test_declarations(modifiers):
    check_declarations(LossyGear(**modifiers))


@pytest.mark.parametrize("table, words", [
    ([[0, 1.2, 0.9, 0, 0]], "eta_mf1"),
    ([[0, 0.9, 0.0, 0, 0]], "eta_mf2"),
    ([[0, 0.9, 0.9, 0, 0], [1, 0.9, -0.5, 0, 0]], "row 2"),
    ([[0, 0.9, 0.9, 0, 0], [0, 0.8, 0.8, 0, 0]], "strictly increasing"),
    ([[1, 0.9, 0.9, 0, 0], [0.5, 0.8, 0.8, 0, 0]], "strictly increasing"),
    ([[0, 0.9, 0.9, 0]], "n x 5"),
    ([], "n x 5"),
    ([[0, 0.9, float("nan"), 0, 0]], "non-finite"),
])
def test_bad_loss_table_is_a_parameter_error(table, words):
    with pytest.raises(ParameterError) as info:
        attach(LossyGear(lossTable=table), "gear")
    message = str(info.value)
    assert "gear.lossTable" in message and words in message


def test_zero_ratio_and_unsupported_smoothness_are_parameter_errors():
    from acausal.library.blocks.sources import Smoothness
    with pytest.raises(ParameterError, match=r"gear\.ratio = 0"):
        attach(LossyGear(ratio=0), "gear")
    with pytest.raises(ParameterError, match=r"gear\.smoothness"):
        attach(LossyGear(smoothness=Smoothness.ConstantSegments), "gear")


# --------------------------------------------------------------------------
# efficiency in both power directions


def two_inertias(gear, tau_a=0.0, tau_b=0.0, w0=0.0, J1=1.0, J2=2.0, heat=False):
    """Constant torque tau_a on Inertia1 (flange_a side), tau_b on Inertia2 (flange_b side)."""

    class TwoInertias(Model):
        W = Variable(start=0.0, fixed=True, unit="J", description="Work done by the two torque sources")

        def build(self):
            self.source_a = ConstantTorque(tau_constant=tau_a)
            self.inertia1 = Inertia(J=J1, phi=REST, w=dict(start=w0, fixed=True))
            self.gear = gear
            self.inertia2 = Inertia(J=J2)
            self.source_b = ConstantTorque(tau_constant=tau_b)
            self.connect(self.source_a.flange, self.inertia1.flange_a)
            self.connect(self.inertia1.flange_b, self.gear.flange_a)
            self.connect(self.gear.flange_b, self.inertia2.flange_a)
            self.connect(self.inertia2.flange_b, self.source_b.flange)
            if heat:
                self.capacitor = HeatCapacitor(C=10.0, T=dict(start=300.0, fixed=True))
                self.connect(self.gear.heatPort, self.capacitor.port)

        def equations(self):
            return [Eq(der(self.W), self.source_a.tau * self.inertia1.w + self.source_b.tau * self.inertia2.w)]

    return TwoInertias()


RATIO, ETA1, ETA2 = 3.0, 0.8, 0.6


def test_flange_a_driving_transmits_eta_mf1_of_the_power():
    # rolling forward from w0 > 0, torque on flange_a only: flange_a drives, quadrant 1
    # (J1 + J2/(eta1*i^2))*a1 = T  and  flange_b.tau = -i*eta1*flange_a.tau
    T, J1, J2, w0 = 5.0, 1.0, 2.0, 1.0
    gear = LossyGear(ratio=RATIO, lossTable=[[0, ETA1, ETA2, 0, 0]])
    result = simulate(two_inertias(gear, tau_a=T, w0=w0, J1=J1, J2=J2), stop_time=1.0, interval=0.1)
    a1 = T / (J1 + J2 / (ETA1 * RATIO**2))
    t = result.time
    assert np.allclose(result["inertia1.w"], w0 + a1 * t, rtol=1e-7, atol=1e-9)
    tau_a, tau_b = result["gear.flange_a.tau"], result["gear.flange_b.tau"]
    assert np.allclose(tau_b, -RATIO * ETA1 * tau_a, rtol=1e-9)
    power_in = tau_a * result["gear.w_a"]
    power_out = -tau_b * result["inertia2.w"]
    assert np.allclose(power_out / power_in, ETA1, rtol=1e-9)
    assert set(result["gear.mode"]) == {FORWARD}
    assert np.all(result["gear.tau_etaPos"] == 1)


def test_flange_b_driving_transmits_eta_mf2_of_the_power():
    # rolling forward, torque on flange_b only: flange_b drives, quadrant 2
    # flange_a.tau = -J1*a1, flange_b.tau = -i*flange_a.tau/eta2, J2*a1/i = T - flange_b.tau
    T, J1, J2, w0 = 5.0, 1.0, 2.0, 1.0
    gear = LossyGear(ratio=RATIO, lossTable=[[0, ETA1, ETA2, 0, 0]])
    result = simulate(two_inertias(gear, tau_b=T, w0=w0, J1=J1, J2=J2), stop_time=1.0, interval=0.1)
    a1 = T / (J2 / RATIO + RATIO * J1 / ETA2)
    t = result.time
    assert np.allclose(result["inertia1.w"], w0 + a1 * t, rtol=1e-7, atol=1e-9)
    tau_a, tau_b = result["gear.flange_a.tau"], result["gear.flange_b.tau"]
    assert np.allclose(tau_b, -RATIO * tau_a / ETA2, rtol=1e-9)
    power_in = tau_b * result["inertia2.w"]
    power_out = -tau_a * result["gear.w_a"]
    assert np.allclose(power_out / power_in, ETA2, rtol=1e-9)
    assert np.all(result["gear.tau_etaPos"] == 0)


def test_backward_rolling_uses_the_same_efficiencies():
    # the mirror image of the two tests above (w0 < 0, torques reversed): quadrants 3 and 4
    T, J1, J2, w0 = 5.0, 1.0, 2.0, -1.0
    for tau_a, tau_b, eta, a1 in ((-T, 0.0, ETA1, -T / (J1 + J2 / (ETA1 * RATIO**2))),
                                  (0.0, -T, ETA2, -T / (J2 / RATIO + RATIO * J1 / ETA2))):
        gear = LossyGear(ratio=RATIO, lossTable=[[0, ETA1, ETA2, 0, 0]])
        result = simulate(two_inertias(gear, tau_a=tau_a, tau_b=tau_b, w0=w0, J1=J1, J2=J2),
                          stop_time=1.0, interval=0.1)
        assert np.allclose(result["inertia1.w"], w0 + a1 * result.time, rtol=1e-7, atol=1e-9)
        assert set(result["gear.mode"]) == {BACKWARD}
        power_a = result["gear.flange_a.tau"] * result["gear.w_a"]
        power_b = result["gear.flange_b.tau"] * result["inertia2.w"]
        driving, driven = (power_a, power_b) if tau_a else (power_b, power_a)
        assert np.allclose(-driven / driving, eta, rtol=1e-9)


# --------------------------------------------------------------------------
# bearing friction without load


def test_bearing_friction_coasts_to_rest_and_stays_there():
    # eta = 1: the loss is the bearing friction tau_bf referred to flange_a, for either
    # driving side; (J1 + J2/i^2)*a1 = -tau_bf until w = 0 at t* = J*w0/tau_bf, then locked
    J1, J2, w0, tau_bf = 1.0, 4.5, 1.0, 0.5
    gear = LossyGear(ratio=RATIO, lossTable=[[0, 1, 1, tau_bf, tau_bf]])
    result = simulate(two_inertias(gear, w0=w0, J1=J1, J2=J2), stop_time=4.0, interval=0.05)
    J = J1 + J2 / RATIO**2
    t_stop = J * w0 / tau_bf
    stops = [t for t, old, new in changes_of(result, "gear.mode") if (old, new) == (FORWARD, STUCK)]
    assert stops == [pytest.approx(t_stop, abs=1e-7)]
    t, w = result.time, result["inertia1.w"]
    rolling = t < t_stop - 1e-6
    assert np.allclose(w[rolling], w0 - tau_bf / J * t[rolling], rtol=1e-8, atol=1e-9)
    at_rest = t > t_stop + 1e-6
    assert np.all(np.abs(w[at_rest]) < 1e-9)
    assert np.all(result["gear.mode"][at_rest] == STUCK) and np.all(result["gear.locked"][at_rest] == 1)
    print(f"[lossy gear] coast-down stop at {stops[0]:.9f} s (closed form {t_stop:.9f} s)")


@pytest.mark.parametrize("w0", [2.0, -2.0])
def test_bearing_friction_split_with_open_flange_b(w0):
    # flange_b open (flange_b.tau = 0): flange_a.tau = tauLoss.  Rolling forward with flange_a
    # driving (quadrant 1): tauLoss = (1 - eta1)*tau_a + tau_bf1 = tau_a, so the brake torque on
    # Inertia1 is tau_bf1/eta1: the bearing friction of side b reaches side a through the mesh.
    eta1, eta2, tau_bf_a, tau_bf_b_over_i = 0.9, 0.8, 0.2, 0.3
    tau_bf1 = eta1 * tau_bf_a + tau_bf_b_over_i
    tau_bf2 = tau_bf_a / eta2 + tau_bf_b_over_i
    J1 = 1.0

    class Coast(Model):
        def build(self):
            self.inertia1 = Inertia(J=J1, phi=REST, w=dict(start=w0, fixed=True))
            self.gear = LossyGear(ratio=RATIO, lossTable=[[0, eta1, eta2, tau_bf1, tau_bf2]])
            self.connect(self.inertia1.flange_b, self.gear.flange_a)

    result = simulate(Coast(), stop_time=1.0, interval=0.1)
    decel = tau_bf1 / eta1
    assert np.allclose(result["gear.tau_bf_a"], tau_bf_a, rtol=1e-12)
    assert np.allclose(result["inertia1.w"], w0 - np.sign(w0) * decel / J1 * result.time, rtol=1e-8)
    assert np.allclose(result["gear.tauLoss"], np.sign(w0) * decel, rtol=1e-9)


# --------------------------------------------------------------------------
# ideal gear


def test_ideal_loss_table_is_an_ideal_gear():
    # default lossTable [0, 1, 1, 0, 0]: the same motion as IdealGear, no loss, mode Free
    source = dict(amplitude=3.0, f=2.0)

    def geared(make_gear):
        class Geared(Model):
            def build(self):
                self.sine = Sine(**source)
                self.torque = Torque()
                self.inertia1 = Inertia(J=1.0, phi=REST, w=REST)
                self.gear = make_gear()
                self.inertia2 = Inertia(J=2.0)
                self.load = ConstantTorque(tau_constant=-1.0)
                self.connect(self.sine.y, self.torque.tau)
                self.connect(self.torque.flange, self.inertia1.flange_a)
                self.connect(self.inertia1.flange_b, self.gear.flange_a)
                self.connect(self.gear.flange_b, self.inertia2.flange_a)
                self.connect(self.inertia2.flange_b, self.load.flange)

        return simulate(Geared(), stop_time=1.0, interval=0.01, rtol=1e-9)

    lossy = geared(lambda: LossyGear(ratio=RATIO))
    ideal = geared(lambda: IdealGear(ratio=RATIO))
    # the relation tau_eta >= 0 still makes events (as in the MSL), so compare on IdealGear's grid
    for name in ("inertia1.w", "inertia2.w", "inertia2.phi", "gear.flange_a.tau", "gear.flange_b.tau"):
        assert np.allclose(np.interp(ideal.time, lossy.time, lossy[name]), ideal[name],
                           rtol=1e-6, atol=1e-7), name
    assert np.all(lossy["gear.mode"] == FREE) and np.all(lossy["gear.ideal"] == 1)
    assert np.all(lossy["gear.lossPower"] == 0) and np.all(lossy["gear.locked"] == 0)
    changed = {name for e in lossy.events for (name, _, _) in e.changes}
    assert changed <= {"gear.tau_etaPos", "gear.tau_aPos"}, changed


# --------------------------------------------------------------------------
# locked under load


@pytest.mark.parametrize("load, expected", [(-25.0, STUCK), (-9.0, FORWARD), (-41.0, BACKWARD)])
def test_locked_gear_holds_a_load_below_its_self_locking_limit(load, expected):
    # eta1 = eta2 = 0.5, ratio 2, drive 10 N.m on flange_a, gear at rest.  Locked, the holding
    # torque is sa = tau_a + tau_b/ratio with tau_a = 10, tau_b = load, and the gear stays
    # locked while -tau_a/eta2 <= tau_b/ratio <= -eta1*tau_a, i.e. -40 <= load <= -10.
    gear = LossyGear(ratio=2.0, lossTable=[[0, 0.5, 0.5, 0, 0]])
    result = simulate(two_inertias(gear, tau_a=10.0, tau_b=load, J1=1.0, J2=1.5), stop_time=0.5,
                      interval=0.01)
    mode = result["gear.mode"]
    if expected == STUCK:
        assert np.all(mode == STUCK) and np.all(result["gear.locked"] == 1)
        assert np.all(result["inertia1.w"] == 0.0) and np.all(result["inertia2.w"] == 0.0)
        assert np.allclose(result["gear.sa"], 10.0 + load / 2.0, rtol=1e-12)
        assert not [e for e in result.events if e.changes and e.kind == "state"]
    else:
        assert mode[-1] == expected
        assert np.sign(result["inertia1.w"][-1]) == expected
        # the gear leaves the lock at t = 0 (the torques exceed the limit from the start)
        assert changes_of(result, "gear.locked")[0][0] == 0.0


# --------------------------------------------------------------------------
# heat port: energy balance


def test_heat_port_energy_balance():
    # lossPower = power into the gear through its flanges, pointwise; and the heat stored
    # in the capacitor equals the work of the sources minus the kinetic energy gained,
    # across rolling and locked phases (sine drive, constant load, eta 0.7/0.6, bearing friction)
    J1, J2, C = 1.0, 2.0, 10.0

    class Heated(Model):
        W = Variable(start=0.0, fixed=True, unit="J", description="Work done by the torque sources")

        def build(self):
            self.sine = Sine(amplitude=12.0, f=1.0)
            self.torque = Torque()
            self.inertia1 = Inertia(J=J1, phi=REST, w=REST)
            self.gear = LossyGear(ratio=RATIO, lossTable=[[0, 0.7, 0.6, 0.3, 0.4], [5, 0.6, 0.5, 0.5, 0.6]],
                                  useHeatPort=True)
            self.inertia2 = Inertia(J=J2)
            self.load = ConstantTorque(tau_constant=-6.0)
            self.capacitor = HeatCapacitor(C=C, T=dict(start=300.0, fixed=True))
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia1.flange_a)
            self.connect(self.inertia1.flange_b, self.gear.flange_a)
            self.connect(self.gear.flange_b, self.inertia2.flange_a)
            self.connect(self.inertia2.flange_b, self.load.flange)
            self.connect(self.gear.heatPort, self.capacitor.port)

        def equations(self):
            return [Eq(der(self.W), self.torque.tau * self.inertia1.w + self.load.tau * self.inertia2.w)]

    # the balance is checked between independently integrated states (capacitor, W, speeds),
    # so it holds to the integrator's global error: tight tolerance, high order
    result = simulate(Heated(), stop_time=2.0, interval=0.01, method="DOP853", rtol=1e-10)
    modes = set(result["gear.mode"])
    assert {FORWARD, STUCK, BACKWARD} <= modes, modes
    flange_power = (result["gear.flange_a.tau"] * result["inertia1.w"]
                    + result["gear.flange_b.tau"] * result["inertia2.w"])
    assert np.allclose(result["gear.lossPower"], flange_power, atol=1e-9)
    assert np.allclose(result["gear.heatPort.Q_flow"], -result["gear.lossPower"], atol=1e-12)
    assert np.all(result["gear.lossPower"] >= -1e-9)
    heat = C * (result["capacitor.T"] - 300.0)
    kinetic = 0.5 * J1 * result["inertia1.w"] ** 2 + 0.5 * J2 * result["inertia2.w"] ** 2
    imbalance = np.max(np.abs(heat - (result["W"] - kinetic)))
    print(f"[lossy gear] heat {heat[-1]:.6f} J, energy imbalance {imbalance:.2e} J, "
          f"modes {sorted(int(m) for m in modes)}")
    assert imbalance < 1e-8 * np.max(np.abs(result["W"]))
    # the loss table is interpolated linearly in |w_a| (extrapolated through the last two rows)
    speed = np.abs(result["gear.w_a"])
    assert np.allclose(result["gear.eta_mf1"], 0.7 - 0.02 * speed, rtol=1e-12)
    assert np.allclose(result["gear.tau_bf2"], 0.4 + 0.04 * speed, rtol=1e-12)
    assert np.allclose(result["gear.interpolation_result[1, 2]"], 0.6 - 0.02 * speed, rtol=1e-12)


# --------------------------------------------------------------------------
# Gearbox = LossyGear + ElastoBacklash


def drive_train(make_transmission, J1=1.0, J2=2.0, heat=False, connect_support=False):
    """Sine drive on inertia1 -> transmission -> inertia2 with a constant load; all at rest at t = 0."""

    class DriveTrain(Model):
        W = Variable(start=0.0, fixed=True, unit="J", description="Work done by the torque sources")

        def build(self):
            self.sine = Sine(amplitude=12.0, f=2.0)
            self.torque = Torque()
            self.inertia1 = Inertia(J=J1, phi=REST, w=REST)
            self.inertia2 = Inertia(J=J2, phi=REST, w=REST)
            self.load = ConstantTorque(tau_constant=-2.0)
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia1.flange_a)
            self.connect(self.inertia2.flange_b, self.load.flange)
            first, last = make_transmission(self)
            self.connect(self.inertia1.flange_b, first)
            self.connect(last, self.inertia2.flange_a)
            if heat:
                self.capacitor = HeatCapacitor(C=10.0, T=dict(start=1.0, fixed=True))
                self.connect(self.gearbox.heatPort, self.capacitor.port)
            if connect_support:
                self.fixed = Fixed()
                self.connect(self.gearbox.support, self.fixed.flange)

        def equations(self):
            return [Eq(der(self.W), self.torque.tau * self.inertia1.w + self.load.tau * self.inertia2.w)]

    return DriveTrain()


def test_gearbox_without_losses_and_backlash_is_a_gear_and_a_spring_damper():
    c, d = 1.0e4, 20.0

    def gearbox(model):
        model.gearbox = Gearbox(ratio=RATIO, c=c, d=d)
        return model.gearbox.flange_a, model.gearbox.flange_b

    def gear_and_spring(model):
        model.gear = IdealGear(ratio=RATIO)
        model.spring = SpringDamper(c=c, d=d)
        model.connect(model.gear.flange_b, model.spring.flange_a)
        return model.gear.flange_a, model.spring.flange_b

    boxed = simulate(drive_train(gearbox), stop_time=1.0, interval=0.01, rtol=1e-9)
    plain = simulate(drive_train(gear_and_spring), stop_time=1.0, interval=0.01, rtol=1e-9)
    for name in ("inertia1.w", "inertia2.w", "inertia2.phi"):
        assert np.allclose(np.interp(plain.time, boxed.time, boxed[name]), plain[name], rtol=1e-6, atol=1e-8), name
    assert np.allclose(np.interp(plain.time, boxed.time, boxed["gearbox.phi_rel"]), plain["spring.phi_rel"],
                       rtol=1e-6, atol=1e-10)
    # the gearbox's relative states are those over the elasticity
    assert np.allclose(boxed["gearbox.phi_rel"], boxed["inertia2.phi"] - boxed["inertia1.phi"] / RATIO,
                       atol=1e-12)
    assert np.allclose(boxed["gearbox.w_rel"], boxed["inertia2.w"] - boxed["inertia1.w"] / RATIO, atol=1e-9)


@pytest.mark.parametrize("d, b", [(0.0, 0.004), (20.0, 0.0)], ids=["backlash", "damping"])
def test_gearbox_heat_port_balances_work_kinetic_and_spring_energy(d, b):
    # heat from both parts (mesh and bearing losses, contact damping) = work of the sources
    # - kinetic energy - energy stored in the elasticity (zero inside the backlash gap).
    # Not with damping *and* backlash together: when the damper would pull the contact apart,
    # the MSL ElastoBacklash transmits no torque although the spring stays deflected, so the
    # spring energy 0.5*c*(|phi_rel| - b/2)^2 is not conserved there (a property of the MSL
    # model: 5e-4 J of 1.1 J in this drive train).
    c = 1.0e4
    J1, J2, C = 1.0, 2.0, 10.0

    def gearbox(model):
        model.gearbox = Gearbox(ratio=RATIO, lossTable=[[0, 0.8, 0.7, 0.2, 0.3]], c=c, d=d, b=b,
                                useHeatPort=True, useSupport=True)
        return model.gearbox.flange_a, model.gearbox.flange_b

    result = simulate(drive_train(gearbox, J1, J2, heat=True, connect_support=True), stop_time=1.0,
                      interval=0.01, method="DOP853", rtol=1e-10)
    assert result.success
    modes = set(result["gearbox.lossyGear.mode"])
    assert {FORWARD, BACKWARD} <= modes, modes
    stretch = np.maximum(np.abs(result["gearbox.phi_rel"]) - b / 2, 0.0)
    spring = 0.5 * c * stretch**2
    kinetic = 0.5 * J1 * result["inertia1.w"] ** 2 + 0.5 * J2 * result["inertia2.w"] ** 2
    heat = C * (result["capacitor.T"] - 1.0)
    imbalance = np.max(np.abs(heat - (result["W"] - kinetic - spring)))
    print(f"[gearbox] heat {heat[-1]:.6f} J of work {result['W'][-1]:.6f} J, imbalance {imbalance:.2e} J")
    assert imbalance < 1e-7 * np.max(np.abs(result["W"]))
    assert np.allclose(result["gearbox.heatPort.Q_flow"],
                       -(result["gearbox.lossyGear.lossPower"] + result["gearbox.elastoBacklash.lossPower"]),
                       atol=1e-12)
    # the housing takes the reaction torque of the gear
    housing = -(result["gearbox.lossyGear.flange_a.tau"] + result["gearbox.lossyGear.flange_b.tau"])
    assert np.allclose(result["gearbox.support.tau"], housing, atol=1e-9)


def test_gearbox_relative_states_can_be_fixed_at_the_start():
    # as in ModelicaTest.Rotational.AllComponents: phi_rel and w_rel fixed, inertia2 free
    class Preloaded(Model):
        def build(self):
            self.inertia1 = Inertia(J=1.0, phi=REST, w=REST)
            self.gearbox = Gearbox(ratio=RATIO, c=1.0e4, phi_rel=dict(start=1e-3, fixed=True),
                                   w_rel=dict(start=0.0, fixed=True))
            self.inertia2 = Inertia(J=2.0)
            self.connect(self.inertia1.flange_b, self.gearbox.flange_a)
            self.connect(self.gearbox.flange_b, self.inertia2.flange_a)

    result = simulate(Preloaded(), stop_time=0.05, interval=0.001)
    assert result["gearbox.phi_rel"][0] == pytest.approx(1e-3)
    assert result["inertia2.phi"][0] == pytest.approx(1e-3)
    # the preloaded spring pushes inertia2 back and, through the gear, inertia1 forward
    assert result["inertia2.w"][5] < 0
