"""ModelicaTest.Blocks.MuxDemux: multiplexers and demultiplexers passing one clock signal.

A ContinuousClock feeds both inputs of a Multiplex of size 2 and all three
of a Multiplex of size 3; a Multiplex of size 5 joins their outputs
(``mux2.y`` to ``mux5.u[1:2]``, ``mux3.y`` to ``mux5.u[3:5]``), a
DeMultiplex of size 5 takes them and hands its first two outputs to a
DeMultiplex of size 2, its last three to one of size 3, whose outputs are
the model's outputs ``y1`` ... ``y5``.  Every signal is ``time``: the
routing neither loses nor reorders anything.

Run ``acausal compare examples/blocks_mux_demux.py`` to check it against the
MSL reference results (ModelicaTest.Blocks.MuxDemux).
"""

from acausal import Experiment, Model, RealOutput
from acausal.library.blocks import ContinuousClock, DeMultiplex, Multiplex


class MuxDemux(Model):
    """Test model for the Mux and Demux blocks."""

    modelica_class = "ModelicaTest.Blocks.MuxDemux"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=2.0 / 5000)

    y1 = RealOutput()
    y2 = RealOutput()
    y3 = RealOutput()
    y4 = RealOutput()
    y5 = RealOutput()

    def build(self):
        self.clock = ContinuousClock()
        self.mux5 = Multiplex(n=5)
        self.demux5 = DeMultiplex(n=5)
        self.mux3 = Multiplex(n=3)
        self.mux2 = Multiplex(n=2)
        self.demux2 = DeMultiplex(n=2)
        self.demux3 = DeMultiplex(n=3)

        self.connect(self.clock.y, self.mux2.u[1])
        self.connect(self.clock.y, self.mux2.u[2])
        self.connect(self.clock.y, self.mux3.u[1])
        self.connect(self.clock.y, self.mux3.u[2])
        self.connect(self.clock.y, self.mux3.u[3])
        self.connect(self.mux2.y, self.mux5.u[1:2])
        self.connect(self.mux3.y, self.mux5.u[3:5])
        self.connect(self.mux5.y, self.demux5.u)
        self.connect(self.demux2.y[1], self.y1)
        self.connect(self.demux2.y[2], self.y2)
        self.connect(self.demux2.u, self.demux5.y[1:2])
        self.connect(self.y3, self.demux3.y[1])
        self.connect(self.y4, self.demux3.y[2])
        self.connect(self.y5, self.demux3.y[3])
        self.connect(self.demux3.u, self.demux5.y[3:5])


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(MuxDemux())
    print(result.summary())
    for name in ("y1", "y2", "y3", "y4", "y5"):
        print(f"{name}(2) = {result.final(name)}")
