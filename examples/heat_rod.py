"""A heat rod discretised into ``n`` cells, built with arrays of components.

The physics
-----------
A rod of length ``L`` and cross-section ``A`` (density times specific heat
``rho_c``, conductivity ``k``) starts at the temperature ``T0``; at ``t = 0``
its end at ``x = 0`` is held at ``T_hot`` and its other end is insulated.
Its temperature ``T(x, t)`` obeys the heat equation

    rho_c * dT/dt = k * d2T/dx2,   T(0, t) = T_hot,   dT/dx(L, t) = 0,

whose diffusivity ``alpha = k / rho_c`` sets the time the heat needs to
cross the rod, ``L**2 / alpha`` (the slowest mode decays with the time
constant ``4 L**2 / (pi**2 alpha)``).

The method of lines cuts the rod into ``n`` cells of length ``dx = L / n``:

* each cell is a :class:`~acausal.library.thermal.HeatCapacitor` of heat
  capacity ``C = rho_c A dx`` (``cell[1]`` ... ``cell[n]``);
* neighbouring cells are joined by ``n - 1``
  :class:`~acausal.library.thermal.ThermalConductor` elements of conductance
  ``G = k A / dx`` (``link[i]`` from ``cell[i]`` to ``cell[i+1]``);
* ``cell[1]`` is held at ``T_hot`` by a
  :class:`~acausal.library.thermal.FixedTemperature` (its start value is
  therefore not fixed); nothing is connected to ``cell[n]``: no heat leaves
  the far end.

so that ``C dT_i/dt = G (T_{i-1} - 2 T_i + T_{i+1})`` inside the rod and
``C dT_n/dt = G (T_{n-1} - T_n)`` at the insulated end: the second
difference, the heat equation's ``d2T/dx2`` to second order in ``dx``.

Energy is conserved: the heat the fixed temperature gives the rod,
``Q_in = -hot.port.Q_flow``, is the rate of change of the heat it stores,

    d/dt sum_i C_i T_i = Q_in,

which :func:`energy_balance` checks on a result (``result["cell.T"]`` reads
every cell's temperature as one ``(time, n)`` array).

The size ``n`` is a structural parameter (``HeatRod(n=100)``): the model
has about ``10 n`` equations, which makes it the bench's measure of how
translation scales with arrays (``acausal bench --only scaling``).

Run ``python examples/heat_rod.py [n]`` to simulate it and print the balance.
"""

from __future__ import annotations

import numpy as np

from acausal import Experiment, Model, Parameter
from acausal.language import ComponentArray
from acausal.library.thermal import FixedTemperature, HeatCapacitor, ThermalConductor


class HeatRod(Model):
    """An aluminium rod, 0.5 m long, heated at one end and insulated at the other, in ``n`` cells."""

    experiment = Experiment(start_time=0.0, stop_time=600.0, interval=1.0)

    n = Parameter(10, structural=True, description="Number of cells (at least 2)")
    L = Parameter(0.5, unit="m", description="Length of the rod")
    A = Parameter(1e-4, unit="m2", description="Cross-section of the rod")
    rho_c = Parameter(2.43e6, unit="J/(m3.K)", description="Density times specific heat (aluminium)")
    k = Parameter(237.0, unit="W/(m.K)", description="Thermal conductivity (aluminium)")
    T0 = Parameter(293.15, unit="K", description="Initial temperature of the rod")
    T_hot = Parameter(373.15, unit="K", description="Temperature held at the end x = 0")

    def build(self):
        n = self.n
        if not isinstance(n, int) or n < 2:
            raise ValueError(f"HeatRod needs n >= 2 cells, not {n!r}")
        dx = self.L / n
        # cell[1] follows the fixed temperature: only the others start at T0
        self.cell = [HeatCapacitor(C=self.rho_c * self.A * dx, T=dict(start=self.T0, fixed=i > 1))
                     for i in range(1, n + 1)]
        self.link = ComponentArray.of(ThermalConductor, n - 1, G=self.k * self.A / dx)
        self.hot = FixedTemperature(T=self.T_hot)
        self.connect(self.hot.port, self.cell[1].port)
        self.connect(self.link.port_a, self.cell[1:n - 1].port)  # Modelica slices: both ends included
        self.connect(self.link.port_b, self.cell[2:n].port)


def energy_balance(result) -> tuple[np.ndarray, np.ndarray]:
    """The heat stored in the rod since the start and the heat that came in, along ``result``.

    Parameters
    ----------
    result : SimulationResult
        A run of :class:`HeatRod`.

    Returns
    -------
    stored, came_in : ndarray
        ``sum_i C_i (T_i(t) - T_i(0))`` and the trapezoid integral of
        ``Q_in = -hot.port.Q_flow`` from the start, in J, at every output
        time; they agree to the integrator's and the trapezoid rule's error.
    """
    from scipy.integrate import cumulative_trapezoid

    temperatures = result["cell.T"]                    # (time, n)
    capacities = result["cell.C"][0]                   # (n,)
    stored = (temperatures - temperatures[0]) @ capacities
    came_in = cumulative_trapezoid(-result["hot.port.Q_flow"], result.time, initial=0.0)
    return stored, came_in


def power_balance(result) -> tuple[np.ndarray, np.ndarray]:
    """The rate at which the rod stores heat, ``sum_i C_i der(T_i)``, and the heat flow into it,
    ``Q_in``, at every output point of ``result`` (W); equal up to rounding."""
    storing = result["cell.der_T"] @ result["cell.C"][0]
    return storing, -result["hot.port.Q_flow"]


def scaling_case():
    """The rod as the array case of ``acausal bench``'s scaling section
    (:class:`acausal.tools.bench.ArrayScalingCase`): ``HeatRod(n=N)`` translated for
    growing N, then run for 1 s, its heat balance checked (:func:`energy_balance`,
    :func:`power_balance`)."""
    from acausal.tools.bench import ArrayScalingCase

    def balance(result) -> tuple[np.ndarray, np.ndarray, float]:
        stored, came_in = energy_balance(result)
        storing, flowing_in = power_balance(result)
        return stored, came_in, float(np.max(np.abs(storing - flowing_in)) / np.max(np.abs(flowing_in)))

    return ArrayScalingCase(
        name="HeatRod", make=lambda n: HeatRod(n=n), size_label="cells", quantity="heat", unit="J",
        balance=balance, stop_time=1.0,
        description="`HeatRod(n=N)` of `examples/heat_rod.py`: N HeatCapacitors (`self.cell = [...]`) "
                    "joined by N-1 ThermalConductors (`ComponentArray.of`), connected with array slices, "
                    "the first cell held at a fixed temperature, the last insulated; about 10 N equations.")


if __name__ == "__main__":
    import sys

    from acausal import simulate

    size = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    result = simulate(HeatRod(n=size), rtol=1e-8)
    print(result.summary(values=False))
    stored, came_in = energy_balance(result)
    print(f"heat stored {stored[-1]:.6g} J, heat in {came_in[-1]:.6g} J "
          f"(difference {abs(stored[-1] - came_in[-1]) / came_in[-1]:.1e} of the heat in)")
    final = result.at(result.time[-1], "cell.T")
    print("final temperatures [K]:", np.array2string(final, precision=2, max_line_width=100))
