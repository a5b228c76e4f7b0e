"""Component libraries reproducing parts of the Modelica Standard Library.

* :mod:`acausal.library.rotational`: Modelica.Mechanics.Rotational
* :mod:`acausal.library.thermal`: Modelica.Thermal.HeatTransfer
* :mod:`acausal.library.translational`: Modelica.Mechanics.Translational
* :mod:`acausal.library.blocks`: Modelica.Blocks
* :mod:`acausal.library.electrical`: Modelica.Electrical.Analog (basic, sources, sensors)

The connectors and partial models they share live in :mod:`components`.
"""
