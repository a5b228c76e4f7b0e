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

    modelica_name = "Modelica.Blocks.Routing.Replicator"

    def equations(self):
        return [Eq(self.y, fill(self.u, self.nout))]


class IntegerReplicator(Component):
    """Integer signal replicator (Modelica.Blocks.Routing.IntegerReplicator): ``y = fill(u, nout)``."""

    modelica_name = "Modelica.Blocks.Routing.IntegerReplicator"

    nout = Parameter(1, structural=True, description="Number of outputs")
    u = IntegerInput(description="Connector of Integer input signal")
    y = IntegerOutput(shape="nout", description="Connector of Integer output signals")

    def equations(self):
        return [Eq(self.y, fill(self.u, self.nout))]


class BooleanReplicator(Component):
    """Boolean signal replicator (Modelica.Blocks.Routing.BooleanReplicator): ``y = fill(u, nout)``."""

    modelica_name = "Modelica.Blocks.Routing.BooleanReplicator"

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

    modelica_name = "Modelica.Blocks.Routing.ExtractSignal"

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

    modelica_name = "Modelica.Blocks.Routing.Extractor"

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

    modelica_name = "Modelica.Blocks.Routing.Multiplex"

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

    modelica_name = "Modelica.Blocks.Routing.DeMultiplex"

    n = Parameter(1, structural=True, min=0, description="Dimension of output signal connector")
    u = RealInput("n", description="Connector of Real input signals")
    y = RealOutput("n", description="Connector of Real output signals")

    def equations(self):
        return [Eq(self.y, self.u)]


def _total(parts: int):
    """The size ``n1 + ... + n<parts>`` of a concatenated vector (a shape read from the sizes)."""
    def size(value) -> int:
        return sum(value(f"n{i}") for i in range(1, parts + 1))

    size.text = " + ".join(f"n{i}" for i in range(1, parts + 1))  # how show writes it
    return size


class _Concatenation(Component):
    """A block with a vector that is the concatenation of ``parts`` vectors of sizes
    ``n1``, ``n2``, ... (Modelica's ``y[n1 + n2]``)."""

    #: The number of concatenated vectors (n1 ... n<parts>).
    parts: ClassVar[int] = 0

    def _parts(self, prefix: str) -> list[Array]:
        """The concatenated vectors ``prefix1``, ``prefix2``, ... of this instance."""
        return [getattr(self, f"{prefix}{i}") for i in range(1, self.parts + 1)]


class _Multiplex(_Concatenation):
    """Base of Multiplex2 ... Multiplex6: ``y = [u1; u2; ...]``."""

    def equations(self):
        return [Eq(self.y, cat(1, *self._parts("u")))]


class _DeMultiplex(_Concatenation):
    """Base of DeMultiplex2 ... DeMultiplex6: ``[u] = [y1; y2; ...]``."""

    def equations(self):
        return [Eq(cat(1, *self._parts("y")), self.u)]


_ORDINALS = {2: "two", 3: "three", 4: "four", 5: "five", 6: "six"}


def _concatenation(base: type, parts: int) -> type:
    """Multiplex<parts> or DeMultiplex<parts>, as the MSL declares it: sizes ``n1`` ...,
    vectors ``u1`` ... (or ``y1`` ...) and the whole vector ``y[n1 + ...]`` (or ``u``)."""
    mux = base is _Multiplex
    name = f"{'Multiplex' if mux else 'DeMultiplex'}{parts}"
    listed = "; ".join(f"{'u' if mux else 'y'}{i}" for i in range(1, parts + 1))
    total = " + ".join(f"n{i}" for i in range(1, parts + 1)) if parts < 4 else f"n1 + ... + n{parts}"
    doc = (f"{'Multiplexer' if mux else 'DeMultiplexer'} block for {_ORDINALS[parts]} "
           f"{'input' if mux else 'output'} connectors (Modelica.Blocks.Routing.{name}): "
           + (f"``y[{total}] = [{listed}]``." if mux else f"``[u] = [{listed}]``, ``u`` of size ``{total}``."))
    namespace: dict[str, Any] = {"__module__": __name__, "__qualname__": name, "__doc__": doc,
                                 "modelica_name": f"Modelica.Blocks.Routing.{name}", "parts": parts}
    part, whole = (RealInput, RealOutput) if mux else (RealOutput, RealInput)
    kind = "input" if mux else "output"
    for i in range(1, parts + 1):
        namespace[f"n{i}"] = Parameter(1, structural=True, min=0, description=f"Dimension of {kind} signal connector {i}")
    for i in range(1, parts + 1):
        namespace[f"{'u' if mux else 'y'}{i}"] = part(f"n{i}", description=f"Connector of Real {kind} signals {i}")
    namespace["y" if mux else "u"] = whole(_total(parts), description=f"Connector of Real "
                                                                     f"{'output' if mux else 'input'} signals")
    return type(name, (base,), namespace)


Multiplex2, Multiplex3, Multiplex4, Multiplex5, Multiplex6 = (_concatenation(_Multiplex, k) for k in range(2, 7))
DeMultiplex2, DeMultiplex3, DeMultiplex4, DeMultiplex5, DeMultiplex6 = (
    _concatenation(_DeMultiplex, k) for k in range(2, 7))


class RealPassThrough(SISO):
    """Pass a Real signal through without modification (Modelica.Blocks.Routing.RealPassThrough):
    ``y = u``."""

    modelica_name = "Modelica.Blocks.Routing.RealPassThrough"

    def equations(self):
        return [Eq(self.y, self.u)]


class IntegerPassThrough(Component):
    """Pass a Integer signal through without modification (Modelica.Blocks.Routing.IntegerPassThrough):
    ``y = u``."""

    modelica_name = "Modelica.Blocks.Routing.IntegerPassThrough"

    u = IntegerInput(description="Input signal")
    y = IntegerOutput(description="Output signal")

    def equations(self):
        return [Eq(self.y, self.u)]


class BooleanPassThrough(PartialBooleanSISO):
    """Pass a Boolean signal through without modification (Modelica.Blocks.Routing.BooleanPassThrough):
    ``y = u``."""

    modelica_name = "Modelica.Blocks.Routing.BooleanPassThrough"

    def equations(self):
        return [Eq(self.y, self.u)]
