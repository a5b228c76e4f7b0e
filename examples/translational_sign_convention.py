"""Modelica.Mechanics.Translational.Examples.SignConvention: the sign conventions of forces and flanges.

Three 1 kg masses (length 1 m) start at rest and are pushed by a constant
1 N force each.  The force acts on flange_a of mass1, on flange_b of mass2
and, through a source that reacts on a fixed housing, on flange_b of mass3:
in every case a positive force accelerates the mass in the positive
direction (all three move to s = 0.5 m at t = 1 s), whichever flange it acts
on.  force3 has ``useSupport=false``: the source is implicitly grounded and
the MSL's connection of its (disabled) support to ``fixed`` is void.

Run ``acausal compare examples/translational_sign_convention.py`` to check
it against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Constant
from acausal.library.translational import Fixed, Force, Mass


class SignConvention(Model):
    """Examples for the used sign conventions."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.SignConvention"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        at_rest = dict(fixed=True)
        self.mass1 = Mass(L=1, s=at_rest, v=at_rest, m=1)
        self.force1 = Force()
        self.constant1 = Constant(k=1)
        self.mass2 = Mass(L=1, s=at_rest, v=at_rest, m=1)
        self.force2 = Force()
        self.constant2 = Constant(k=1)
        self.mass3 = Mass(L=1, s=at_rest, v=at_rest, m=1)
        self.force3 = Force(useSupport=False)
        self.constant3 = Constant(k=1)
        self.fixed = Fixed()

        self.connect(self.constant1.y, self.force1.f)
        self.connect(self.constant2.y, self.force2.f)
        self.connect(self.constant3.y, self.force3.f)
        self.connect(self.force1.flange, self.mass1.flange_a)
        self.connect(self.force2.flange, self.mass2.flange_b)
        self.connect(self.mass3.flange_b, self.force3.flange)
        # The MSL also connects fixed.flange to force3.support; with useSupport=false that
        # connector does not exist and Modelica deletes the connection.  The engine rejects a
        # connection to a disabled connector instead, so it is left out here (same equations).


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(SignConvention())
    print(result.summary())
    print("s(1) of the three masses:", [result.final(f"mass{i}.s") for i in (1, 2, 3)])
