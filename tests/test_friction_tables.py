"""Friction characteristics must be non-negative (tau_pos, mu_pos).

A negative entry in the second column of a friction table would make the
element push in the direction of the motion it is supposed to oppose: an
inertia on ``BearingFriction(tau_pos=[[0, 1], [1, -5]])`` with no drive spun
up from 1 to 1.36e5 rad/s in 2 s.  The MSL assumes tau_pos, mu_pos >= 0; the
library rejects a negative entry with a ParameterError that names the table
parameter, the row (counted from 1) and the value.  The generic option of
:func:`acausal.tables.validate_table` behind it is tested without any library.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import acausal
from acausal import Model
from acausal.errors import ParameterError
from acausal.tables import table_function, validate_table
from acausal.library.blocks import Constant
from acausal.library.rotational import BearingFriction, Brake, Clutch, Inertia, OneWayClutch

REST = dict(start=0, fixed=True)

#: Words of the domains that the engine's messages must not use (as tests/test_architecture.py).
DOMAIN_WORDS = ("friction", "clutch", "inertia", "torque", "bearing", "brake", "gear", "flange",
                "rotational", "translational", "thermal", "heat")


# --------------------------------------------------------------------------
# models


def attach(component, name="element"):
    """Give ``component`` a path in a model and build it (this runs its parameter checks)."""
    model = Model()
    setattr(model, name, component)
    component.ensure_built()
    return component


class Coast(Model):
    """An inertia spinning at 1 rad/s against a bearing, no drive."""

    def __init__(self, tau_pos=((0.0, 1.0),), **kwargs):
        self.tau_pos = [list(row) for row in tau_pos]
        super().__init__(**kwargs)

    def build(self):
        self.inertia = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
        self.bearing = BearingFriction(tau_pos=self.tau_pos)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


class Clutched(Model):
    """Two inertias coupled by an engaged clutch."""

    def __init__(self, mu_pos, **kwargs):
        self.mu_pos = mu_pos
        super().__init__(**kwargs)

    def build(self):
        self.inertia1 = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
        self.clutch = Clutch(mu_pos=self.mu_pos, fn_max=10)
        self.inertia2 = Inertia(J=1, phi=REST, w=REST)
        self.force = Constant(k=1)
        self.connect(self.inertia1.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.inertia2.flange_a)
        self.connect(self.force.y, self.clutch.f_normalized)


class Braked(Model):
    """An inertia spinning against an applied brake."""

    def __init__(self, mu_pos, **kwargs):
        self.mu_pos = mu_pos
        super().__init__(**kwargs)

    def build(self):
        self.inertia = Inertia(J=1, phi=REST, w=dict(start=1, fixed=True))
        self.brake = Brake(mu_pos=self.mu_pos, fn_max=1)
        self.force = Constant(k=1)
        self.connect(self.inertia.flange_b, self.brake.flange_a)
        self.connect(self.force.y, self.brake.f_normalized)


class Freewheel(Model):
    """Two inertias coupled by an engaged one-way clutch."""

    def __init__(self, mu_pos, **kwargs):
        self.mu_pos = mu_pos
        super().__init__(**kwargs)

    def build(self):
        self.inertia1 = Inertia(J=1, phi=REST, w=REST)
        self.oneWayClutch = OneWayClutch(mu_pos=self.mu_pos, fn_max=1, phi_rel=REST,
                                         w_rel=dict(start=1, fixed=True))
        self.inertia2 = Inertia(J=1)
        self.force = Constant(k=1)
        self.connect(self.inertia1.flange_b, self.oneWayClutch.flange_a)
        self.connect(self.oneWayClutch.flange_b, self.inertia2.flange_a)
        self.connect(self.force.y, self.oneWayClutch.f_normalized)


class Drive(Model):
    """A sub-model, so that the table's path has two levels."""

    def build(self):
        self.train = Coast(tau_pos=[[0, 1], [1, 2], [2, -0.5]])


# --------------------------------------------------------------------------
# the library rejects negative friction


def _raises(run, model):
    with pytest.raises(ParameterError) as info:
        run(model)
    return info.value


