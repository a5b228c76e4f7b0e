"""The DC machines' ``powerBalance`` record (Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDC*).

The three MSL start-up examples (``examples/electrical_dc_machines.py``), as
given and with losses switched on, are simulated once each; at every output
row the power the machine takes at its pins must equal what its shaft
delivers, what its inertias and windings store and what it loses.  Every
power except the total loss is computed here from independent quantities:
the pins' voltages and currents, the flange's torque and the load's speed,
``J*w*dw/dt`` and ``L*i*di/dt`` with the derivatives taken numerically from
the output trajectory (central differences on the 0.1 ms output grid,
between the events), and each loss from its law (``Ra*ia^2``, the brush drop
times the current, ``GcRef*v^2``, the friction and stray load torques times
the speed).  The record leaves out the windings' magnetic energy; the
balance here adds it.

The tolerance reflects the numerical derivatives of an RK45 trajectory
(rtol 1e-6): measured residuals are below 1e-5 of the peak electrical power
for the permanent magnet and electrically excited machines and 1e-4 for the
series excited one (whose current rises in milliseconds at the start).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from acausal import simulate
from acausal.errors import StartValueWarning
from acausal.library.electrical import DC_ElectricalExcited, DC_PermanentMagnet, DC_SeriesExcited
from acausal.library.electrical.machines import (
    PartialPowerBalanceDCMachines,
    PowerBalanceDCEE,
    PowerBalanceDCPM,
    PowerBalanceDCSE,
)
from examples.electrical_dc_machines import ARMATURE, DCEE_Start, DCPM_Start, DCSE_Start

#: Losses switched on: friction, stray load, brushes and (PM, EE) core losses.  The series
#: machine keeps its core lossless: the core's conductance across the air gap makes it a
#: stiff system (time constant La*GcRef ~ 30 us) that RK45 crosses in seconds, not a test's time.
P_FRICTION, P_STRAY, P_CORE, V_BRUSH, I_LINEAR = 100.0, 50.0, 200.0, 1.0, 1.0
LOSSES = dict(frictionParameters=dict(PRef=P_FRICTION), strayLoadParameters=dict(PRef=P_STRAY),
              brushParameters=dict(V=V_BRUSH, ILinear=I_LINEAR))
LOSSES_WITH_CORE = dict(LOSSES, coreParameters=dict(PRef=P_CORE))

#: Example -> (machine instance name, its record class, its nominal speed, excitation winding (Re, Le) or None).
MACHINES = {
    DCPM_Start: ("dcpm", PowerBalanceDCPM, 1425 * 2 * math.pi / 60, None),
    DCEE_Start: ("dcee", PowerBalanceDCEE, 1425 * 2 * math.pi / 60, (100.0, 1.0)),
    DCSE_Start: ("dcse", PowerBalanceDCSE, 1410 * 2 * math.pi / 60, (0.01, 0.0005)),
}
RA, LA, JR = ARMATURE["Ra"], ARMATURE["La"], ARMATURE["Jr"]
IA_NOMINAL, VA_NOMINAL = ARMATURE["IaNominal"], ARMATURE["VaNominal"]

#: The balance's tolerance, relative to the peak electrical input power.
BALANCE_TOLERANCE = 5e-4

CASES = [(example, lossy) for example in MACHINES for lossy in (False, True)]
IDS = [f"{example.__name__}-{'losses' if lossy else 'lossless'}" for example, lossy in CASES]

_results: dict = {}


def start_up(example, lossy: bool):
    """The example's result (each simulated once per test session)."""
    key = (example, lossy)
    if key not in _results:
        name, *_ = MACHINES[example]
        losses = (LOSSES if example is DCSE_Start else LOSSES_WITH_CORE) if lossy else {}
        with warnings.catch_warnings():
            # DCSE_Start leaves la.i (= the air gap's current) to its start value, as the MSL example does
            warnings.simplefilter("ignore", StartValueWarning)
            result = simulate(example(**({name: losses} if losses else {})))
        assert result.success, result.message
        _results[key] = result
    return _results[key]


