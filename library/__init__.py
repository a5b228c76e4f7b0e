"""Component libraries reproducing parts of the Modelica Standard Library.

* :mod:`library.rotational`: Modelica.Mechanics.Rotational
* :mod:`library.thermal`: Modelica.Thermal.HeatTransfer
* :mod:`library.blocks`: Modelica.Blocks (sources and math)

The connectors and partial models they share live in :mod:`components`.
"""
