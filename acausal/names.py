"""The names of the symbols flattening introduces, in one place.

After flattening every unknown of a model is a plain sympy symbol named by
its dotted Modelica path (``clutch1.w_rel``).  Four more kinds of symbol
stand for things that are not plain variables; their names follow Modelica's
notation, so that equations, messages and generated-code comments read as a
Modelica user writes them:

========================  ====================  =================================
kind                      name                  what it stands for
========================  ====================  =================================
derivative (order n)      ``der(der(x))``       the n-th time derivative of ``x``
pre value                 ``pre(x)``            a discrete variable before the event
relation indicator        ``$rel3``             the value of relation 3 (partition)
sample clock              ``$sample2``          true at the ticks of clock 2 (partition)
initial()                 ``initial()``         true while initializing
terminal()                ``terminal()``        true at the end of a successful run
========================  ====================  =================================

The engine's own variables (a when-condition, a value held between
events) are plain variables named ``<component>.$when4``, ``$floor5``.

Every stage asks this module what a name is (:func:`parse`) and builds names
with it (:func:`der_name`, :func:`pre_name`, :func:`relation_name`), instead
of slicing strings itself.  The names are part of the generated code's
identifiers and of the determinism guarantee, so they are never changed
here without changing every stage's expectations.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

__all__ = [
    "INITIAL_NAME",
    "TERMINAL_NAME",
    "sample_name",
    "Name",
    "parse",
    "der_name",
    "pre_name",
    "relation_name",
    "base_name",
    "derivative_order",
    "is_derivative",
    "is_relation",
]

#: The name of the symbol ``initial()`` becomes after flattening.
INITIAL_NAME = "initial()"

#: The name of the symbol ``terminal()`` becomes after flattening.
TERMINAL_NAME = "terminal()"

_DER, _PRE, _REL, _SAMPLE = "der(", "pre(", "$rel", "$sample"

Kind = Literal["variable", "derivative", "pre", "relation", "sample", "initial", "terminal"]


@dataclass(frozen=True)
class Name:
    """What a flat symbol's name denotes.

    Attributes
    ----------
    text : str
        The name itself.
    kind : {'variable', 'derivative', 'pre', 'relation', 'sample', 'initial', 'terminal'}
    base : str
        The variable it is about: ``x`` for ``der(der(x))`` and ``pre(x)``;
        the name itself for a variable, a relation indicator and ``initial()``.
    order : int
        How often ``base`` is differentiated (0 unless a derivative).
    index : int
        The number of a relation indicator or a sample clock, else -1.
    """

    text: str
    kind: Kind
    base: str
    order: int = 0
    index: int = -1

    @property
    def lower(self) -> str:
        """The name differentiated once less: ``der(x)`` for ``der(der(x))``."""
        if self.kind != "derivative":
            raise ValueError(f"{self.text} is not a derivative")
        return self.text[len(_DER):-1]


@lru_cache(maxsize=65536)
def parse(name: str) -> Name:
    """What ``name`` denotes (see the table in the module docstring)."""
    if name == INITIAL_NAME:
        return Name(name, "initial", name)
    if name == TERMINAL_NAME:
        return Name(name, "terminal", name)
    if name.startswith(_REL) and name[len(_REL):].isdigit():
        return Name(name, "relation", name, index=int(name[len(_REL):]))
    if name.startswith(_SAMPLE) and name[len(_SAMPLE):].isdigit():
        return Name(name, "sample", name, index=int(name[len(_SAMPLE):]))
    if name.startswith(_PRE) and name.endswith(")"):
        return Name(name, "pre", name[len(_PRE):-1])
    base, order = name, 0
    while base.startswith(_DER) and base.endswith(")"):
        base, order = base[len(_DER):-1], order + 1
    return Name(name, "derivative" if order else "variable", base, order)


def der_name(name: str, order: int = 1) -> str:
    """The name of the ``order``-th derivative of ``name``: ``der(x)``."""
    for _ in range(order):
        name = f"{_DER}{name})"
    return name


def pre_name(name: str) -> str:
    """The name of the value of ``name`` before an event: ``pre(x)``."""
    return f"{_PRE}{name})"


def relation_name(index: int) -> str:
    """The name of relation ``index``'s indicator: ``$rel3``."""
    return f"{_REL}{index}"


def sample_name(index: int) -> str:
    """The name of sample clock ``index``'s value: ``$sample2``."""
    return f"{_SAMPLE}{index}"


def base_name(name: str) -> str:
    """The undifferentiated variable: ``der(der(x))`` -> ``x``."""
    return parse(name).base if parse(name).kind in ("variable", "derivative") else name


def derivative_order(name: str) -> int:
    """How many times ``name`` is differentiated: ``der(der(x))`` -> 2."""
    return parse(name).order


def is_derivative(name: str) -> bool:
    """Whether ``name`` is a time derivative."""
    return parse(name).kind == "derivative"


def is_relation(name: str) -> bool:
    """Whether ``name`` is a relation indicator."""
    return parse(name).kind == "relation"
