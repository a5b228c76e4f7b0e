"""ModelicaTest.Blocks.ConversionBlocks: every unit conversion there and back.

A cosine ``10 + 10*cos(4*pi*t)`` drives the 13 ``To_<unit>`` blocks of
Modelica.Blocks.Math.UnitConversions (from the SI unit), each followed by its
``From_<unit>`` (back to the SI unit); the model's outputs ``ydegC`` ...
``ygps`` are the round trips, so each equals the cosine.

Run ``acausal compare examples/blocks_conversion.py`` to check it against the
MSL reference results.
"""

from acausal import Eq, Experiment, Model, RealOutput
from acausal.library.blocks import Cosine
from acausal.library.blocks import unit_conversions

#: The units converted, in the order of the MSL model.
UNITS = ("degC", "degF", "degRk", "deg", "rpm", "kmh", "day", "hour", "minute", "litre", "kWh", "bar", "gps")


class ConversionBlocks(Model):
    """ModelicaTest.Blocks.ConversionBlocks."""

    modelica_class = "ModelicaTest.Blocks.ConversionBlocks"
    experiment = Experiment(start_time=0.0, stop_time=1.1, interval=1.1 / 5000)

    ydegC = RealOutput()  # noqa: N815 - the MSL model's names
    ydegF = RealOutput()  # noqa: N815
    ydegRk = RealOutput()  # noqa: N815
    ydeg = RealOutput()
    yrpm = RealOutput()
    ykmh = RealOutput()
    yday = RealOutput()
    yhour = RealOutput()
    yminute = RealOutput()
    ylitre = RealOutput()
    ykWh = RealOutput()  # noqa: N815
    ybar = RealOutput()
    ygps = RealOutput()

    def build(self):
        self.cosine = Cosine(f=2, amplitude=10, offset=10)
        for unit in UNITS:
            to_block = getattr(unit_conversions, f"To_{unit}")()
            from_block = getattr(unit_conversions, f"From_{unit}")()
            setattr(self, f"to_{unit}", to_block)
            setattr(self, f"from_{unit}", from_block)
            self.connect(self.cosine.y, to_block.u)
            self.connect(to_block.y, from_block.u)

    def equations(self):
        return [Eq(getattr(self, f"y{unit}"), getattr(self, f"from_{unit}").y) for unit in UNITS]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(ConversionBlocks())
    print(result.summary())
