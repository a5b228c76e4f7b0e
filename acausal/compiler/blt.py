"""Stage 6: block lower triangular (BLT) sorting.

With every equation matched to the unknown it solves, equation ``i`` depends
on equation ``k`` when it uses the unknown ``k`` solves.  The strongly
connected components of that dependency graph are the blocks (algebraic
loops where larger than one equation); in topological order they can be
solved one after the other.

networkx's ``strongly_connected_components`` promises no order, so the
components are taken from ``nx.condensation`` and ordered by a topological
sort whose ties are broken by the smallest equation index: the same model
always gives the same order.

References
----------
.. [1] R. E. Tarjan, "Depth-first search and linear graph algorithms",
   SIAM J. Comput. 1(2), 146-160, 1972.
.. [2] I. S. Duff and J. K. Reid, "An implementation of Tarjan's algorithm
   for the block triangularization of a matrix", ACM TOMS 4(2), 137-147, 1978.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import networkx as nx

__all__ = ["Block", "BLTResult", "sort_blt"]


@dataclass(frozen=True)
class Block:
    """Equations solved together and the unknowns they solve (matched pairwise)."""

    equations: tuple[int, ...]
    unknowns: tuple[int, ...]

    @property
    def size(self) -> int:
        return len(self.equations)


@dataclass(frozen=True)
class BLTResult:
    """Blocks in the order they are solved."""

    blocks: tuple[Block, ...]

    @property
    def equation_order(self) -> tuple[int, ...]:
        return tuple(i for b in self.blocks for i in b.equations)

    @property
    def unknown_order(self) -> tuple[int, ...]:
        return tuple(j for b in self.blocks for j in b.unknowns)

    @property
    def largest_block(self) -> int:
        return max((b.size for b in self.blocks), default=0)


def sort_blt(incidence: Sequence[Sequence[int]], matching: Sequence[int]) -> BLTResult:
    """Sort matched equations into blocks.

    Parameters
    ----------
    incidence : sequence of sequence of int
        Unknowns occurring in each equation.
    matching : sequence of int
        ``matching[i]`` = unknown solved by equation ``i``.
    """
    solver_of = {j: i for i, j in enumerate(matching)}
    graph = nx.DiGraph()
    graph.add_nodes_from(range(len(matching)))
    for i, unknowns in enumerate(incidence):
        for j in unknowns:
            k = solver_of[j]
            if k != i:
                graph.add_edge(k, i)
    condensed = nx.condensation(graph)
    blocks = []
    for component in nx.lexicographical_topological_sort(
            condensed, key=lambda c: min(condensed.nodes[c]["members"])):
        members = tuple(sorted(condensed.nodes[component]["members"]))
        blocks.append(Block(members, tuple(matching[i] for i in members)))
    return BLTResult(tuple(blocks))
