"""Blocks to combine and extract signals (Modelica.Blocks.Routing), as in MSL 4.1.0.

The multiplexers join vectors of signals into one (``y = [u1; u2; ...]``),
the demultiplexers split one up (``[u] = [y1; y2; ...]``); the generic
:class:`Multiplex` and :class:`DeMultiplex` pass a vector of ``n`` signals
through.  :class:`Replicator` copies a signal to a vector, :class:`ExtractSignal`
picks elements of a vector by a fixed index vector and :class:`Extractor` one
element by an Integer input.  The pass-through blocks rename a signal.

Every size is a structural Integer parameter, given where the block is made
(``Multiplex2(n1=2, n2=3)``): acausal has no ``connectorSizing``, so the
generic blocks (``Multiplex(n=5)``) need their size too (their default is
1, not the MSL's 0, which only a connection enlarges).  The elements are
named as in Modelica (``mux.y[2]``); a vector connector connects element by
element (``self.connect(mux.y, demux.u)``, ``self.connect(mux2.y, mux5.u[1:2])``).

A concatenating block declares one more structural parameter than the MSL's,
``n``: the size of its concatenated vector (``n1 + n2 + ...``), set from the
parts (acausal's array sizes name a parameter, not an expression of them).
"""

from __future__ import annotations

from typing import Any, ClassVar

import sympy as sp

from acausal.arrays import Array, cat, fill
from acausal.components.blocks import (MIMO, MISO, SIMO, SISO, BooleanInput, BooleanOutput, IntegerInput,
                                       IntegerOutput, PartialBooleanSISO)
from acausal.errors import ArraySizeError, ModifierError
from acausal.hybrid import Assert
from acausal.language import Component, Eq, Parameter, RealInput, RealOutput

__all__ = ["Replicator", "IntegerReplicator", "BooleanReplicator", "ExtractSignal", "Extractor",
           "Multiplex", "Multiplex2", "Multiplex3", "Multiplex4", "Multiplex5", "Multiplex6",
           "DeMultiplex", "DeMultiplex2", "DeMultiplex3", "DeMultiplex4", "DeMultiplex5", "DeMultiplex6",
           "RealPassThrough", "IntegerPassThrough", "BooleanPassThrough"]


# -- replicators ----------------------------------------------------------------------------


class Replicator(SIMO):
    """Signal replicator (Modelica.Blocks.Routing.Replicator): ``y = fill(u, nout)``."""

    def equations(self):
        return [Eq(self.y, fill(self.u, self.nout))]


class IntegerReplicator(Component):
    """Integer signal replicator (Modelica.Blocks.Routing.IntegerReplicator): ``y = fill(u, nout)``."""

    nout = Parameter(1, structural=True, description="Number of outputs")
    u = IntegerInput(description="Connector of Integer input signal")
    y = IntegerOutput(shape="nout", description="Connector of Integer output signals")

    def equations(self):
        return [Eq(self.y, fill(self.u, self.nout))]


class BooleanReplicator(Component):
    """Boolean signal replicator (Modelica.Blocks.Routing.BooleanReplicator): ``y = fill(u, nout)``."""

    nout = Parameter(1, structural=True, description="Number of outputs")
    u = BooleanInput(description="Connector of Boolean input signal")
    y = BooleanOutput(shape="nout", description="Connector of Boolean output signals")

    def equations(self):
        return [Eq(self.y, fill(self.u, self.nout))]


# -- extracting -----------------------------------------------------------------------------


class ExtractSignal(MIMO):
    """Extract signals from an input signal vector (Modelica.Blocks.Routing.ExtractSignal):
    ``y[i] = u[extract[i]]``.

    ``extract`` lists, for each of the ``nout`` outputs, the input it takes
    (``nin=7, nout=4, extract=[6, 3, 3, 2]``); None (the default) is the
    MSL's ``1:nout``.  It is structural: it selects the equations.
    """

    extract = Parameter(None, structural=True, description="Extracting vector (default 1:nout)")

    def equations(self):
        chosen = list(range(1, self.nout + 1)) if self.extract is None else [int(i) for i in self.extract]
        if len(chosen) != self.nout:
            raise ArraySizeError(f"{self.path or type(self).__name__}.extract has size [{len(chosen)}], "
                                 f"the output y has size [{self.nout}]",
                                 hint="give one input index per output (extract[nout])")
        return [Eq(self.y[i], self.u[k]) for i, k in enumerate(chosen, start=1)]


