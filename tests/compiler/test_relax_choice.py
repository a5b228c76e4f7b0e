"""Which share a redundant constraint leaves open (issue 22, item 3).

A LossyGear and a Brake both stuck lock one shaft twice; their heat ports
share one Convection node.  ``relax_redundant`` used to set the first flow
variable of the under-determined part to zero, in declaration order: with
the convection declared first that was a heat flow, which the loss power
ties to the torques only through ``lossPower = tauLoss*w`` (zero speed when
stuck), so the system was numerically singular at initialization.  The
share set to zero must be a variable of the redundant constraint itself (a
torque of the locked loop), whatever the declaration order.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.errors import RedundantConstraintWarning
from acausal.library.blocks import Constant, Sine
from acausal.library.rotational import Brake, Inertia, LossyGear, Torque
from acausal.library.thermal import Convection, FixedTemperature


def _gear_and_brake(convection_first: bool) -> Model:
    class GearAndBrake(Model):
        """A drive below both holding limits: the gear and the brake stay stuck."""

        experiment = Experiment(stop_time=1.0, interval=0.001)

        def build(self):
            if convection_first:
                self.convection = Convection()
            self.drive = Sine(amplitude=2, f=1)
            self.torque = Torque()
            self.inertia1 = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.gear = LossyGear(ratio=2, lossTable=[[0, 0.5, 0.5, 0, 0]], useHeatPort=True)
            self.inertia2 = Inertia(J=1.5)
            self.brake = Brake(fn_max=10, mu_pos=[[0, 0.5]], useHeatPort=True)
            self.fn = Constant(k=1)
            self.gc = Constant(k=10)
            self.ambient = FixedTemperature(T=293.15)
            if not convection_first:
                self.convection = Convection()
            self.connect(self.drive.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia1.flange_a)
            self.connect(self.inertia1.flange_b, self.gear.flange_a)
            self.connect(self.gear.flange_b, self.inertia2.flange_a)
            self.connect(self.inertia2.flange_b, self.brake.flange_a)
            self.connect(self.fn.y, self.brake.f_normalized)
            self.connect(self.gear.heatPort, self.convection.solid)
            self.connect(self.brake.heatPort, self.convection.solid)
            self.connect(self.convection.fluid, self.ambient.port)
            self.connect(self.gc.y, self.convection.Gc)

    return GearAndBrake()


def _run(convection_first: bool):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(_gear_and_brake(convection_first), rtol=1e-8, atol=1e-10)
    # what was left out and what was set to zero (the lines after the components)
    relaxations = {"\n".join(str(w.message).splitlines()[1:3]) for w in caught
                   if issubclass(w.category, RedundantConstraintWarning)}
    return result, relaxations


@pytest.mark.parametrize("convection_first", [True, False], ids=["convection-first", "convection-last"])
def test_a_torque_of_the_locked_loop_is_left_open(convection_first):
    result, relaxations = _run(convection_first)
    assert result.success, result.message
    assert relaxations, "both elements stuck: the state constrains the shaft twice"
    for text in relaxations:
        zeroed = text.split("set to 0: ", 1)[1].split(" ", 1)[0]
        assert zeroed.endswith(".tau") and "heatPort" not in zeroed, text
    # stuck all along: the shaft rests, the inertias feel no net torque, nothing dissipates
    assert np.max(np.abs(result["inertia1.w"])) < 1e-9
    assert np.max(np.abs(result["inertia1.flange_a.tau"] + result["inertia1.flange_b.tau"])) < 1e-8
    assert np.max(np.abs(result["convection.Q_flow"])) < 1e-8
    # the drive is held: the torque reaching the gear is the drive's
    drive = 2 * np.sin(2 * np.pi * result.time)
    assert np.max(np.abs(result["gear.flange_a.tau"] - drive)) < 1e-8


def test_the_choice_does_not_depend_on_the_declaration_order():
    first, relax_first = _run(True)
    last, relax_last = _run(False)
    assert relax_first == relax_last
    for name in ("inertia1.phi", "gear.flange_a.tau", "brake.tau", "convection.Q_flow"):
        np.testing.assert_allclose(first[name], last[name], atol=1e-12)
