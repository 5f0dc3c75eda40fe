"""The move reduction's metric test (tidyplan.planning.move_metric): walked edge by edge, it says
what the matrices say."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from tidyplan.planning.move_metric import _closed, _closed_dense

PLACES = "abcdefg"


@st.composite
def move_costs(draw):
    n = draw(st.integers(2, len(PLACES)))
    pairs = [(a, c) for a in PLACES[:n] for c in PLACES[:n]]
    chosen = draw(st.lists(st.sampled_from(pairs), unique=True, max_size=len(pairs)))
    # costs near each other, so the triangle inequality holds about as often as not
    return {e: draw(st.integers(0, 12)) for e in chosen}


@settings(max_examples=600, derandomize=True)
@given(move_costs())
def test_the_edge_walk_agrees_with_the_matrices(edges):
    assert _closed(edges) == _closed_dense(edges)


def test_a_complete_metric_is_closed_and_a_missing_or_dearer_direct_move_is_not():
    line = {("a", "b"): 2, ("b", "a"): 2, ("b", "c"): 3, ("c", "b"): 3, ("a", "c"): 5, ("c", "a"): 5}
    assert _closed(line) and _closed_dense(line)
    assert not _closed({**line, ("a", "c"): 7})  # 2 + 3 + 1 < 7: two moves beat one
    assert _closed({**line, ("a", "c"): 6})  # within the rounding tolerance
    del line[("a", "c")]
    assert not _closed(line)  # a→b→c with no a→c