@pytest.mark.parametrize("run", [lambda m: acausal.simulate(m, stop_time=2), acausal.translate],
                         ids=["simulate", "translate"])
def test_pushing_bearing_friction_is_rejected(run):
    """The reproducer: tau_pos = [[0, 1], [1, -5]] spun an undriven inertia up to 1.36e5 rad/s."""
    error = _raises(run, Coast(tau_pos=[[0, 1], [1, -5]]))
    message = str(error)
    assert "bearing.tau_pos" in error.message
    assert "row 2" in error.message
    assert "-5" in error.message
    assert error.hint is not None and "hint:" in message
    assert "friction torque must not be negative" in error.hint
    assert isinstance(error, ValueError)


@pytest.mark.parametrize("model, where, row, value, quantity", [
    (lambda: Clutched(mu_pos=[[0, 0.5], [1, 0.4], [2, -0.1]]), "clutch.mu_pos", 3, "-0.1",
     "friction coefficient"),
    (lambda: Clutched(mu_pos=[[0, -0.5]]), "clutch.mu_pos", 1, "-0.5", "friction coefficient"),
    (lambda: Braked(mu_pos=[[0, 0.5], [10, -2]]), "brake.mu_pos", 2, "-2", "friction coefficient"),
    (lambda: Braked(mu_pos=[[0, -1e-3], [1, 0.5]]), "brake.mu_pos", 1, "-0.001", "friction coefficient"),
    (lambda: Freewheel(mu_pos=[[0, 0.5], [1, -0.5]]), "oneWayClutch.mu_pos", 2, "-0.5",
     "friction coefficient"),
    (lambda: Coast(tau_pos=[[0, -1]]), "bearing.tau_pos", 1, "-1", "friction torque"),
    (lambda: Drive(), "train.bearing.tau_pos", 3, "-0.5", "friction torque"),
])
def test_negative_friction_tables_are_rejected(model, where, row, value, quantity):
    error = _raises(acausal.translate, model())
    assert f"table {where}:" in error.message
    assert f"row {row} " in error.message
    assert f"y = {value}" in error.message
    assert f"{quantity} must not be negative" in error.hint
    assert "MSL" in error.hint


def test_first_negative_row_is_named():
    error = _raises(acausal.translate, Coast(tau_pos=[[0, 1], [1, -2], [2, -3]]))
    assert "row 2 " in error.message and "y = -2" in error.message


def test_negative_table_is_rejected_when_the_component_is_built():
    """The check runs in build(), before any equation is generated."""
    with pytest.raises(ParameterError, match=r"bf1\.tau_pos"):
        attach(BearingFriction(tau_pos=[[0, 1], [1, -5]]), "bf1")


def test_other_table_checks_still_come_first():
    """A malformed table reports its shape/order, not its values."""
    with pytest.raises(ParameterError, match="strictly increasing"):
        acausal.translate(Coast(tau_pos=[[1, -1], [0, -2]]))
    with pytest.raises(ParameterError, match="n x 2"):
        acausal.translate(Coast(tau_pos=[[0, -1, 2]]))


# --------------------------------------------------------------------------
# zero friction is allowed


def test_zero_at_rest_gives_viscous_decay():
    """tau_pos = [[0, 0], [1, 1]]: tau = w for w >= 0, so J*dw/dt = -w, w = exp(-t)."""
    result = acausal.simulate(Coast(tau_pos=[[0, 0], [1, 1]]), stop_time=2, rtol=1e-9, atol=1e-12)
    w = np.asarray(result["inertia.w"])
    t = np.asarray(result.time)
    np.testing.assert_allclose(w, np.exp(-t), rtol=1e-5, atol=1e-8)
    assert math.isclose(w[-1], math.exp(-2), rel_tol=1e-5)


def test_no_friction_keeps_the_speed():
    """tau_pos = [[0, 0]]: no friction at any speed, the inertia keeps its 1 rad/s."""
    result = acausal.simulate(Coast(tau_pos=[[0, 0]]), stop_time=2)
    np.testing.assert_allclose(result["inertia.w"], 1.0, rtol=1e-9)


