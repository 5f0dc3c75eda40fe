"""The tidy domain's behaviour units against the symbolic world: the state monitor's interrupt,
a class (C) drop mended by an inserted pick-up, and the belief keeping every object accounted for.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import pytest

from tests.test_loop import EXACT, _scenario
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import Placed
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.monitor.unit import FailureClass, StateMonitor
from tidyplan.worlds.base import Outcome
from tidyplan.worlds.symbolic import SymbolicWorld


def _holding_world(rates):
    scenario = _scenario("carry", [("t1", 1.8, 1.0)])
    world = SymbolicWorld(scenario, RoomMap(scenario), seed=0, rates=rates)
    world.robot = (1.8, 1.45)
    assert world.grasp((1.8, 1.0)).ok and world.holds()
    return world


def test_the_state_monitor_interrupts_a_drive_the_moment_the_item_falls():
    world = _holding_world(replace(EXACT, grasp_drop=1.0))
    path = [(1.8, 1.45), (1.6, 1.45), (1.4, 1.45), (1.2, 1.45), (1.0, 1.45), (0.8, 1.45)]
    monitor = StateMonitor()
    monitor.watch("grasp_drop", FailureClass.C, world.holds)
    out = world.follow(path, monitor)
    assert not out.ok and out.failure == "interrupted"
    assert monitor.fired.what == "grasp_drop" and monitor.fired.klass is FailureClass.C
    # It stopped where the item fell, short of the goal, and went no further.
    assert world.pose() in path[1:-1]
    assert math.isclose(out.metres, path.index(world.pose()) * 0.2, abs_tol=1e-6)
    item = world.items["t1"]
    assert item.state == "placed" and 0.3 <= math.dist((item.x, item.y), world.pose()) <= 0.46


def test_without_a_monitor_the_drive_goes_on_and_the_drop_goes_unnoticed():
    world = _holding_world(replace(EXACT, grasp_drop=1.0))
    path = [(1.8, 1.45), (1.6, 1.45), (1.4, 1.45)]
    out = world.follow(path)
    assert out.ok and world.pose() == path[-1] and not world.holds()


def _events(path):
    return [json.loads(line) for line in open(path, encoding="utf-8")]


def test_a_drop_in_transit_is_picked_up_by_an_inserted_unit_and_the_drive_resumes(tmp_path, monkeypatch):
    # The first carrying drive drops the toy (class C); after that nothing falls.
    real_fall = SymbolicWorld._fall

    def fall_once(self):
        real_fall(self)
        self.rates = replace(self.rates, grasp_drop=0.0)

    monkeypatch.setattr(SymbolicWorld, "_fall", fall_once)
    scenario = _scenario("drop", [("t1", 1.8, 1.0)])
    trace = tmp_path / "t.jsonl"
    summary = run(
        scenario,
        trace,
        Settings(
            world="symbolic", rates=replace(EXACT, grasp_drop=1.0), planner="lama-first", time_budget=0.5
        ),
    )
    assert summary["success"] and summary["lost_objects"] == 0
    assert summary["replans"] == 0  # mended inside the action: the planner never knew
    events = _events(trace)
    steps = [e for e in events if e["kind"] in ("unit", "recovery")]
    drop = next(i for i, e in enumerate(steps) if e.get("failure") == "grasp_drop")
    assert steps[drop]["kind"] == "unit" and steps[drop]["unit"] == "navigate" and steps[drop]["interrupted"]
    insert = steps[drop + 1]
    assert insert["kind"] == "recovery" and insert["layer"] == "insert_unit"
    assert insert["failure_class"] == "C" and insert["then"] == ["adjust_base", "grasp"]
    after = [(e["unit"], e["step"], e["ok"], e["depth"]) for e in steps[drop + 2 :] if e["kind"] == "unit"]
    # The pick-up (depth 1) ends with a grasp that holds, then the original drive (depth 0) runs
    # again from its check and reaches the deposit.
    first_nav = next(i for i, r in enumerate(after) if r[0] == "navigate")
    assert ("grasp", "do", True, 1) in after[:first_nav]
    assert all(r[3] == 1 for r in after[:first_nav])
    assert after[first_nav : first_nav + 3] == [
        ("navigate", "check", True, 0),
        ("navigate", "plan", True, 0),
        ("navigate", "do", True, 0),
    ]
    action = next(e for e in events if e["kind"] == "action" and e["recoveries"])
    assert action["ok"] and action["action"].startswith("(move") and not action["recovery_exhausted"]


def test_an_item_forgotten_by_a_later_look_of_the_same_action_is_not_reported_new():
    """An action looks more than once (a unit's check, the closing look): a phantom first seen by
    one look and forgotten by the next is not among the action's new items, so the loop never
    tries to bind or plan for an item the belief no longer holds."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context

    scenario = _scenario("phantom", [("t1", 1.8, 1.0)])
    room = RoomMap(scenario)
    belief = Belief(scenario, room)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    looks = iter([[Detection("toy", 0.9, 1.6, "floor")], []])

    def observe(_detections, waypoint, why="", stops=None):
        update = belief.observe(next(looks), waypoint)
        return update.new

    ctx = Context(world, belief, observe)
    ctx.look()
    assert len(ctx.new) == 1
    phantom = ctx.new[0]
    belief.forget(phantom)  # what the next looks do to a detection they do not confirm
    ctx.look()
    assert phantom not in belief.items and ctx.new == []


def test_an_item_the_arm_cannot_place_as_held_is_put_down_and_taken_again(tmp_path, monkeypatch):
    # The first placement finds the item out of reach as it is held (class C): the place unit
    # has it put down beside the robot and picked up again (another grasp), then places it.
    real_place = SymbolicWorld.place
    calls = []

    def place(self, deposit, approach):
        calls.append(deposit)
        if len(calls) == 1:
            return Outcome(False, "out_of_reach", 3.0)
        return real_place(self, deposit, approach)

    monkeypatch.setattr(SymbolicWorld, "place", place)
    scenario = _scenario("regrasp", [("t1", 1.8, 1.0)])
    trace = tmp_path / "t.jsonl"
    summary = run(
        scenario, trace, Settings(world="symbolic", rates=EXACT, planner="lama-first", time_budget=0.5)
    )
    assert summary["success"] and summary["lost_objects"] == 0 and len(calls) == 2
    events = _events(trace)
    insert = next(e for e in events if e["kind"] == "recovery" and e["failure"] == "out_of_reach")
    assert insert["failure_class"] == "C" and insert["layer"] == "insert_unit"
    assert insert["then"] == ["put_down", "adjust_base", "grasp"]
    done = [
        (e["unit"], e["depth"])
        for e in events
        if e["kind"] == "unit" and e["step"] == "do" and e["ok"] and e["unit"] != "look"
    ]
    placed = len(done) - done[::-1].index(("place", 0))  # then the deposit is looked into
    assert done[placed - 4 : placed] == [("put_down", 1), ("adjust_base", 1), ("grasp", 1), ("place", 0)]
    assert [e["confirmed"] for e in events if e["kind"] == "inspect_deposit"] == [["toy-1"]]
    # A put-down to take it again is no removal (Algorithm 1): nothing to move back to.
    assert not any(e["kind"] == "plan" and e["stratum"] == 3 for e in events)


def test_an_action_that_keeps_failing_after_recovery_gives_its_item_up(tmp_path, monkeypatch):
    # Every placement fails (the hand never opens): each time the recoveries are exhausted and
    # the planner replans the same delivery; after max_same_failure the error layer gives the
    # item up (the only one here), and the mission ends saying so, the item not tidied.
    def place(self, deposit, approach):
        return Outcome(False, "place_fail", 3.0)

    monkeypatch.setattr(SymbolicWorld, "place", place)
    scenario = _scenario("stuck", [("t1", 1.8, 1.0)])
    trace = tmp_path / "t.jsonl"
    summary = run(
        scenario, trace, Settings(world="symbolic", rates=EXACT, planner="lama-first", time_budget=0.5)
    )
    assert not summary["success"] and summary["delivered"] == 0
    assert summary["reason"] == "gave up on toy-1, the rest tidied; the world has 1 items left"
    given = [e for e in map(json.loads, open(trace, encoding="utf-8")) if e["kind"] == "give_up"]
    assert len(given) == 1 and "failed (place_fail) 5 times" in given[0]["why"]
    assert summary["replan_causes"] == {"recovery_exhausted": 4}


def test_an_item_beside_the_base_is_not_forgotten_by_looks_that_cannot_see_the_floor_there():
    """The sweep's lowest frame reaches ``look_down_deg`` below the horizon: the floor nearer the
    base is blind, so looks that miss an item lying there are no evidence it is gone (in pybullet,
    a box dropped beside the robot was forgotten and then driven into). The same item farther out,
    in plain view, is forgotten after as many misses."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import FORGET_AFTER, Belief

    scenario = _scenario("beside", [("t1", 1.8, 1.0)])
    belief = Belief(scenario, RoomMap(scenario))
    belief.robot = (1.5, 1.0)
    near = belief.observe([Detection("toy", 1.5, 1.25, "floor")], None).new[0]  # 0.25 m out
    far = belief.observe(
        [Detection("toy", 1.5, 1.25, "floor"), Detection("toy", 1.5, 2.7, "floor")], None
    ).new[0]
    assert not belief.should_see(belief.items[near]) and belief.should_see(belief.items[far])
    for _ in range(FORGET_AFTER + 1):
        belief.observe([], None)
    assert near in belief.items and far not in belief.items


def test_a_look_that_confirms_an_item_takes_its_place_and_extent_as_it_lies_now():
    """A tall box knocked over covers more floor, a cup knocked aside lies elsewhere: the look that
    confirms them says so, and the map the robot plans on follows (in pybullet the belief kept a
    toppled toolbox upright, and the base drove into it again and again)."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief

    scenario = _scenario("toppled", [("t1", 1.8, 1.0)])
    belief = Belief(scenario, RoomMap(scenario))
    belief.robot = (1.5, 2.5)
    name = belief.observe([Detection("toy", 1.5, 1.0, "floor", 0.19, 0.19, 0.45)], None).new[0]
    belief.observe([Detection("toy", 1.6, 1.0, "floor", 0.45, 0.19, 0.19)], None)
    k = belief.items[name]
    assert (k.x, k.y, k.sx, k.sy, k.sz) == (1.6, 1.0, 0.45, 0.19, 0.19)
    assert belief.placed()[0].box().sx == 0.45
    belief.relocate(name, 1.6, 1.1, (0.19, 0.45, 0.19))  # a unit's close look, turned the other way
    assert (k.y, k.sx, k.sy) == (1.1, 0.19, 0.45)


def _holding(label: str, at: tuple[float, float], size: tuple[float, float, float]):
    """A symbolic world and belief with the robot at (1.5, 1.5) holding the one item, seen at
    ``at`` on the floor (``size``): (room, world, belief, the item's name, its put_down unit)."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context, PutDown

    scenario = _scenario(label, [("t1", *at, size)])
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    world.robot = (1.5, 1.5)
    belief = Belief(scenario, room)
    belief.robot = world.robot
    name = belief.observe([Detection("toy", *at, "floor", *size)], None).new[0]
    assert world.grasp(at).ok
    belief.taken(name)
    return room, world, belief, name, lambda: PutDown(Context(world, belief, lambda d, w, why="": []), name)


def test_a_long_item_is_put_down_far_enough_out_to_leave_the_robot_free_to_go():
    """drop_object puts the item on a ring around the base: 0.45 m out, or farther for a long one,
    so that turned any way it leaves the robot's own cell free (a toolbox lying, 0.45 m long, put
    down 0.45 m out shut the robot in beside it: case III with faults, seed 3)."""
    room, world, belief, name, put_down = _holding("long", (1.5, 1.0), (0.45, 0.19, 0.19))
    unit = put_down()
    assert unit.check() is None and unit.plan() is None
    assert math.dist(unit.spot, world.robot) >= room.nav_radius + math.hypot(0.45, 0.19) / 2
    for turned in ((0.45, 0.19), (0.19, 0.45)):  # lying along x or along y: the robot can still go
        box = Placed(name, "toy", *unit.spot, sx=turned[0], sy=turned[1]).box()
        assert room.grid([box]).free(*world.robot), turned
    # put down, it is aside (not one of the items a pair no single item frees waits for)
    assert unit.do(None) is None
    assert belief.placed()[0].aside and belief.placed()[0].xy == unit.spot
    belief.taken(name)  # taken again and slipped out of the hand: not put aside
    belief.fell(name, world.robot, 0.1)
    assert not belief.placed()[0].aside


def test_an_item_is_not_put_down_back_where_it_was_taken_from():
    """Put back on its spot, an item taken to open a way closes it again: in a crowded room it
    was taken, put back and taken again, 9 times in a row. The spot it would have had is not
    chosen when the item was taken from there."""
    _room, _world, belief, name, put_down = _holding("back", (1.0, 1.0), (0.08, 0.08, 0.1))
    unit = put_down()
    assert unit.plan() is None
    best = unit.spot  # taken from elsewhere, the item would go here
    assert math.dist(best, (1.0, 1.0)) >= 0.2
    belief.items[name].x, belief.items[name].y = best  # as if taken from that spot
    again = put_down()
    assert again.plan() is None
    assert math.dist(again.spot, best) >= 0.2


def test_where_every_spot_shuts_some_way_the_item_goes_where_the_most_stay_open(monkeypatch):
    """No spot keeps every waypoint the robot reaches: the one that keeps the most is chosen, not
    the one farthest from the room's centre (four such spots in a row, chosen by that alone,
    walled the robot in by the entrance of a room of 96 items)."""
    from sim.grid import OccupancyGrid

    _room, _world, _belief, _name, put_down = _holding("most", (1.0, 1.0), (0.08, 0.08, 0.1))
    unit = put_down()
    assert unit.plan() is None
    farthest = unit.spot  # every spot keeps every way: the farthest from the centre
    asked: list = []

    def reaches_with(self, box, a, points):
        # each spot shuts some way, the farther east the more
        asked.append((box.cx, box.cy))
        return len(points) - 1 - round(box.cx * 1000)

    monkeypatch.setattr(OccupancyGrid, "reaches_with", reaches_with)
    unit = put_down()
    assert unit.plan() is None
    west = min(asked)
    assert unit.spot == west != farthest


def test_a_drive_does_not_step_back_to_the_centre_of_the_cell_the_robot_stands_in():
    """A path on the grid starts at the centre of the robot's cell; the base, stopped anywhere in
    it, goes straight on to the next one instead. An object too close for the camera beside the
    base, the way to that centre (2.4 cm) ran into it, whichever way the robot was going: in
    pybullet a bowl fallen beside the base pinned the robot at container B (wrs-task1-s005)."""
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context, Navigate

    scenario = _scenario("beside", [("t1", 1.0, 1.0, (0.08, 0.08, 0.1))])
    room = RoomMap(scenario)
    nav = room.grid(())
    centre = nav.xy(*nav.cell(1.5, 1.0))
    pose = (round(centre[0] + 0.024, 3), centre[1])  # in the cell, 2.4 cm east of its centre
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    # the toy (unknown to the belief) 1 cm beyond the base's reach from the pose, to the west
    world.items["t1"].x, world.items["t1"].y = pose[0] - room.bare_radius - 0.04 - 0.01, pose[1]
    world.robot = pose
    belief = Belief(scenario, room)
    belief.robot = pose
    goal = (pose[0] + 1.0, pose[1])
    unit = Navigate(Context(world, belief, lambda d, w, why="": []), goal, "wp-east")
    assert unit.plan() is None
    assert unit.path[0] == pose and all(math.dist(q, centre) > 1e-6 for q in unit.path)
    assert unit.do(StateMonitor()) is None and world.robot == goal
    # the step the grid's path began with would have run into it
    world.robot = pose
    assert not world.follow([pose, centre]).ok


def test_after_a_bump_the_close_look_goes_where_the_base_touched_else_along_its_way():
    """What stopped the base lies where its bumper touched it, which may be well aside of the way
    it was going: ahead alone, a low box 40 degrees aside was out of the camera's field, never
    found, and the robot stayed pinned for 750 s (wrs-task1-s004, pybullet)."""
    from tidyplan.exec.units import BUMP_AHEAD, Context, Navigate

    scenario = _scenario("bump", [("t1", 1.0, 1.0)])
    world = SymbolicWorld(scenario, RoomMap(scenario), seed=0, rates=EXACT)
    unit = Navigate(Context(world, None, lambda d, w, why="": []), (2.0, 1.0), "wp-east")
    unit.path = [(round(1.0 + 0.05 * k, 2), 1.0) for k in range(21)]  # cell centres, as planned
    here = (1.2, 1.0)
    assert unit._ahead(here) == pytest.approx((1.2 + BUMP_AHEAD, 1.0))
    touched = (1.2 + 0.215 * math.cos(-0.7), 1.0 + 0.215 * math.sin(-0.7))  # its right front
    x, y = unit._ahead(here, touched)
    assert math.atan2(y - 1.0, x - 1.2) == pytest.approx(-0.7) and math.dist((x, y), here) == pytest.approx(
        BUMP_AHEAD
    )


def test_a_drive_the_bumper_stopped_is_retried_round_what_a_close_look_found_there():
    """What the base ran into lies at its edge, nearer than the head camera sees the floor: a
    sweep there finds nothing, and the retry drove into it again. The retry's check looks close
    where the bumper touched; what it finds is on the map, and the path goes round it
    (wrs-task1-s000, pybullet: four sweeps saw nothing, 31 s, then a replan)."""
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context, Navigate

    toy = (1.5, 1.0)
    scenario = _scenario("bumped", [("t1", *toy)])
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    pose = (1.0, 1.0)
    world.robot = pose
    belief = Belief(scenario, room)
    belief.robot = pose
    sweeps = []

    def observe(detections, waypoint, why="", **kw):
        sweeps.append(why)
        return []

    ctx = Context(world, belief, observe)
    unit = Navigate(ctx, (2.2, 1.0), "wp-east")
    assert unit.check() is None and unit.plan() is None
    assert min(math.dist(q, toy) for q in unit.path) < 0.05  # the belief has no toy: straight on
    unit.touched = (toy[0] - 0.04, toy[1])  # the bumper's front touched it
    assert unit.check() is None  # the retry's check
    assert sweeps == []  # no sweep: it lies too near for one
    assert [belief.items[n].category for n in ctx.new] == ["toy"]
    assert unit.plan() is None
    assert min(math.dist(q, toy) for q in unit.path) > room.bare_radius  # round it
    # with no touch to go by (a transient obstacle, the fault), the sweep of the way ahead
    unit.touched = None
    assert unit.check() is None and sweeps == ["a drive stopped: what is in the way now?"]


def test_an_item_the_arm_did_not_reach_is_grasped_from_another_pose_next_time():
    """The map's reach is a distance, the arm's is not: a take that found no base pose, or whose
    arm did not reach, is not tried from the same pose again (wrs-task1-s106, pybullet: a spoon
    on the floor between two tables, tried 0.64 m out from one pose until given up)."""
    from tidyplan.belief.mapfacts import grasp_waypoint
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief

    scenario = _scenario("reach", [("t1", 1.5, 1.5)])
    belief = Belief(scenario, RoomMap(scenario))
    belief.robot = (1.5, 2.5)
    name = belief.observe([Detection("toy", 1.5, 1.5, "floor")], None).new[0]
    wp = grasp_waypoint(name)
    tried = []
    for _ in range(3):
        facts = belief.facts()
        pose = facts.points[wp]
        assert all(math.dist(pose, q) >= 0.15 for q in tried)
        tried.append(pose)
        belief.robot = pose
        belief.unreached(name)
    assert name in belief.items  # not forgotten: it is there, only not from those poses


def test_each_look_after_an_action_says_what_it_was_for():
    """A sweep's expected finds: the items nobody has found, spread over the placement points
    nobody has seen, the share of them in view, at the detector's hit rate. The trace says why
    each sweep was taken; where one could find nothing, there is none (the glance only)."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context, Look

    scenario = _scenario("why", [("t1", 1.8, 1.0), ("t2", 0.6, 2.6)])  # told of two toys
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    belief = Belief(scenario, room)
    belief.robot = world.robot
    ctx = Context(world, belief, lambda d, w, why="": [])
    assert belief.look_finds(world.robot) > 0.05  # nothing seen yet, two toys expected
    why, stops = Look(ctx, None).why()
    assert why.startswith("unseen space in view: ")
    assert Look(ctx, None, after_failure=True).why() == ("after a failure: what changed?", None)  # all around
    belief.observe([Detection("toy", 1.8, 1.0, "floor"), Detection("toy", 0.6, 2.6, "floor")], None)
    assert belief.virtual() == [] and belief.look_finds(world.robot) == 0.0  # both found
    assert Look(ctx, None).why() is None  # nothing a sweep could find here: the glance only
    tall = belief.observe([Detection("toy", 1.2, 1.2, "floor", 0.3, 0.3, 0.45)], None).new[0]
    belief.items[tall].state, belief.holding = "held", tall
    why, stops = Look(ctx, None, took=tall).why()
    assert why.startswith(f"{tall} (0.45 m tall) taken away")
    # what it hid lies beyond where it stood: the three stops around that way, not all around
    toward = math.atan2(1.2 - world.robot[1], 1.2 - world.robot[0])
    assert len(stops) == 3
    assert min(abs((h - toward + math.pi) % math.tau - math.pi) for h in stops) <= math.pi / 7


