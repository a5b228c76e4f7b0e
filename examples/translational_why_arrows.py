"""Modelica.Mechanics.Translational.Examples.WhyArrows: what the arrows of the icons mean.

Why every icon has an arrow (from flange_a to flange_b): a rod's length
counts along its arrow, whichever way it is drawn.  Three 1 m rods meet at
one fixed point: rod1 ends there with flange_b, rod2 and rod3 start there
with flange_a, so the position sensors at their free ends read -1, +1 and
+1 m.  In the diagram rod3 is drawn flipped, to the left of the fixed
point like rod1, yet its free end is at +1 m like rod2's: only its arrow
tells.  Below, two identical 1 kg masses of length
2 m are pulled by springs (``s_rel0 = 2``, ``c = 11``) fixed at -1.9 m, each
spring acting on the mass's flange_b: mass1 is drawn in the axis direction,
inertia2 flipped, yet both move identically (the equations follow the
flanges, not the drawing).

Run ``acausal compare examples/translational_why_arrows.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.translational import Fixed, Mass, PositionSensor, Rod, Spring


class WhyArrows(Model):
    """Use of arrows in Mechanics.Translational."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.WhyArrows"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        fixed = dict(fixed=True)
        self.fixed = Fixed()
        self.rod1 = Rod(L=1)
        self.rod2 = Rod(L=1)
        self.rod3 = Rod(L=1)
        self.positionSensor2 = PositionSensor()
        self.positionSensor1 = PositionSensor()
        self.positionSensor3 = PositionSensor()
        self.fixed1 = Fixed(s0=-1.9)
        self.spring1 = Spring(s_rel0=2, c=11)
        self.mass1 = Mass(L=2, s=fixed, v=fixed, m=1)
        self.fixed2 = Fixed(s0=-1.9)
        self.spring2 = Spring(s_rel0=2, c=11)
        self.inertia2 = Mass(L=2, m=1, s=fixed, v=fixed)

        self.connect(self.spring1.flange_b, self.mass1.flange_b)
        self.connect(self.spring2.flange_b, self.inertia2.flange_b)
        self.connect(self.rod3.flange_b, self.positionSensor3.flange)
        self.connect(self.rod1.flange_a, self.positionSensor1.flange)
        self.connect(self.rod1.flange_b, self.fixed.flange)
        self.connect(self.rod3.flange_a, self.fixed.flange)
        self.connect(self.fixed.flange, self.rod2.flange_a)
        self.connect(self.rod2.flange_b, self.positionSensor2.flange)
        self.connect(self.fixed1.flange, self.spring1.flange_a)
        self.connect(self.fixed2.flange, self.spring2.flange_a)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(WhyArrows())
    print(result.summary())
    print("sensors:", [result.final(f"positionSensor{i}.s") for i in (1, 2, 3)])
