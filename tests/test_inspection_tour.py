"""The tour the robot looks into the deposits on before a mission ends (tidyplan.loop.looking):
the shortest it finds from where it stands, by the map's path lengths, not the scenario's order."""

from __future__ import annotations

import itertools
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from tidyplan.belief.mapfacts import MapFacts, deposit_waypoint
from tidyplan.loop.looking import NO_WAY, inspection_tour


def _facts(at: dict[str, tuple[float, float]], blocked: frozenset = frozenset()) -> MapFacts:
    """Every pair of waypoints joined by a straight path, but the ``blocked`` pairs."""
    facts = MapFacts(points=dict(at))
    for a, b in itertools.permutations(at, 2):
        if (a, b) not in blocked:
            facts.path[(a, b)] = math.dist(at[a], at[b])
    return facts


def _length(facts: MapFacts, start: str, order: list[str]) -> float:
    stops = [start] + [deposit_waypoint(d) for d in order]
    total = 0.0
    for a, b in zip(stops[:-1], stops[1:], strict=True):
        d = 0.0 if a == b else facts.distance(a, b)
        total += NO_WAY if d is None else d
    return total


def test_from_the_middle_of_a_row_of_deposits_the_near_end_first_then_the_far_one():
    """Task 1's deposits stand in a row along the wall: from container B near one end, up to
    the drawers and then down to the bins (wrs-task1-s000: 6.4 m in the scenario's order)."""
    ys = {"bin-a": -1.7, "bin-b": -1.2, "tray-a": -0.75, "tray-b": -0.45, "container-a": -0.2}
    ys |= {"container-b": 0.1, "drawer-left": 0.67, "drawer-bottom": 1.0, "drawer-top": 1.0}
    at = {deposit_waypoint(d): (-2.2, y) for d, y in ys.items()}
    facts = _facts(at)
    order = inspection_tour(facts, deposit_waypoint("container-b"), sorted(ys))
    assert order[0] == "container-b"  # where it stands: no drive
    assert set(order[1:4]) == {"drawer-left", "drawer-bottom", "drawer-top"}
    assert order[-1] == "bin-a"
    assert math.isclose(_length(facts, deposit_waypoint("container-b"), order), 0.9 + 2.7)
    assert _length(facts, deposit_waypoint("container-b"), sorted(ys)) > 6.0


def test_a_leg_the_map_has_no_path_for_comes_last_if_at_all():
    at = {"wp-robot": (0.0, 0.0), "wp-a": (1.0, 0.0), "wp-b": (2.0, 0.0), "wp-c": (3.0, 0.0)}
    # a to b is blocked (an item in the way): the tour goes round by the other legs
    facts = _facts(at, frozenset({("wp-a", "wp-b"), ("wp-b", "wp-a")}))
    order = inspection_tour(facts, "wp-robot", ["a", "b", "c"])
    assert _length(facts, "wp-robot", order) < NO_WAY
    assert order == ["a", "c", "b"]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)), min_size=1, max_size=13, unique=True),
    st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)),
)
def test_the_tour_visits_each_deposit_once_and_is_the_shortest_where_that_is_cheap(places, start):
    names = [f"d{k}" for k in range(len(places))]
    at = {deposit_waypoint(n): xy for n, xy in zip(names, places, strict=True)} | {"wp-robot": start}
    facts = _facts(at)
    order = inspection_tour(facts, "wp-robot", names)
    assert sorted(order) == sorted(names)
    length = _length(facts, "wp-robot", order)
    assert length <= _length(facts, "wp-robot", names) + 1e-9  # never worse than the given order
    if len(names) <= 7:  # exact there (up to EXACT_TOUR): the shortest of every order
        best = min(_length(facts, "wp-robot", list(p)) for p in itertools.permutations(names))
        assert math.isclose(length, best, rel_tol=1e-9, abs_tol=1e-9)
