"""Layered recovery (Yamazaki et al., Section VII-C), one test per failure class and layer.

Each test is a table, in the style of py_trees' tests: scripted units return the statuses the
test gives them, and the table lists, step by step, every check / plan / do the runner ran and
every recovery it chose. A row is (unit, step, status) or ("recovery", unit, class, layer, attempt).
"""

from __future__ import annotations

import pytest

from tidyplan.monitor.recovery import RecoveryConfig, Runner
from tidyplan.monitor.unit import Failure, FailureClass, StateMonitor, Unit

OK = "ok"


class Scripted(Unit):
    """A unit whose check/plan/do return, call by call, the classes in its script ("A", "B",
    "C" or "ok"); once a script runs out the step succeeds."""

    def __init__(self, name, earlier=None, inserts=(), **script):
        self.name, self.earlier = name, earlier
        self.script = {step: list(v) for step, v in script.items()}
        self.inserts = list(inserts)
        self.differently = 0

    def _next(self, step):
        left = self.script.get(step, [])
        status = left.pop(0) if left else OK
        return None if status == OK else Failure(FailureClass(status), f"{self.name}-{step}-fails")

    def check(self):
        return self._next("check")

    def plan(self):
        return self._next("plan")

    def do(self, monitor):
        return self._next("do")

    def insert_for(self, failure):
        return self.inserts

    def again_differently(self):
        self.differently += 1


def _table(units, max_iterations=3):
    rows = []

    def emit(kind, **f):
        if kind == "unit":
            rows.append((f["unit"], f["step"], OK if f["ok"] else f["failure_class"]))
        else:
            rows.append(("recovery", f["unit"], f["failure_class"], f["layer"], f["attempt"]))

    result = Runner(RecoveryConfig(max_iterations=max_iterations), emit).run(units)
    return result, rows


def _ok(unit):
    return [(unit, "check", OK), (unit, "plan", OK), (unit, "do", OK)]


def test_class_a_at_check_checks_again_in_the_same_unit():
    result, rows = _table([Scripted("locate", check=["A"])])
    assert rows == [
        ("locate", "check", "A"),
        ("recovery", "locate", "A", "same_unit", 1),
        *_ok("locate"),
    ]
    assert result.ok and result.recoveries == 1


def test_class_a_again_reruns_an_earlier_unit_from_another_pose():
    adjust = Scripted("adjust_base")
    grasp = Scripted("grasp", earlier="adjust_base", plan=["A", "A"])
    result, rows = _table([adjust, grasp])
    assert rows == [
        *_ok("adjust_base"),
        ("grasp", "check", OK),
        ("grasp", "plan", "A"),
        ("recovery", "grasp", "A", "same_unit", 1),
        ("grasp", "check", OK),
        ("grasp", "plan", "A"),
        ("recovery", "grasp", "A", "earlier_unit", 2),
        *_ok("adjust_base"),
        *_ok("grasp"),
    ]
    assert result.ok and adjust.differently == 1


def test_class_b_goes_from_do_back_to_check_in_the_same_unit():
    result, rows = _table([Scripted("adjust_base"), Scripted("grasp", earlier="adjust_base", do=["B"])])
    assert rows == [
        *_ok("adjust_base"),
        ("grasp", "check", OK),
        ("grasp", "plan", OK),
        ("grasp", "do", "B"),
        ("recovery", "grasp", "B", "same_unit", 1),
        *_ok("grasp"),
    ]
    assert result.ok


def test_class_b_again_reruns_an_earlier_unit():
    adjust = Scripted("adjust_base")
    result, rows = _table([adjust, Scripted("grasp", earlier="adjust_base", do=["B", "B"])])
    assert rows == [
        *_ok("adjust_base"),
        ("grasp", "check", OK),
        ("grasp", "plan", OK),
        ("grasp", "do", "B"),
        ("recovery", "grasp", "B", "same_unit", 1),
        ("grasp", "check", OK),
        ("grasp", "plan", OK),
        ("grasp", "do", "B"),
        ("recovery", "grasp", "B", "earlier_unit", 2),
        *_ok("adjust_base"),
        *_ok("grasp"),
    ]
    assert result.ok and adjust.differently == 1


def test_class_c_inserts_a_different_unit_then_returns_to_the_original():
    pick_up = [Scripted("adjust_base"), Scripted("grasp")]
    result, rows = _table([Scripted("navigate", inserts=pick_up, do=["C"])])
    assert rows == [
        ("navigate", "check", OK),
        ("navigate", "plan", OK),
        ("navigate", "do", "C"),
        ("recovery", "navigate", "C", "insert_unit", 1),
        *_ok("adjust_base"),
        *_ok("grasp"),
        *_ok("navigate"),
    ]
    assert result.ok


def test_the_inserted_unit_recovers_by_its_own_layers():
    pick_up = [Scripted("adjust_base", check=["A"]), Scripted("grasp", earlier="adjust_base", do=["B"])]
    result, rows = _table([Scripted("navigate", inserts=pick_up, do=["C"])])
    assert rows == [
        ("navigate", "check", OK),
        ("navigate", "plan", OK),
        ("navigate", "do", "C"),
        ("recovery", "navigate", "C", "insert_unit", 1),
        ("adjust_base", "check", "A"),
        ("recovery", "adjust_base", "A", "same_unit", 1),
        *_ok("adjust_base"),
        ("grasp", "check", OK),
        ("grasp", "plan", OK),
        ("grasp", "do", "B"),
        ("recovery", "grasp", "B", "same_unit", 1),
        *_ok("grasp"),
        *_ok("navigate"),
    ]
    assert result.ok


@pytest.mark.parametrize("cap", [1, 2, 3])
def test_the_error_layer_stops_a_recovery_past_the_cap(cap):
    result, rows = _table([Scripted("locate", check=["A"] * 10)], max_iterations=cap)
    recoveries = [r for r in rows if r[0] == "recovery"]
    assert [r[3] for r in recoveries] == ["same_unit"] * cap + ["error_layer"]
    assert [r[4] for r in recoveries] == list(range(1, cap + 2))
    assert not result.ok and result.exhausted and result.unit == "locate"
    assert result.failure.klass is FailureClass.A


def test_the_count_starts_again_once_the_failing_unit_succeeds():
    # The grasp fails, the base is adjusted again and that fails once too: each recovery is
    # counted on its own, so a cap of 2 is not reached by their sum (3).
    units = [Scripted("adjust_base", do=[OK, "B"]), Scripted("grasp", earlier="adjust_base", do=["B", "B"])]
    result, rows = _table(units, max_iterations=2)
    assert [r[1:] for r in rows if r[0] == "recovery"] == [
        ("grasp", "B", "same_unit", 1),
        ("grasp", "B", "earlier_unit", 2),
        ("adjust_base", "B", "same_unit", 1),
    ]
    assert result.ok and result.recoveries == 3


def test_state_monitor_interrupts_at_the_first_condition_that_fails():
    hand = {"full": True}
    monitor = StateMonitor()
    monitor.watch("grasp_drop", FailureClass.C, lambda: hand["full"])
    assert monitor.poll() and monitor.fired is None
    hand["full"] = False
    assert not monitor.poll()
    assert monitor.fired.klass is FailureClass.C and monitor.fired.interrupted
    hand["full"] = True
    assert not monitor.poll()  # once fired, the motion stays stopped
