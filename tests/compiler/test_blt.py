"""Unit tests of the BLT stage (:func:`acausal.compiler.blt.sort_blt`) on small hand-made patterns.

Every expected block order is derived by hand from the incidence pattern and
the matching: equation ``i`` depends on equation ``k`` when it uses the
unknown ``k`` solves; the blocks are the strongly connected components of
that graph, in topological order with ties broken by the smallest equation
index.
"""

from __future__ import annotations

from acausal.compiler.blt import sort_blt


def test_sort_blt_chain_gives_singletons_in_dependency_order():
    """e2 solves v0 from nothing, e1 solves v1 from v0, e0 solves v2 from v1: order e2, e1, e0."""
    incidence = [[1, 2], [0, 1], [0]]
    matching = [2, 1, 0]
    blt = sort_blt(incidence, matching)
    assert [b.equations for b in blt.blocks] == [(2,), (1,), (0,)]
    assert [b.unknowns for b in blt.blocks] == [(0,), (1,), (2,)]
    assert blt.largest_block == 1


def test_sort_blt_two_cycle_is_one_block_after_its_input_and_before_its_consumer():
    """e0 (v1) and e1 (v2) need each other; they read v0 from e2 and feed e3: blocks e2 | e0,e1 | e3."""
    incidence = [[0, 1, 2], [1, 2], [0], [1, 3]]
    matching = [1, 2, 0, 3]
    blt = sort_blt(incidence, matching)
    assert [b.equations for b in blt.blocks] == [(2,), (0, 1), (3,)]
    assert blt.blocks[1].unknowns == (1, 2)
    assert blt.largest_block == 2
    assert blt.equation_order == (2, 0, 1, 3)
    assert blt.unknown_order == (0, 1, 2, 3)


def test_sort_blt_is_deterministic_and_breaks_ties_by_equation_index():
    """Independent equations come in index order, and repeated calls give the identical result."""
    incidence = [[3], [2], [1], [0, 3]]
    matching = [3, 2, 1, 0]
    first = sort_blt(incidence, matching)
    # e3 depends on e0 (v3); e1 and e2 are free: ties broken by the smallest index
    assert first.equation_order == (0, 1, 2, 3)
    for _ in range(5):
        assert sort_blt(incidence, matching) == first