def test_after_a_failure_at_an_item_the_look_sweeps_where_it_may_be_not_all_around():
    """An approach or a grasp that failed at an item (not found where believed, or reached from
    nowhere): the sweep after it takes the stops that expect to find something, around where
    the item was lost; where nothing is left to find, only the glance. Without an item (a drive
    that failed), and without a prior, all around as before."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import Context, Look

    scenario = _scenario("why-failed", [("t1", 1.8, 1.0), ("t2", 0.6, 2.6)])
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    belief = Belief(scenario, room)
    belief.robot = world.robot
    ctx = Context(world, belief, lambda d, w, why="": [])
    belief.observe([Detection("toy", 1.8, 1.0, "floor"), Detection("toy", 0.6, 2.6, "floor")], None)
    t1 = next(k.name for k in belief.items.values() if (k.x, k.y) == (1.8, 1.0))
    t2 = next(k.name for k in belief.items.values() if (k.x, k.y) == (0.6, 2.6))
    assert Look(ctx, None, after_failure=True, failed_at=t2).why() is None  # nothing lost: a glance
    assert Look(ctx, None, after_failure=True).why() == ("after a failure: what changed?", None)
    belief.lost(t1)  # the close look did not find it: the space around its place is unseen again
    why, stops = Look(ctx, None, after_failure=True, failed_at=t1).why()
    assert why.startswith(f"after a failure at {t1}: ") and why.endswith("of 7 stops)")
    assert stops is not None and 0 < len(stops) < 7  # not all around
    toward = math.atan2(1.0 - world.robot[1], 1.8 - world.robot[0])
    assert min(abs((h - toward + math.pi) % math.tau - math.pi) for h in stops) <= math.pi / 7
    belief.prior = None  # nothing says an item is missing: all around, as before
    assert Look(ctx, None, after_failure=True, failed_at=t1).why() == ("after a failure: what changed?", None)


def test_after_an_action_where_no_sweep_pays_the_robot_glances_in_no_time():
    """The Look unit: the frames on the way and one from here, for the monitor, at no cost; a
    sweep only where one pays. A frame counts misses only in its own field: an item behind the
    robot is not missed by it, one ahead is."""
    from tidyplan.belief.percepts import Detection, Frame
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import GLANCE_WHY, Context, Look

    scenario = _scenario("glance", [("t1", 1.8, 1.0), ("t2", 0.6, 2.6)])
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    belief = Belief(scenario, room)
    belief.robot = world.robot
    whys = []

    def observe(detections, waypoint, why="", frames=None, stops=None):
        whys.append((why, frames is not None))
        for f in frames or []:
            belief.observe(f.detections, None, f)
        return []

    ctx = Context(world, belief, observe)
    belief.observe([Detection("toy", 1.8, 1.0, "floor"), Detection("toy", 0.6, 2.6, "floor")], None)
    assert Look(ctx, None).why() is None
    before = world.odometer.sim_time_s
    Look(ctx, None).do(None)
    assert whys == [(GLANCE_WHY, True)] and world.odometer.sim_time_s == before
    Look(ctx, None, after_failure=True).do(None)
    assert whys[-1] == ("after a failure: what changed?", False)  # a sweep
    assert world.odometer.sim_time_s > before
    # misses: from (0.5, 1.0) a frame looking east has t1 1.3 m ahead, t2 off to its side
    belief.robot = (0.5, 1.0)
    t1 = next(k for k in belief.items.values() if (k.x, k.y) == (1.8, 1.0))
    t2 = next(k for k in belief.items.values() if (k.x, k.y) == (0.6, 2.6))
    t1.misses = t2.misses = 0
    east = Frame((0.5, 1.0), 0.0, [])
    assert belief.should_see(t1) and belief.should_see(t2)  # a sweep from here would miss both
    for _ in range(2):
        belief.observe([], None, east)
    assert (t1.misses, t2.misses) == (2, 0)


def test_a_sweep_is_taken_stop_by_stop_where_the_space_nobody_has_seen_is():
    """Look where it pays: a stop's expected finds are its part of the sweep's (they add up to
    it); with the space east of the robot seen, the unseen-space sweep takes only stops facing
    the rest; a sweep of some stops marks seen, and counts misses in, their frames only."""
    from tidyplan.belief.percepts import SWEEP_STOPS
    from tidyplan.belief.state import Belief
    from tidyplan.exec.units import STOP_FINDS, Context, Look

    scenario = _scenario("stops", [("t1", 1.8, 1.0), ("t2", 0.6, 2.6)])
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0, rates=EXACT)
    belief = Belief(scenario, room)
    here = belief.robot = world.robot = (1.5, 1.5)
    per_stop = belief.stop_finds(here)
    assert [h for h, _ in per_stop] == list(SWEEP_STOPS)
    assert sum(f for _, f in per_stop) == pytest.approx(belief.look_finds(here))
    east = (SWEEP_STOPS[0],)  # 0 deg
    belief.observe([], None, stops=east)
    after = dict(belief.stop_finds(here))
    assert after[SWEEP_STOPS[0]] == pytest.approx(0.0, abs=1e-9)  # what it framed is seen
    assert all(after[h] > 0 for h in SWEEP_STOPS[2:6])  # the west is not
    ctx = Context(world, belief, lambda d, w, why="", stops=None: [])
    why, stops = Look(ctx, None).why()
    assert stops is not None and SWEEP_STOPS[0] not in stops
    assert all(f >= STOP_FINDS for h, f in belief.stop_finds(here) if h in stops)
    assert why.endswith(f"({len(stops)} of 7 stops)")


def test_a_sweep_of_some_stops_counts_a_miss_only_in_their_frames():
    from tidyplan.belief.percepts import SWEEP_STOPS, Detection
    from tidyplan.belief.state import Belief

    scenario = _scenario("misses", [("t1", 2.5, 1.5), ("t2", 0.5, 1.5)])
    room = RoomMap(scenario)
    belief = Belief(scenario, room)
    belief.robot = (1.5, 1.5)
    belief.observe([Detection("toy", 2.5, 1.5, "floor"), Detection("toy", 0.5, 1.5, "floor")], None)
    east_toy = next(k for k in belief.items.values() if k.x > 2)
    west_toy = next(k for k in belief.items.values() if k.x < 1)
    assert belief.should_see(east_toy) and belief.should_see(west_toy)
    belief.observe([], None, stops=(SWEEP_STOPS[0],))  # a stop facing east shows neither toy now
    assert (east_toy.misses, west_toy.misses) == (1, 0)


def test_a_grasp_asked_to_approach_again_where_no_other_pose_is_free_is_tried_from_here():
    """After a failed grasp the recovery asks the base adjustment for another pose; where no
    other is free and the robot reaches the item from where it stands, it stays and the grasp
    is tried again from there (asked four times for a pose there was not, the take was given up:
    the last item of the 96-object mission, 15 of 54 missions with faults). Out of reach, there
    is nothing to try from: no base pose, as before."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief
    from tidyplan.exec.context import Context
    from tidyplan.exec.units import AdjustBase

    scenario = _scenario("hemmed", [("t1", 1.8, 1.0)])
    world = SymbolicWorld(scenario, RoomMap(scenario), seed=0, rates=EXACT)
    belief = Belief(scenario, RoomMap(scenario))
    world.robot = belief.robot = (1.8, 1.45)  # 0.45 m from the toy
    name = belief.observe([Detection("toy", 1.8, 1.0, "floor")], None).new[0]
    unit = AdjustBase(Context(world, belief, lambda *a, **k: []), name)
    assert unit.check() is None and unit.plan() is None and unit.path is None  # within reach
    _near, best, _far = unit.reach
    tx, ty = unit.target
    # every pose of the ring tried before (as after failures from each)
    unit.tried = [
        (tx + best * math.cos(2 * math.pi * k / 16), ty + best * math.sin(2 * math.pi * k / 16))
        for k in range(16)
    ]
    unit.again_differently()
    assert unit.plan() is None and unit.path is None  # from here again
    unit.do(StateMonitor())
    assert world.pose() == (1.8, 1.45) and not unit.another
    world.robot = belief.robot = (1.8, 2.2)  # out of reach
    unit.again_differently()
    failure = unit.plan()
    assert failure is not None and failure.what == "no_base_pose"
