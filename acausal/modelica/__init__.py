"""Modelica text in and out.

``load(path_or_text, name=None)`` makes an acausal model class of a Modelica
model (:mod:`acausal.modelica.read`); ``dump(model)`` writes an acausal model
as Modelica text (:mod:`acausal.modelica.write`).  Expressions go both ways
through :mod:`acausal.modelica.expressions`.  The parser is pymoca's
(``pip install acausal[modelica]``).
"""

from .read import load, modelica_path, parse
from .write import dump

__all__ = ["load", "dump", "parse", "modelica_path"]
