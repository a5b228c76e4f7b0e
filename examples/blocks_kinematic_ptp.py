"""ModelicaTest.Blocks.KinematicPTP: point-to-point motions, as acceleration and as position.

Two ``KinematicPTP`` blocks (distances 1 and 4, ``qd_max = 3``, ``qdd_max =
4``, starting at t = 0.5) give the acceleration of the fastest motion; two
integrators each turn it into a position starting at 1.  Two
``KinematicPTP2`` blocks plan the same motions from 1 to 2 and from 1 to 5
and give the position directly; the feedbacks subtract them from the
integrated ones (zero up to the integration error).  The first motion never
reaches ``qd_max`` (bang-bang), the second cruises at it.

Run ``acausal compare examples/blocks_kinematic_ptp.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Feedback, Integrator
from acausal.library.blocks.sources import KinematicPTP, KinematicPTP2


class KinematicPTPTest(Model):
    """ModelicaTest.Blocks.KinematicPTP."""

    modelica_class = "ModelicaTest.Blocks.KinematicPTP"
    experiment = Experiment(start_time=0.0, stop_time=3.0, interval=0.0006)

    def build(self):
        self.kinematicPTP1a = KinematicPTP(qd_max=[3], qdd_max=[4], startTime=0.5, deltaq=[1])
        self.integrator = Integrator()
        self.integrator1 = Integrator(y_start=1)
        self.kinematicPTP2a = KinematicPTP(qd_max=[3], qdd_max=[4], startTime=0.5, deltaq=[4])
        self.integrator2 = Integrator()
        self.integrator3 = Integrator(y_start=1)
        self.kinematicPTP1b = KinematicPTP2(qd_max=[3], qdd_max=[4], startTime=0.5, q_end=[2], q_begin=[1])
        self.kinematicPTP2b = KinematicPTP2(qd_max=[3], qdd_max=[4], startTime=0.5, q_end=[5], q_begin=[1])
        self.diff1 = Feedback()
        self.diff2 = Feedback()
        self.connect(self.kinematicPTP1a.y[1], self.integrator.u)
        self.connect(self.integrator.y, self.integrator1.u)
        self.connect(self.kinematicPTP2a.y[1], self.integrator2.u)
        self.connect(self.integrator2.y, self.integrator3.u)
        self.connect(self.integrator1.y, self.diff1.u1)
        self.connect(self.kinematicPTP1b.q[1], self.diff1.u2)
        self.connect(self.integrator3.y, self.diff2.u1)
        self.connect(self.kinematicPTP2b.q[1], self.diff2.u2)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(KinematicPTPTest())
    print(result.summary())
