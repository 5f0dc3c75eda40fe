"""The improvement's patience (`tidyplan.planning.fastdownward._follow`): an anytime search is stopped once
no cheaper plan has come for `patience` seconds, never past the time budget, and never while an
optimal search runs beside it. A fake clock and scripted searches: nothing here depends on the
machine's speed."""

from __future__ import annotations

import pytest

from tidyplan.planning import fastdownward as fd


class _Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def perf_counter(self) -> float:
        return self.now


class _Scripted:
    """A search whose plans appear at given times (of the fake clock), with given costs."""

    def __init__(self, clock: _Clock, plans: list[tuple[float, int]], anytime: bool = True) -> None:
        self.clock, self.script = clock, sorted(plans)
        self.search = fd.Search(("--search", "scripted"), anytime=anytime)
        self.plans: list[fd.Plan] = []

    def poll_plans(self) -> None:
        while self.script and self.script[0][0] <= self.clock.now:
            at, cost = self.script.pop(0)
            self.plans.append(fd.Plan([("step",)], cost, at))

    def ended(self):
        return None  # runs until stopped


@pytest.fixture
def clock(monkeypatch):
    c = _Clock()

    class _Time:
        perf_counter = staticmethod(c.perf_counter)

    def wait(seconds: float) -> None:
        c.now = round(c.now + seconds, 6)

    monkeypatch.setattr(fd, "time", _Time)
    monkeypatch.setattr(fd, "_wait", wait)
    return c


def test_improvement_ends_when_no_cheaper_plan_came_for_the_patience(clock):
    lama = _Scripted(clock, [(0.1, 100), (0.2, 90), (0.3, 95)])  # 95 is no improvement
    result = fd._follow([lama], first_deadline=60.0, improve=1.0, patience=0.25)
    assert result.ending is fd.Ending.IMPROVING and result.plan.cost == 90
    assert clock.now == pytest.approx(0.45, abs=0.011)  # 0.25 s after the plan of cost 90


def test_patience_never_runs_past_the_budget(clock):
    lama = _Scripted(
        clock, [(round(0.1 + 0.1 * k, 6), 100 - k) for k in range(50)]
    )  # a cheaper plan every 0.1 s
    result = fd._follow([lama], first_deadline=60.0, improve=1.0, patience=0.25)
    assert clock.now == pytest.approx(1.1, abs=0.011)  # first plan at 0.1, then the 1 s budget
    assert result.plan.cost == 100 - 10  # the plans of the first second after the first


def test_no_patience_waits_for_the_whole_budget(clock):
    lama = _Scripted(clock, [(0.1, 100)])
    fd._follow([lama], first_deadline=60.0, improve=1.0, patience=None)
    assert clock.now == pytest.approx(1.1, abs=0.011)


def test_an_optimal_search_beside_lama_is_waited_for(clock):
    """lama-optimal: the optimal search's plan is worth the whole budget; patience is ignored."""
    lama = _Scripted(clock, [(0.1, 100)])
    optimal = _Scripted(clock, [(0.8, 80)], anytime=False)
    result = fd._follow([optimal, lama], first_deadline=60.0, improve=1.0, patience=0.25)
    assert result.ending is fd.Ending.SOLVED and result.plan.cost == 80
    assert clock.now == pytest.approx(0.8, abs=0.011)
