"""Unknown objects (WRS Task 1: one of each category with no recognition data): the detector
reports them as ``unknown``, their true category only the referee holds, and they go where the
scenario's deposits for unknown objects are (bin B in the rulebook's room)."""

from __future__ import annotations

import json

import pytest

from sim.scenario.model import UNKNOWN, ScenarioError
from sim.scenario.read import loads
from tidyplan.belief.geometry import RoomMap
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.symbolic import SymbolicWorld

ROOM = """
schema = 1
name = "unknowns"
title = "a room with an unknown object"
[room]
bounds = [0.0, 3.0, 0.0, 3.0]
entrance = [2.6, 0.4]
[prior]
count = {{ toy = 1, unknown = 1 }}
[[furniture]]
name = "shelf"
center = [0.2, 1.5]
size = [0.3, 1.0]
height = 0.9
kind = "table"
[[deposit]]
name = "box"
category = "toy"
position = [0.2, 1.3, 0.9]
approach = [0.75, 1.3]
{bin_b}
[[item]]
name = "toy"
category = "toy"
position = [1.8, 1.0]
[[item]]
name = "mystery"
category = "toy"
position = [1.8, 2.2]
unknown = true
"""
BIN_B = """
[[deposit]]
name = "bin-b"
category = "unknown"
position = [0.2, 1.8, 0.9]
approach = [0.75, 1.8]
"""
EXACT = Rates(take=1.0, deliver=1.0, drop=1.0, false_negative=0.0, false_positive=0.0)


def test_an_unknown_object_is_seen_as_unknown_and_keeps_its_true_category_for_the_referee():
    s = loads(ROOM.format(bin_b=BIN_B), "u.toml")
    mystery = next(i for i in s.items if i.name == "mystery")
    assert mystery.unknown and mystery.category == "toy" and mystery.label == UNKNOWN
    world = SymbolicWorld(s, RoomMap(s), seed=0, rates=EXACT)
    seen = world.look()
    assert sorted(d.category for d in seen) == ["toy", "unknown"]
    assert world.untidied() == ["mystery", "toy"]


def test_the_mission_puts_the_unknown_object_where_the_scenario_says_and_the_referee_agrees(tmp_path):
    s = loads(ROOM.format(bin_b=BIN_B), "u.toml")
    trace = tmp_path / "u.jsonl"
    summary = run(s, trace, Settings(world="symbolic", planner="lama-first", rates=EXACT))
    assert summary["success"], summary["reason"]
    assert summary["untidied"] == [] and summary["delivered"] == 2
    end = [json.loads(line) for line in open(trace)][-2]
    assert end["items"]["mystery"][0] == "tidied:bin-b" and end["items"]["toy"][0] == "tidied:box"
    assert end["misplaced"] == []


def test_an_unknown_object_in_its_true_categorys_deposit_is_not_tidied_by_the_rules(tmp_path):
    s = loads(ROOM.format(bin_b=BIN_B), "u.toml")
    world = SymbolicWorld(s, RoomMap(s), seed=0, rates=EXACT)
    world.items["mystery"].state, world.items["mystery"].deposit = "tidied", "box"
    assert "mystery" in world.untidied()


@pytest.mark.parametrize(
    ("change", "where", "what"),
    [
        ({"bin_b": ""}, 'item "mystery".unknown', "an unknown object, and no deposit accepts 'unknown'"),
        (
            {"category": True},
            'item "mystery".category',
            "the true category, not 'unknown': say unknown = true",
        ),
        ({"flag": True}, 'item "mystery".unknown', "must be true or false, got 'yes'"),
    ],
)
def test_unknown_objects_the_rooms_deposits_cannot_take_are_refused(change, where, what):
    text = ROOM.format(bin_b="" if "bin_b" in change else BIN_B)
    if "category" in change:
        text = text.replace(
            'category = "toy"\nposition = [1.8, 2.2]', 'category = "unknown"\nposition = [1.8, 2.2]'
        )
    if "flag" in change:
        text = text.replace("unknown = true", 'unknown = "yes"')
    with pytest.raises(ScenarioError) as err:
        loads(text, "u.toml")
    assert f"u.toml: {where}: {what}" in err.value.messages
