"""The belief's association of detections with believed items (tidyplan.belief.state)."""

from __future__ import annotations

from sim.scenario.read import loads
from tests.test_loop import ROOM
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.percepts import Detection
from tidyplan.belief.state import Belief

# The test room of tests/test_loop.py with a second category and its deposit.
BOOKS = """
[prior]
count = { toy = 1, book = 1 }
[[deposit]]
name = "tray"
category = "book"
position = [0.2, 1.85, 0.9]
approach = [0.75, 1.85]
"""


def _belief_with_a_puzzle() -> tuple[Belief, str]:
    scenario = loads(ROOM.format(name="two-kinds") + BOOKS, "two-kinds.toml")
    belief = Belief(scenario, RoomMap(scenario))
    name = belief.observe([Detection("toy", 1.5, 1.5, "floor", 0.08, 0.08, 0.06)], None).new[0]
    return belief, name


def test_a_detection_lying_on_a_believed_item_is_that_item_seen_again_not_a_new_one():
    # A false detection 2.5 cm from a toy, as another category: two solid objects cannot lie
    # there. Added, it was a "book" the planner had to tidy, and each one's grasp poses came to
    # need the other gone: no plan for either (case I, seed 11, before this rule).
    belief, toy = _belief_with_a_puzzle()
    update = belief.observe([Detection("book", 1.504, 1.476, "floor")], None)
    assert update.new == [] and update.overlapping == [toy]
    assert sorted(belief.items) == [toy]


def test_a_detection_beside_a_believed_item_or_above_it_is_a_new_item():
    belief, _ = _belief_with_a_puzzle()
    beside = belief.observe([Detection("book", 1.58, 1.5, "floor")], None)  # touching, not on it
    assert len(beside.new) == 1 and beside.overlapping == []
    belief, _ = _belief_with_a_puzzle()
    above = belief.observe([Detection("book", 1.5, 1.5, "shelf")], None)  # on another support
    assert len(above.new) == 1 and above.overlapping == []
