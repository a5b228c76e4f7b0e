"""Stage 6: block lower triangular (BLT) sorting.

With every equation matched to the unknown it solves, equation ``i`` depends
on equation ``k`` when it uses the unknown ``k`` solves.  The strongly
connected components of that dependency graph are the blocks (algebraic
loops where larger than one equation); in topological order they can be
solved one after the other.

The components (Tarjan's algorithm, iterative) are ordered by a topological
sort whose ties are broken by the smallest equation index: the same model
always gives the same order (the order networkx's
``lexicographical_topological_sort`` of the condensation gives, keyed so).

References
----------
.. [1] R. E. Tarjan, "Depth-first search and linear graph algorithms",
   SIAM J. Comput. 1(2), 146-160, 1972.
.. [2] I. S. Duff and J. K. Reid, "An implementation of Tarjan's algorithm
   for the block triangularization of a matrix", ACM TOMS 4(2), 137-147, 1978.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass
from typing import Sequence

__all__ = ["Block", "BLTResult", "sort_blt"]


@dataclass(frozen=True, slots=True)
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
    n = len(matching)
    solver_of = {j: i for i, j in enumerate(matching)}
    # successors: equation k -> the equations that use the unknown k solves
    successors: list[list[int]] = [[] for _ in range(n)]
    for i, unknowns in enumerate(incidence):
        for j in unknowns:
            k = solver_of[j]
            if k != i:
                successors[k].append(i)
    component = _strong_components(successors)
    members: dict[int, list[int]] = {}
    for i in range(n):
        members.setdefault(component[i], []).append(i)
    # the condensation, sorted topologically, ties broken by the smallest equation
    # (as networkx's lexicographical_topological_sort keyed by it)
    first = {c: m[0] for c, m in members.items()}  # (members are listed in increasing order)
    indegree = dict.fromkeys(members, 0)
    after: dict[int, set[int]] = {c: set() for c in members}
    for k in range(n):
        ck = component[k]
        for i in successors[k]:
            ci = component[i]
            if ci != ck and ci not in after[ck]:
                after[ck].add(ci)
                indegree[ci] += 1
    ready = [(first[c], c) for c, d in indegree.items() if d == 0]
    heapq.heapify(ready)
    blocks = []
    while ready:
        _, c = heapq.heappop(ready)
        chosen = tuple(members[c])
        blocks.append(Block(chosen, tuple(matching[i] for i in chosen)))
        for d in after[c]:
            indegree[d] -= 1
            if indegree[d] == 0:
                heapq.heappush(ready, (first[d], d))
    return BLTResult(tuple(blocks))


def _strong_components(successors: Sequence[Sequence[int]]) -> list[int]:
    """The strongly connected component of each node (Tarjan's algorithm, iterative):
    ``component[v]``, numbers that identify the components (in no promised order)."""
    n = len(successors)
    index = [-1] * n
    low = [0] * n
    on_stack = [False] * n
    component = [-1] * n
    stack: list[int] = []
    counter = 0
    found = 0
    for root in range(n):
        if index[root] != -1:
            continue
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack[root] = True
        while work:
            v, k = work[-1]
            nexts = successors[v]
            if k < len(nexts):
                work[-1] = (v, k + 1)
                w = nexts[k]
                if index[w] == -1:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack[w] = True
                    work.append((w, 0))
                elif on_stack[w] and index[w] < low[v]:
                    low[v] = index[w]
                continue
            work.pop()
            if work:
                u = work[-1][0]
                if low[v] < low[u]:
                    low[u] = low[v]
            if low[v] == index[v]:
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    component[w] = found
                    if w == v:
                        break
                found += 1
    return component