def time_derivative(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """dy/dt by second-order differences, piecewise between the events (the rows with repeated times)."""
    dy = np.full_like(y, np.nan)
    cuts = np.flatnonzero(np.diff(t) <= 0) + 1
    for start, stop in zip(np.r_[0, cuts], np.r_[cuts, len(t)]):
        if stop - start > 2:
            dy[start:stop] = np.gradient(y[start:stop], t[start:stop], edge_order=2)
    return dy


def brush_drop(i: np.ndarray, V: float, i_linear: float) -> np.ndarray:  # noqa: N803 - Modelica name
    """The carbon brushes' voltage drop: +-V beyond +-i_linear, linear in between."""
    return np.where(i > i_linear, V, np.where(i < -i_linear, -V, V * i / i_linear))


def independent_losses(example, lossy: bool, result) -> dict[str, np.ndarray]:
    """Each loss of the record, from its law and the machine's currents, voltages and speed."""
    name, _record, w_nominal, winding = MACHINES[example]
    x = lambda variable: result[f"{name}.{variable}"]  # noqa: E731
    ia, w = x("pin_ap.i"), x("wMechanical")
    zero = np.zeros_like(ia)
    losses = {"lossPowerArmature": RA * ia ** 2, "lossPowerCore": zero, "lossPowerStrayLoad": zero,
              "lossPowerFriction": zero, "lossPowerBrush": zero}
    if lossy:
        losses["lossPowerBrush"] = brush_drop(ia, V_BRUSH, I_LINEAR) * ia
        # friction: tauRef*(|w|/wRef)^2 beyond wLinear = 1e-3*wRef, linear below (wRef = wNominal)
        tau_ref, w_linear = P_FRICTION / w_nominal, 1e-3 * w_nominal
        tau_linear = tau_ref * (w_linear / w_nominal) ** 2
        tau_friction = np.where(np.abs(w) > w_linear, tau_ref * np.sign(w) * (np.abs(w) / w_nominal) ** 2,
                                tau_linear * w / w_linear)
        losses["lossPowerFriction"] = tau_friction * w
        # stray load: tauRef*(i/IRef)^2*(|w|/wRef) with IRef = IaNominal
        losses["lossPowerStrayLoad"] = P_STRAY / w_nominal * (ia / IA_NOMINAL) ** 2 * np.abs(w) / w_nominal * np.abs(w)
        if example is not DCSE_Start:
            # core: GcRef = PRef/ViNominal^2 across the air gap and the armature inductance
            vi_nominal = VA_NOMINAL - RA * IA_NOMINAL - V_BRUSH
            losses["lossPowerCore"] = P_CORE / vi_nominal ** 2 * (x("la.p.v") - x("airGapDC.pin_an.v")) ** 2
    if example is DCPM_Start:
        losses["lossPowerPermanentMagnet"] = zero
    elif example is DCEE_Start:
        losses["lossPowerExcitation"] = winding[0] * x("pin_ep.i") ** 2
    else:
        losses["lossPowerSeriesExcitation"] = winding[0] * x("pin_ep.i") ** 2
    return losses


# --------------------------------------------------------------------------
# the records


def test_each_machine_carries_its_msl_record():
    expected = {DC_PermanentMagnet: PowerBalanceDCPM, DC_ElectricalExcited: PowerBalanceDCEE,
                DC_SeriesExcited: PowerBalanceDCSE}
    common = {"powerArmature", "powerMechanical", "powerInertiaStator", "powerInertiaRotor", "lossPowerTotal",
              "lossPowerArmature", "lossPowerCore", "lossPowerStrayLoad", "lossPowerFriction", "lossPowerBrush"}
    own = {PowerBalanceDCPM: {"lossPowerPermanentMagnet"},
           PowerBalanceDCEE: {"powerExcitation", "lossPowerExcitation"},
           PowerBalanceDCSE: {"powerSeriesExcitation", "lossPowerSeriesExcitation"}}
    package = "Modelica.Electrical.Machines.Interfaces.DCMachines."
    assert PartialPowerBalanceDCMachines.modelica_name == package + "PartialPowerBalanceDCMachines"
    for machine, record in expected.items():
        assert machine.power_balance_record is record
        assert record.modelica_name == package + record.__name__
        declared = record.declarations()
        assert set(declared) == common | own[record]
        assert all(declaration.unit == "W" for declaration in declared.values())


# --------------------------------------------------------------------------
# the balance at every output row


@pytest.mark.parametrize("example, lossy", CASES, ids=IDS)
def test_power_in_is_power_out_plus_stored_plus_lost_at_every_row(example, lossy):
    """va*ia (+ ve*ie) = tauShaft*w + J*w*dw/dt + L*i*di/dt + lossPowerTotal, from the pins and flanges."""
    result = start_up(example, lossy)
    name, _record, _w_nominal, winding = MACHINES[example]
    x = lambda variable: result[f"{name}.{variable}"]  # noqa: E731
    t = result.time
    power_in = (x("pin_ap.v") - x("pin_an.v")) * x("pin_ap.i")
    if winding is not None:
        power_in = power_in + (x("pin_ep.v") - x("pin_en.v")) * x("pin_ep.i")
    # the shaft turns the load inertia: its speed is the flange's (the stator is fixed)
    w = result["loadInertia.w"]
    power_shaft = -x("flange.tau") * w
    power_inertia = JR * w * time_derivative(t, w)
    # the magnetic energy of the armature inductance and of the field winding (main + stray: Le)
    ia = x("la.i")
    power_magnetic = LA * ia * time_derivative(t, ia)
    if winding is not None:
        ie = x("pin_ep.i")
        power_magnetic = power_magnetic + winding[1] * ie * time_derivative(t, ie)
    residual = power_in - power_shaft - power_inertia - power_magnetic - x("powerBalance.lossPowerTotal")

    peak = np.max(np.abs(power_in))
    assert peak > 1e4  # the machines run up to about 11 kW
    checked = ~np.isnan(residual)
    assert checked.sum() > 0.99 * len(t)  # only segments of two rows or fewer between events are left out
    worst = np.max(np.abs(residual[checked]))
    assert worst < BALANCE_TOLERANCE * peak, f"worst residual {worst:.3g} W of {peak:.3g} W"


@pytest.mark.parametrize("example, lossy", CASES, ids=IDS)
def test_the_record_terms_are_the_powers_at_the_pins_and_flanges(example, lossy):
    result = start_up(example, lossy)
    name, _record, _w_nominal, winding = MACHINES[example]
    x = lambda variable: result[f"{name}.{variable}"]  # noqa: E731
    balance = lambda term: x(f"powerBalance.{term}")  # noqa: E731
    t, w = result.time, result["loadInertia.w"]
    peak = np.max(np.abs(balance("powerArmature")))
    np.testing.assert_allclose(balance("powerArmature"), (x("pin_ap.v") - x("pin_an.v")) * x("pin_ap.i"),
                               rtol=1e-9, atol=1e-9 * peak)
    np.testing.assert_allclose(balance("powerMechanical"), -x("flange.tau") * w, rtol=1e-9, atol=1e-9 * peak)
    inertia = JR * w * time_derivative(t, w)
    checked = ~np.isnan(inertia)
    np.testing.assert_allclose(balance("powerInertiaRotor")[checked], inertia[checked],
                               atol=BALANCE_TOLERANCE * peak)
    # the stator is fixed: it stores nothing
    np.testing.assert_array_equal(balance("powerInertiaStator"), 0.0)
    if winding is not None:
        term = "powerExcitation" if example is DCEE_Start else "powerSeriesExcitation"
        np.testing.assert_allclose(balance(term), (x("pin_ep.v") - x("pin_en.v")) * x("pin_ep.i"),
                                   rtol=1e-9, atol=1e-9 * peak)


@pytest.mark.parametrize("example, lossy", CASES, ids=IDS)
def test_each_loss_follows_its_law_and_the_total_is_their_sum(example, lossy):
    result = start_up(example, lossy)
    name, record, *_ = MACHINES[example]
    balance = lambda term: result[f"{name}.powerBalance.{term}"]  # noqa: E731
    expected = independent_losses(example, lossy, result)
    # every loss term of the record, and no other
    assert set(expected) == {n for n in record.declarations() if n.startswith("lossPower")} - {"lossPowerTotal"}
    scale = np.max(np.abs(balance("powerArmature")))
    for term, law in expected.items():
        np.testing.assert_allclose(balance(term), law, rtol=1e-8, atol=1e-9 * scale, err_msg=term)
    if lossy:
        for term in ("lossPowerBrush", "lossPowerFriction", "lossPowerStrayLoad"):
            assert np.max(balance(term)) > 1.0, term  # the losses switched on are there
    total = sum(balance(term) for term in expected)
    np.testing.assert_allclose(balance("lossPowerTotal"), total, rtol=1e-12, atol=1e-9 * scale)
