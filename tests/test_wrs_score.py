"""The WRS Tidy Up score counted from trace events (tidyplan/trace/score.py), rule by rule as the
RoboCup 2021 DSPL rulebook counts Task 1 (docs/sources.md)."""

from __future__ import annotations

from tidyplan.trace.score import WrsTally, wrs_score


def _start(n: int = 2, drawers=()) -> dict:
    return {"kind": "start", "sim_s": 0.0, "expected": {"food": n}, "drawers": list(drawers)}


def _open(drawer: str, t: float) -> dict:
    step = f"(open_drawer {drawer} wp-{drawer})"
    return {
        "kind": "action",
        "sim_s": t,
        "ok": True,
        "action": step,
        "units": ["approach_handle", "pull_handle"],
    }


def _take(item: str, t: float) -> dict:
    step = f"(take_object {item} wp)"
    return {"kind": "action", "sim_s": t, "ok": True, "action": step, "units": ["grasp"]}


def _deliver(item: str, t: float) -> dict:
    return {
        "kind": "action",
        "sim_s": t,
        "ok": True,
        "action": f"(deliver_it {item} tray wp-tray food)",
        "units": ["approach_deposit", "place"],
        "delivered": item,
    }


def _drop(t: float) -> dict:
    return {"kind": "recovery", "sim_s": t, "failure": "grasp_drop", "layer": "insert_unit"}


def _end(success: bool = True, misplaced=()) -> dict:
    items = {"apple": ["tidied:tray", 0, 0], "banana": ["tidied:tray", 0, 0]}
    return {"kind": "end", "sim_s": 500.0, "success": success, "items": items, "misplaced": list(misplaced)}


def test_wrs_20_points_per_object_in_its_category_and_50_when_all_are_put_away():
    events = [_start(), _take("a", 10), _deliver("a", 20), _take("b", 30), _deliver("b", 40), _end()]
    assert wrs_score(events) == 2 * 20 + 50


def test_wrs_a_drop_costs_nothing_when_the_robot_picks_the_same_object_up_again():
    events = [_start(), _take("a", 10), _drop(15), _drop(16), _deliver("a", 20)]
    events += [_take("b", 30), _deliver("b", 40), _end()]
    assert wrs_score(events) == 20 + 20 + 50


def test_wrs_a_drop_halves_the_next_object_deposited_when_it_is_another():
    # a falls and stays; b is taken and deposited next: b's points are halved; a, later, is not
    events = [_start(), _take("a", 10), _drop(15), _take("b", 30), _deliver("b", 40)]
    events += [_take("a", 50), _deliver("a", 60), _end()]
    assert wrs_score(events) == 20 / 2 + 20 + 50


def test_wrs_opening_every_drawer_earns_50_and_not_one_fewer():
    drawers = ("drawer-left", "drawer-top")
    both = [_start(drawers=drawers), _open("drawer-left", 5), _open("drawer-top", 8)]
    both += [_take("a", 10), _deliver("a", 20), _take("b", 30), _deliver("b", 40), _end()]
    assert wrs_score(both) == 2 * 20 + 50 + 50
    one = [e for e in both if "drawer-top" not in e.get("action", "")]
    assert wrs_score(one) == 2 * 20 + 50
    late = [*both[:2], _open("drawer-top", 950), *both[3:]]
    assert wrs_score(late, time_limit_s=900) == 2 * 20 + 50  # opened after the referee stopped the run


def test_wrs_no_points_until_one_object_is_in_a_deposit():
    drawers = ("drawer-left",)
    events = [_start(drawers=drawers), _open("drawer-left", 5), _take("a", 10)]
    assert wrs_score(events) == 0


def test_wrs_a_delivery_after_the_time_limit_scores_nothing_and_loses_the_bonus():
    events = [_start(), _take("a", 10), _deliver("a", 20), _take("b", 30), _deliver("b", 950), _end()]
    assert wrs_score(events, time_limit_s=900) == 20
    assert wrs_score(events, time_limit_s=1000) == 90


def test_wrs_a_deposit_of_another_category_earns_10_and_no_bonus():
    events = [_start(), _take("a", 10), _deliver("a", 20), _take("b", 30), _deliver("b", 40)]
    assert wrs_score([*events, _end(misplaced=["banana"])]) == 30


def test_wrs_a_killed_run_scores_what_it_deposited_so_far():
    tally = WrsTally()
    for e in [_start(), _take("a", 10), _deliver("a", 20), _take("b", 30)]:
        tally.see(e)
    assert tally.score() == 20


def test_wrs_an_orientation_item_standing_the_right_way_earns_10_more():
    events = [_start(), _take("a", 10), _deliver("a", 20), _take("b", 30), _deliver("b", 40)]
    standing = {**_end(), "standing": ["banana"]}
    assert wrs_score([*events, standing]) == 2 * 20 + 10 + 50
    # counted for objects deposited in time only: none deposited, none counted
    assert wrs_score([_start(), {**_end(), "standing": ["banana"]}]) == 0