@pytest.mark.parametrize("model", [
    lambda: Clutched(mu_pos=[[0, 0], [1, 0.5]]),
    lambda: Braked(mu_pos=[[0, 0.5], [1, 0.0]]),
    lambda: Freewheel(mu_pos=[[0, 0.0]]),
    lambda: Coast(tau_pos=[[0, 0.0], [1, -0.0]]),  # -0.0 is zero, not negative
])
def test_zero_values_pass(model):
    acausal.translate(model())


# --------------------------------------------------------------------------
# the MSL defaults and the tables of the MSL examples pass


@pytest.mark.parametrize("make", [
    BearingFriction, Clutch, Brake, OneWayClutch,
    lambda: BearingFriction(tau_pos=[[0, 0.5], [1, 1]]),  # LossyGearDemo2
    lambda: BearingFriction(tau_pos=[[0, 5], [100, 5]], peak=1.001),  # TestBearingConversion
    lambda: BearingFriction(tau_pos=[[0, 2]], peak=1.1),  # AllComponents
    lambda: Clutch(mu_pos=[[0, 1]], peak=1.1, cgeo=1.2, fn_max=1.3),  # AllComponents
    lambda: OneWayClutch(peak=25, fn_max=3),  # Examples.OneWayClutch
], ids=["BearingFriction", "Clutch", "Brake", "OneWayClutch", "LossyGearDemo2",
        "TestBearingConversion", "AllComponents.bearing", "AllComponents.clutch", "OneWayClutchExample"])
def test_msl_tables_pass(make):
    attach(make()).check_parameters()


def test_msl_defaults_translate():
    """Every friction element with its default table in one model translates."""
    acausal.translate(Coast())
    acausal.translate(Clutched(mu_pos=[[0.0, 0.5]]))
    acausal.translate(Braked(mu_pos=[[0.0, 0.5]]))
    acausal.translate(Freewheel(mu_pos=[[0.0, 0.5]]))


# --------------------------------------------------------------------------
# validate_table's value bound, without any library


def test_value_min_rejects_a_value_below_it():
    with pytest.raises(ParameterError) as info:
        validate_table([[0, 1], [1, -5]], "part.table", value_min=0.0)
    error = info.value
    assert error.message == ("table part.table: the second column must be >= 0, but row 2 (x = 1) "
                             "has y = -5")
    assert error.hint == "every value of the second column must be at least 0"
    assert isinstance(error, ValueError)


def test_value_min_names_the_first_row_below_it():
    with pytest.raises(ParameterError, match=r"row 3 \(x = 4\) has y = 1\.5"):
        validate_table([[0, 3], [2, 2], [4, 1.5], [6, 1]], "t", value_min=2)


def test_value_min_accepts_values_at_the_bound():
    data = validate_table([[0, 0], [1, 2], [3, 0]], "t", value_min=0)
    np.testing.assert_array_equal(data, [[0, 0], [1, 2], [3, 0]])
    assert not data.flags.writeable
    validate_table([[0, -2], [1, -1]], "t", value_min=-2)


def test_value_min_applies_to_the_second_column_only():
    validate_table([[-3, 1], [-1, 2]], "t", value_min=0)


def test_no_bound_by_default():
    """Without value_min, negative values are fine (tables in general may be negative)."""
    validate_table([[0, -1], [1, -5]], "t")
    f = table_function("signed", [[0, -1], [1, -5]])
    assert float(f(0.5)) == -3.0


def test_value_hint_replaces_the_generic_hint():
    with pytest.raises(ParameterError) as info:
        validate_table([[0, -1]], "t", value_min=0, value_hint="costs cannot be negative")
    assert info.value.hint == "costs cannot be negative"
    assert "row 1 (x = 0) has y = -1" in info.value.message


def test_value_min_is_checked_after_the_structure():
    with pytest.raises(ParameterError, match="strictly increasing"):
        validate_table([[1, -1], [0, -2]], "t", value_min=0)
    with pytest.raises(ParameterError, match="non-finite"):
        validate_table([[0, -np.inf]], "t", value_min=0)


def test_value_messages_are_domain_free():
    with pytest.raises(ParameterError) as info:
        validate_table([[0, -1]], "t", value_min=0)
    text = str(info.value).lower()
    assert not [w for w in DOMAIN_WORDS if w in text]
