"""bench/floor.py, the time an omniscient robot needs: by hand for one item, and never more than
a mission of the symbolic world takes (it drives the same map, and its grasp and put cost more)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

from tests.test_loop import EXACT, _scenario
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import ENTRANCE, Placed, deposit_waypoint
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings

_spec = importlib.util.spec_from_file_location("floor", Path(__file__).parents[1] / "bench" / "floor.py")
floor = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(floor)


def test_one_item_costs_the_drive_to_it_the_grasp_the_drive_to_its_deposit_and_the_put():
    scenario = _scenario("one", [("t1", 1.8, 1.0)])
    f = floor.room_floor(scenario, grasp_s=3.0, place_s=12.0, pull_s=12.0, restarts=2, limit=900.0)
    room = RoomMap(scenario)
    facts = room.facts([Placed("t1", "toy", 1.8, 1.0)])
    bare = room.grid((), bare=True)
    wp = facts.points[facts.grasp["t1"]]
    dep = facts.points[deposit_waypoint(scenario.deposits[0].name)]
    drive = (bare.path_length(facts.points[ENTRANCE], wp) + bare.path_length(wp, dep)) / scenario.robot.speed
    assert f["floor_s"] == pytest.approx(drive + 3.0 + 12.0, abs=0.1)
    assert f["best_score_within_limit"] == 20 + 50  # in its category's deposit, and all put away
    late = floor.room_floor(scenario, 3.0, 12.0, 12.0, 2, limit=f["floor_s"] - 1)
    assert late["best_score_within_limit"] == 0  # not put away in time: nothing


@pytest.mark.slow
def test_the_floor_is_below_a_symbolic_mission_of_the_same_room(tmp_path):
    scenario = _scenario("three", [("t1", 1.8, 1.0), ("t2", 0.7, 2.4), ("t3", 2.2, 2.3)])
    summary = run(scenario, tmp_path / "t.jsonl", Settings(world="symbolic", planner="optimal", rates=EXACT))
    assert summary["success"]
    f = floor.room_floor(scenario, grasp_s=3.2, place_s=12.3, pull_s=12.3, restarts=5, limit=900.0)
    assert math.isfinite(f["floor_s"]) and f["deliveries"] == 3
    assert f["floor_s"] < summary["sim_time_s"]
