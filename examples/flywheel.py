"""A teaching example written from scratch: a flywheel spun up against air drag.

It shows the three things a user writes:

1. a component: ``QuadraticDrag`` declares a flange, a parameter and two
   variables, and states its equation ``tau = k·w·|w|`` (acausal: nothing
   says what is computed from what);
2. a model: instances, modifiers (``w=dict(start=0, fixed=True)``) and
   ``connect`` statements;
3. a simulation, checked against the closed-form answer.

A constant torque T accelerates a flywheel of inertia J against the drag
torque k·w²; the speed approaches w_inf = sqrt(T/k) as

    w(t) = w_inf · tanh(t · sqrt(T·k) / J).
"""

import math

import sympy as sp

from acausal import Component, Eq, Experiment, Model, Parameter, Variable, der
from acausal.components.rotational import Flange_a
from acausal.library.rotational import ConstantTorque, Inertia


class QuadraticDrag(Component):
    """Air drag on a shaft: a torque against the motion, growing with the speed squared."""

    k = Parameter(0.02, unit="N.m.s2/rad2", min=0, description="Drag coefficient")
    flange = Flange_a()
    w = Variable(unit="rad/s", description="Speed of the flange")
    tau = Variable(unit="N.m", description="Drag torque")

    def equations(self):
        return [
            Eq(self.w, der(self.flange.phi)),
            Eq(self.tau, self.k * self.w * sp.Abs(self.w)),
            Eq(self.flange.tau, self.tau),  # the drag acts on the connected shaft against w
        ]


class Flywheel(Model):
    """A motor with constant torque spins a flywheel up against air drag."""

    experiment = Experiment(start_time=0.0, stop_time=20.0, interval=0.01)

    def build(self):
        self.motor = ConstantTorque(tau_constant=2.0)
        self.flywheel = Inertia(J=0.5, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.drag = QuadraticDrag(k=0.02)
        self.connect(self.motor.flange, self.flywheel.flange_a)
        self.connect(self.flywheel.flange_b, self.drag.flange)


def exact_speed(t, T=2.0, J=0.5, k=0.02):
    """The closed-form speed of the flywheel."""
    return math.sqrt(T / k) * math.tanh(t * math.sqrt(T * k) / J)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Flywheel(), rtol=1e-8)
    error = max(abs(w - exact_speed(t)) for t, w in zip(result.time, result["flywheel.w"]))
    print(result.summary())
    print(f"flywheel.w(20) = {result.final('flywheel.w'):.6f} rad/s, "
          f"terminal speed {math.sqrt(2.0 / 0.02):.6f}; max error vs closed form {error:.2e}")
