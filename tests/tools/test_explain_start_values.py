"""explain says which states initialization takes from their start values."""

import warnings

from acausal import Model
from acausal.library.rotational import ConstantTorque, Inertia
from acausal.tools.explain import explain


class OnlySpeedFixed(Model):
    def build(self):
        self.src = ConstantTorque(tau_constant=2.0)
        self.body = Inertia(J=0.5, phi=dict(start=1.5), w=dict(start=10.0, fixed=True))
        self.connect(self.src.flange, self.body.flange_a)


def test_the_states_taken_from_start_values_are_listed(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        text = explain(OnlySpeedFixed(), out_dir=tmp_path, pictures=False).text
    head, _, listed = text.partition("start from their start values")
    assert listed, text
    lines = listed.splitlines()[1:3]
    # the angle (the source's and the inertia's, one state) with its start value
    assert any(line.strip().endswith("= 1.5") and "phi" in line for line in lines), lines


def test_a_fully_fixed_model_lists_none(tmp_path):
    class AllFixed(Model):
        def build(self):
            self.src = ConstantTorque(tau_constant=2.0)
            self.body = Inertia(J=0.5, phi=dict(start=1.5, fixed=True), w=dict(start=10.0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    text = explain(AllFixed(), out_dir=tmp_path, pictures=False).text
    assert "start from their start values" not in text