class Extractor(MISO):
    """Extract scalar signal out of signal vector dependent on IntegerRealInput index
    (Modelica.Blocks.Routing.Extractor): ``y = u[index]``.

    ``index`` is an Integer input.  Outside ``1..nin`` the output is
    ``outOfRangeValue`` when ``allowOutOfRange`` is True; otherwise the
    simulation stops with an assertion error (the output is 0 there, as
    the MSL's ``k*u`` with ``k`` all zeros).  The output is a chain of
    ``if index == i`` on the discrete index, so it changes at the events
    where the index does (the MSL's ``when change(index)``).
    """

    allowOutOfRange = Parameter(False, structural=True,  # noqa: N815 - Modelica's name
                                description="= true, if index may be out of range")
    outOfRangeValue = Parameter(1e10, description="Output signal if index is out of range")  # noqa: N815
    index = IntegerInput(description="Index of the element of u that is the output")

    def equations(self):
        u = self.u
        otherwise = self.outOfRangeValue if self.allowOutOfRange else sp.Integer(0)
        picked = sp.Piecewise(*[(u[i], sp.Eq(self.index, i)) for i in range(1, self.nin + 1)],
                              (otherwise, True))
        equations: list = [Eq(self.y, picked)]
        if not self.allowOutOfRange:
            equations.append(Assert(sp.And(self.index >= 1, self.index <= self.nin),
                                    f"The input index of {self.path or type(self).__name__} is out of "
                                    f"range 1..{self.nin}."))
        return equations


# -- multiplexing ---------------------------------------------------------------------------


class Multiplex(Component):
    """Multiplexer block for arbitrary number of input connectors (Modelica.Blocks.Routing.Multiplex):
    ``y = u``, both of size ``n``.

    The MSL sizes ``u`` by connecting to it (``connectorSizing``, from a
    default of 0); acausal needs ``n`` given (``Multiplex(n=5)``), and its
    default is 1.
    """

    n = Parameter(1, structural=True, min=0, description="Dimension of input signal connector")
    u = RealInput("n", description="Connector of Real input signals")
    y = RealOutput("n", description="Connector of Real output signals")

    def equations(self):
        return [Eq(self.y, self.u)]


class DeMultiplex(Component):
    """DeMultiplexer block for arbitrary number of output connectors
    (Modelica.Blocks.Routing.DeMultiplex): ``y = u``, both of size ``n``.

    The MSL sizes ``y`` by connecting to it (``connectorSizing``, from a
    default of 0); acausal needs ``n`` given (``DeMultiplex(n=5)``), and its
    default is 1.
    """

    n = Parameter(1, structural=True, min=0, description="Dimension of output signal connector")
    u = RealInput("n", description="Connector of Real input signals")
    y = RealOutput("n", description="Connector of Real output signals")

    def equations(self):
        return [Eq(self.y, self.u)]


class _Concatenation(Component):
    """A block with a vector that is the concatenation of ``parts`` vectors of sizes
    ``n1``, ``n2``, ...: its size ``n`` is a structural parameter set from them.

    ``n`` is completed in the modifiers before the instance is sized
    (:meth:`Component.__new__`) and applied; given with a value other than
    ``n1 + n2 + ...`` it is an error.
    """

    #: The number of concatenated vectors (n1 ... n<parts>).
    parts: ClassVar[int] = 0

    def __new__(cls, *args: Any, **modifiers: Any):
        return super().__new__(cls, *args, **cls._with_size(modifiers))

    def __init__(self, **modifiers: Any) -> None:
        super().__init__(**type(self)._with_size(modifiers))

    @classmethod
    def _part_names(cls) -> list[str]:
        return [f"n{i}" for i in range(1, cls.parts + 1)]

    @classmethod
    def _with_size(cls, modifiers: dict[str, Any]) -> dict[str, Any]:
        """``modifiers`` with ``n = n1 + n2 + ...`` (from the modifiers or the defaults)."""
        declarations = cls.declarations()
        sizes = [modifiers.get(name, declarations[name].default) for name in cls._part_names()]
        for name, size in zip(cls._part_names(), sizes):
            if isinstance(size, bool) or not isinstance(size, int) or size < 0:
                raise ModifierError(f"{cls.__name__}.{name} = {size!r}: a vector size is an integer >= 0")
        total = sum(sizes)
        if "n" in modifiers and modifiers["n"] != total:
            raise ArraySizeError(f"{cls.__name__}: n = {modifiers['n']!r}, but the parts have sizes "
                                 f"{' + '.join(map(str, sizes))} = {total}",
                                 hint="n is set from n1, n2, ...; leave it out")
        return {**modifiers, "n": total}

    def _parts(self, prefix: str) -> list[Array]:
        """The concatenated vectors ``prefix1``, ``prefix2``, ... of this instance."""
        return [getattr(self, f"{prefix}{i}") for i in range(1, self.parts + 1)]


