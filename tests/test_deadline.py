"""Against the clock (tidyplan.loop.deadline): where everything known does not fit in the time
left, the first goal is the route worth the most score in it, the rest put off and said so.

The route is checked on WRS Task 1's room with every object known (the belief told each one as
a detection), and in missions of a small symbolic room whose referee allows a minute or two.
"""

from __future__ import annotations

import pytest

from sim.scenario.read import loads
from tests.test_loop import ROOM as LOOP_ROOM
from tests.test_loop import _events, _items
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import deposit_waypoint
from tidyplan.belief.percepts import Detection
from tidyplan.belief.problem import robot_waypoint
from tidyplan.belief.state import Belief
from tidyplan.loop.deadline import DRAWERS_POINTS, PULL_S, PUT_S, STOP_S, TAKE_S, deadline
from tidyplan.loop.goals import HORIZON, goals
from tidyplan.loop.mission import run
from tidyplan.loop.options import OptionError, Settings
from tidyplan.loop.scenarios import load_scenario
from tidyplan.worlds.rates import Rates

EXACT = Rates(take=1.0, deliver=1.0, drop=1.0, false_negative=0.0, false_positive=0.0, handle_slip=0.0)


def _task1_known():
    """WRS Task 1's room with every object seen where it lies (the orientation items as such)."""
    scenario = load_scenario("wrs-task1")
    belief = Belief(scenario, RoomMap(scenario))
    seen = [
        Detection(i.label, i.x, i.y, i.on, i.sx, i.sy, i.sz, (0.0, 0.0, -1.0) if i.orientation else None)
        for i in scenario.items
    ]
    belief.observe(seen, None)
    return belief, belief.facts()


def _seconds(belief, facts, route, drawers) -> float:
    """The route's seconds as the module's model gives them, worked out here on their own: the
    drawers nearest first from the robot, then each item to its nearest accepting deposit."""
    speed = belief.scenario.robot.speed

    def drive(a, b):
        return 0.0 if a == b else facts.path[(a, b)] / speed + STOP_S

    at, t = robot_waypoint(facts, belief), 0.0
    left = list(drawers)
    while left:
        d = min(left, key=lambda d: (drive(at, deposit_waypoint(d)), d))
        t, at = t + drive(at, deposit_waypoint(d)) + PULL_S, deposit_waypoint(d)
        left.remove(d)
    still = belief.closed - set(drawers)
    for name in route:
        k = belief.items[name]
        cat = "orientation" if k.oriented else k.category
        deps = [
            deposit_waypoint(d.name)
            for d in belief.scenario.deposits
            if d.category == cat and d.name not in still
        ]
        wp = facts.grasp[name]
        to = min(deps, key=lambda w: (drive(wp, w), w))
        t += drive(at, wp) + TAKE_S + drive(wp, to) + PUT_S
        at = to
    return t


def test_everything_that_fits_needs_no_route():
    belief, facts = _task1_known()
    assert deadline(belief, facts, 10_000.0) is None


def test_the_route_fits_the_time_left_and_puts_off_the_rest():
    belief, facts = _task1_known()
    d = deadline(belief, facts, 900.0)
    assert d is not None and d.everything_s > 900.0
    assert d.seconds <= 900.0
    assert 0 < len(d.route) < len(belief.items)
    assert sorted(d.route + d.put_off) == sorted(belief.items)  # each item chosen or put off, once
    assert abs(_seconds(belief, facts, d.route, d.drawers) - d.seconds) < 1e-6
    # the score it claims is the rulebook's for what it takes: 20 an item, 30 standing in
    # container B, 50 for every drawer opened
    oriented = sum(belief.items[n].oriented for n in d.route)
    assert d.points == 20 * len(d.route) + 10 * oriented + (DRAWERS_POINTS if d.drawers else 0)
    assert "put off" in d.why() and f"{len(d.put_off)} put off" in d.why()


def test_more_time_never_less_score_and_the_drawers_when_they_pay():
    belief, facts = _task1_known()
    short, long = deadline(belief, facts, 120.0), deadline(belief, facts, 900.0)
    assert short.points <= long.points and len(short.route) <= len(long.route)
    # 15 minutes: opening the three drawers (about a minute) pays 50 and opens two categories
    assert long.drawers == tuple(sorted(belief.closed))
    # a minute: the drawers would take it all; an item or two score more
    tiny = deadline(belief, facts, 60.0)
    assert tiny.drawers == () and tiny.route


