"""The teaching view shows what a model's when-clauses do: condition, assignments, reinits, clocks."""

from __future__ import annotations

from acausal import Eq, Experiment, Model, Parameter, Variable, When, der, pre, reinit, sample
from acausal.tools.explain import explain


class Ball(Model):
    experiment = Experiment(stop_time=1.0)
    e = Parameter(0.8)
    h = Variable(start=1.0, fixed=True)
    v = Variable(start=0.0, fixed=True)

    def equations(self):
        return [Eq(der(self.h), self.v), Eq(der(self.v), -9.81),
                When(self.h <= 0, reinit(self.v, -self.e * self.v))]


class Counter(Model):
    experiment = Experiment(stop_time=1.0)
    x = Variable(start=0.0, fixed=True)
    n = Variable(discrete=True, start=0.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), 1.0), When(sample(0.1, 0.25), Eq(self.n, pre(self.n) + self.x))]


def test_when_clause_with_reinit_is_listed(tmp_path):
    text = str(explain(Ball(), out_dir=tmp_path))
    section = text[text.index("When-clauses (1)"):]
    assert "$when0 = (h <= 0)" in section
    assert "reinit(v, -e*v)" in section


def test_sample_clock_and_held_real_are_listed(tmp_path):
    text = str(explain(Counter(), out_dir=tmp_path))
    section = text[text.index("When-clauses (1)"):]
    assert "assigns: n" in section
    assert "$sample0 = sample(0.1, 0.25)" in section
    assert "Discrete Reals (held between events" in section and " n" in section
