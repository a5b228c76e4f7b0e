"""Modelica.Thermal.HeatTransfer.Examples.TwoMasses: simple conduction demo.

Two heat capacitors at 100 degC and 0 degC exchange heat through a thermal
conductor until both reach the mixing temperature ``T_final_K``, a parameter
with ``fixed=False`` computed by an initial equation (323.15 K).
"""

from acausal import Eq, Experiment, Model, Parameter
from acausal.library.thermal import CelsiusTemperatureSensor, HeatCapacitor, ThermalConductor


class TwoMasses(Model):
    """Two masses with different initial temperatures approaching one temperature."""

    modelica_class = "Modelica.Thermal.HeatTransfer.Examples.TwoMasses"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    T_final_K = Parameter(0.0, unit="K", fixed=False,
                          description="Projected final temperature (computed at initialization)")

    def build(self):
        self.mass1 = HeatCapacitor(C=15, T=dict(start=373.15, fixed=True))
        self.mass2 = HeatCapacitor(C=15, T=dict(start=273.15, fixed=True))
        self.conduction = ThermalConductor(G=10)
        self.Tsensor1 = CelsiusTemperatureSensor()
        self.Tsensor2 = CelsiusTemperatureSensor()
        self.connect(self.mass1.port, self.conduction.port_a)
        self.connect(self.conduction.port_b, self.mass2.port)
        self.connect(self.mass1.port, self.Tsensor1.port)
        self.connect(self.mass2.port, self.Tsensor2.port)

    def initial_equations(self):
        m1, m2 = self.mass1, self.mass2
        return [Eq(self.T_final_K, (m1.T * m1.C + m2.T * m2.C) / (m1.C + m2.C))]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(TwoMasses())
    print(result.summary())
    print("mass1.T(1) =", result.final("mass1.T"), " T_final_K =", result.final("T_final_K"))