def _size(part: int, of: str) -> Parameter:
    """The structural size ``n<part>`` of the ``of`` ("input" or "output") vector number ``part``."""
    return Parameter(1, structural=True, min=0, description=f"Dimension of {of} signal connector {part}")


class _Multiplex(_Concatenation):
    """Base of Multiplex2 ... Multiplex6: ``y = [u1; u2; ...]``."""

    y = RealOutput("n", description="Connector of Real output signals")

    def equations(self):
        return [Eq(self.y, cat(1, *self._parts("u")))]


class _DeMultiplex(_Concatenation):
    """Base of DeMultiplex2 ... DeMultiplex6: ``[u] = [y1; y2; ...]``."""

    u = RealInput("n", description="Connector of Real input signals")

    def equations(self):
        return [Eq(cat(1, *self._parts("y")), self.u)]


class Multiplex2(_Multiplex):
    """Multiplexer block for two input connectors (Modelica.Blocks.Routing.Multiplex2):
    ``y[n1 + n2] = [u1; u2]``."""

    parts = 2
    n = Parameter(2, structural=True, description="Dimension of y, n1 + n2 (set from them)")
    n1 = _size(1, "input")
    n2 = _size(2, "input")
    u1 = RealInput("n1", description="Connector of Real input signals 1")
    u2 = RealInput("n2", description="Connector of Real input signals 2")


class Multiplex3(_Multiplex):
    """Multiplexer block for three input connectors (Modelica.Blocks.Routing.Multiplex3):
    ``y[n1 + n2 + n3] = [u1; u2; u3]``."""

    parts = 3
    n = Parameter(3, structural=True, description="Dimension of y, n1 + n2 + n3 (set from them)")
    n1 = _size(1, "input")
    n2 = _size(2, "input")
    n3 = _size(3, "input")
    u1 = RealInput("n1", description="Connector of Real input signals 1")
    u2 = RealInput("n2", description="Connector of Real input signals 2")
    u3 = RealInput("n3", description="Connector of Real input signals 3")


class Multiplex4(_Multiplex):
    """Multiplexer block for four input connectors (Modelica.Blocks.Routing.Multiplex4):
    ``y[n1 + ... + n4] = [u1; u2; u3; u4]``."""

    parts = 4
    n = Parameter(4, structural=True, description="Dimension of y, n1 + ... + n4 (set from them)")
    n1 = _size(1, "input")
    n2 = _size(2, "input")
    n3 = _size(3, "input")
    n4 = _size(4, "input")
    u1 = RealInput("n1", description="Connector of Real input signals 1")
    u2 = RealInput("n2", description="Connector of Real input signals 2")
    u3 = RealInput("n3", description="Connector of Real input signals 3")
    u4 = RealInput("n4", description="Connector of Real input signals 4")


class Multiplex5(_Multiplex):
    """Multiplexer block for five input connectors (Modelica.Blocks.Routing.Multiplex5):
    ``y[n1 + ... + n5] = [u1; u2; u3; u4; u5]``."""

    parts = 5
    n = Parameter(5, structural=True, description="Dimension of y, n1 + ... + n5 (set from them)")
    n1 = _size(1, "input")
    n2 = _size(2, "input")
    n3 = _size(3, "input")
    n4 = _size(4, "input")
    n5 = _size(5, "input")
    u1 = RealInput("n1", description="Connector of Real input signals 1")
    u2 = RealInput("n2", description="Connector of Real input signals 2")
    u3 = RealInput("n3", description="Connector of Real input signals 3")
    u4 = RealInput("n4", description="Connector of Real input signals 4")
    u5 = RealInput("n5", description="Connector of Real input signals 5")


class Multiplex6(_Multiplex):
    """Multiplexer block for six input connectors (Modelica.Blocks.Routing.Multiplex6):
    ``y[n1 + ... + n6] = [u1; u2; u3; u4; u5; u6]``."""

    parts = 6
    n = Parameter(6, structural=True, description="Dimension of y, n1 + ... + n6 (set from them)")
    n1 = _size(1, "input")
    n2 = _size(2, "input")
    n3 = _size(3, "input")
    n4 = _size(4, "input")
    n5 = _size(5, "input")
    n6 = _size(6, "input")
    u1 = RealInput("n1", description="Connector of Real input signals 1")
    u2 = RealInput("n2", description="Connector of Real input signals 2")
    u3 = RealInput("n3", description="Connector of Real input signals 3")
    u4 = RealInput("n4", description="Connector of Real input signals 4")
    u5 = RealInput("n5", description="Connector of Real input signals 5")
    u6 = RealInput("n6", description="Connector of Real input signals 6")