def test_the_item_in_the_hand_goes_first():
    belief, facts = _task1_known()
    name = max(belief.items, key=lambda n: (facts.grasp.get(n) is not None, n))
    belief.taken(name)
    d = deadline(belief, belief.facts(), 300.0)
    assert d.route[0] == name


def test_the_deadline_goal_comes_first_with_the_routes_dozen_and_its_drawers():
    belief, facts = _task1_known()
    d = deadline(belief, facts, 900.0)
    label, goal, virtual = goals(belief, facts, d)[0]
    assert label == "deadline" and virtual == []
    assert goal == list(d.route[:HORIZON]) + list(d.drawers)
    assert [g[0] for g in goals(belief, facts)][0] != "deadline"  # not against the clock: none


# ---------------------------------------------------------------------- missions
# Two toys beside the deposit, three in the far corner, all in sight of the entrance in the middle:
# in a minute and a half the near ones are worth it.
# test_loop's room, a metre larger each way, the robot starting in its middle
ROOM = (
    LOOP_ROOM.format(name="clock")
    .replace("bounds = [0.0, 3.0, 0.0, 3.0]", "bounds = [0.0, 4.0, 0.0, 4.0]")
    .replace("entrance = [2.6, 0.4]", "entrance = [2.2, 2.2]")
)
SMALL = (0.06, 0.06, 0.06)
TOYS = [(n, x, y, SMALL) for n, x, y in (("near-a", 1.1, 1.2), ("near-b", 1.1, 1.8))] + [
    (n, x, y, SMALL) for n, x, y in (("far-a", 3.6, 3.5), ("far-b", 3.5, 3.7), ("far-c", 3.7, 3.7))
]


def _room(limit: str = "") -> object:
    """The room with the five toys; ``limit`` a top-level line (before the first table)."""
    text = ROOM.replace('title = "a test room"\n', f'title = "a test room"\n{limit}\n', 1)
    return loads(text + "[prior]\ncount = { toy = 5 }\n" + _items(TOYS), "clock.toml")


def _mission(tmp_path, scenario, name, **settings):
    trace = tmp_path / f"{name}.jsonl"
    s = run(scenario, trace, Settings(world="symbolic", rates=EXACT, planner="lama-first", **settings))
    return s, _events(trace)


def test_a_scenario_limit_is_planned_against_and_the_rest_tidied_after_it(tmp_path):
    # 70 s: time for the two toys by the shelf, not for a far one (a take's estimate is 6.7 s, TAKE_S)
    summary, events = _mission(tmp_path, _room("time_limit_s = 70.0"), "limit")
    first = next(e for e in events if e["kind"] == "deadline")
    plan = next(e for e in events if e["kind"] == "plan")
    assert plan["goal_kind"] == "deadline" and plan["goal"] == first["route"]
    assert first["put_off"] and len(first["route"]) + len(first["put_off"]) == 5
    assert f"{len(first['route'])} items" in first["why"]
    # the near toys first: the robot takes them standing by the shelf, the far ones after
    takes = [e for e in events if e["kind"] == "action" and e["action"].startswith("(take_object")]
    assert [e["robot"][0] < 2.0 for e in takes] == [True, True, False, False, False]
    assert summary["delivered"] == 5 and summary["success"]  # continue: everything in the end
    assert summary["time_limit_s"] == 70.0


def test_stop_at_the_limit_ends_the_mission_there(tmp_path):
    summary, events = _mission(tmp_path, _room(), "stop", time_limit=120.0, after_limit="stop")
    end = next(e for e in events if e["kind"] == "end")
    assert "time limit 120 s reached" in end["reason"] and not summary["success"]
    acts = [e for e in events if e["kind"] == "action"]
    # the last action began before the limit: the robot stops once the clock has passed it
    assert acts and all(e["sim_s"] - e["seconds"] < 120.0 for e in acts)
    assert 0 < summary["delivered"] < 5


def test_no_limit_no_route(tmp_path):
    _, events = _mission(tmp_path, _room(), "none")
    assert not [e for e in events if e["kind"] == "deadline"]


@pytest.mark.parametrize("value", [0, -5.0, float("inf")])
def test_a_time_limit_must_be_a_positive_number(value):
    with pytest.raises(OptionError, match="time_limit"):
        Settings(time_limit=value)


def test_after_limit_is_stop_or_continue():
    with pytest.raises(OptionError, match="after_limit"):
        Settings(after_limit="pause")