class DeMultiplex2(_DeMultiplex):
    """DeMultiplexer block for two output connectors (Modelica.Blocks.Routing.DeMultiplex2):
    ``[u] = [y1; y2]``, ``u`` of size ``n1 + n2``."""

    parts = 2
    n = Parameter(2, structural=True, description="Dimension of u, n1 + n2 (set from them)")
    n1 = _size(1, "output")
    n2 = _size(2, "output")
    y1 = RealOutput("n1", description="Connector of Real output signals 1")
    y2 = RealOutput("n2", description="Connector of Real output signals 2")


class DeMultiplex3(_DeMultiplex):
    """DeMultiplexer block for three output connectors (Modelica.Blocks.Routing.DeMultiplex3):
    ``[u] = [y1; y2; y3]``, ``u`` of size ``n1 + n2 + n3``."""

    parts = 3
    n = Parameter(3, structural=True, description="Dimension of u, n1 + n2 + n3 (set from them)")
    n1 = _size(1, "output")
    n2 = _size(2, "output")
    n3 = _size(3, "output")
    y1 = RealOutput("n1", description="Connector of Real output signals 1")
    y2 = RealOutput("n2", description="Connector of Real output signals 2")
    y3 = RealOutput("n3", description="Connector of Real output signals 3")


class DeMultiplex4(_DeMultiplex):
    """DeMultiplexer block for four output connectors (Modelica.Blocks.Routing.DeMultiplex4):
    ``[u] = [y1; y2; y3; y4]``, ``u`` of size ``n1 + ... + n4``."""

    parts = 4
    n = Parameter(4, structural=True, description="Dimension of u, n1 + ... + n4 (set from them)")
    n1 = _size(1, "output")
    n2 = _size(2, "output")
    n3 = _size(3, "output")
    n4 = _size(4, "output")
    y1 = RealOutput("n1", description="Connector of Real output signals 1")
    y2 = RealOutput("n2", description="Connector of Real output signals 2")
    y3 = RealOutput("n3", description="Connector of Real output signals 3")
    y4 = RealOutput("n4", description="Connector of Real output signals 4")


class DeMultiplex5(_DeMultiplex):
    """DeMultiplexer block for five output connectors (Modelica.Blocks.Routing.DeMultiplex5):
    ``[u] = [y1; y2; y3; y4; y5]``, ``u`` of size ``n1 + ... + n5``."""

    parts = 5
    n = Parameter(5, structural=True, description="Dimension of u, n1 + ... + n5 (set from them)")
    n1 = _size(1, "output")
    n2 = _size(2, "output")
    n3 = _size(3, "output")
    n4 = _size(4, "output")
    n5 = _size(5, "output")
    y1 = RealOutput("n1", description="Connector of Real output signals 1")
    y2 = RealOutput("n2", description="Connector of Real output signals 2")
    y3 = RealOutput("n3", description="Connector of Real output signals 3")
    y4 = RealOutput("n4", description="Connector of Real output signals 4")
    y5 = RealOutput("n5", description="Connector of Real output signals 5")


class DeMultiplex6(_DeMultiplex):
    """DeMultiplexer block for six output connectors (Modelica.Blocks.Routing.DeMultiplex6):
    ``[u] = [y1; y2; y3; y4; y5; y6]``, ``u`` of size ``n1 + ... + n6``."""

    parts = 6
    n = Parameter(6, structural=True, description="Dimension of u, n1 + ... + n6 (set from them)")
    n1 = _size(1, "output")
    n2 = _size(2, "output")
    n3 = _size(3, "output")
    n4 = _size(4, "output")
    n5 = _size(5, "output")
    n6 = _size(6, "output")
    y1 = RealOutput("n1", description="Connector of Real output signals 1")
    y2 = RealOutput("n2", description="Connector of Real output signals 2")
    y3 = RealOutput("n3", description="Connector of Real output signals 3")
    y4 = RealOutput("n4", description="Connector of Real output signals 4")
    y5 = RealOutput("n5", description="Connector of Real output signals 5")
    y6 = RealOutput("n6", description="Connector of Real output signals 6")


# -- pass-through ---------------------------------------------------------------------------


class RealPassThrough(SISO):
    """Pass a Real signal through without modification (Modelica.Blocks.Routing.RealPassThrough):
    ``y = u``."""

    def equations(self):
        return [Eq(self.y, self.u)]


class IntegerPassThrough(Component):
    """Pass a Integer signal through without modification (Modelica.Blocks.Routing.IntegerPassThrough):
    ``y = u``."""

    u = IntegerInput(description="Input signal")
    y = IntegerOutput(description="Output signal")

    def equations(self):
        return [Eq(self.y, self.u)]


class BooleanPassThrough(PartialBooleanSISO):
    """Pass a Boolean signal through without modification (Modelica.Blocks.Routing.BooleanPassThrough):
    ``y = u``."""

    def equations(self):
        return [Eq(self.y, self.u)]
