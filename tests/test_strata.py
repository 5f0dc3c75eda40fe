"""O-FSM strata rank plans lexicographically (Yan et al., Eq. 1, P1 ⊂ P2 ⊂ P3)."""

from pathlib import Path
from types import SimpleNamespace

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read
from tidyplan.planning.planner import Status, plan
from tidyplan.planning.strata import Outcome, plan_by_strata, transition

ROOT = Path(__file__).parent.parent
TIDY = ROOT / "domains" / "tidy.pddl"


def _plan(problem: str, **kw):
    # A generous budget: these are rules of the ranking, not speed checks.
    domain, prob = read(TIDY, ROOT / "problems" / f"{problem}.pddl")
    return plan(domain, prob, **{"time_budget": 30.0, **kw})


def test_tidy_domain_has_the_three_operator_sets_of_the_paper():
    domain, _ = read(TIDY)
    by_stratum = {}
    for a in domain.actions:
        if not a.is_assumption:  # assumptions are checked, never executed: not an O-FSM operator
            by_stratum.setdefault(a.stratum, set()).add(a.name)
    assert [a.name for a in domain.actions if a.is_assumption] == ["assume-item-near"]
    # P1 is the paper's, and the WRS drawer's opening: part of delivering into a closed drawer
    assert by_stratum[1] == {"take_object", "move", "deliver_it", "open_drawer"}
    assert by_stratum[2] == {"possible_ego_pose_adjustment"}
    assert by_stratum[3] == {"drop_object", "move_back"}


@pytest.mark.slow
def test_p1_problem_is_solved_within_p1():
    result = _plan("tidy-p1")
    assert result.status is Status.SOLVED
    assert result.stratum == 1
    assert [a.outcome for a in result.attempts] == [Outcome.SOLVED]


@pytest.mark.slow
def test_p2_is_tried_only_after_p1_is_proven_impossible():
    result = _plan("tidy-p2")
    assert result.stratum == 2
    assert [(a.stratum, a.outcome) for a in result.attempts] == [(1, Outcome.UNSOLVABLE), (2, Outcome.SOLVED)]
    assert "possible_ego_pose_adjustment" in {s.name for s in result.steps}


@pytest.mark.slow
def test_p3_removes_the_blocking_object_at_the_removal_waypoint():
    result = _plan("tidy-p3")
    assert result.stratum == 3
    names = [s.name for s in result.steps]
    drop = names.index("drop_object")
    assert names[drop + 1] == "move_back"
    assert names[drop - 1] == "move"


@pytest.mark.slow
def test_higher_stratum_is_not_used_even_when_much_cheaper():
    """A P2 plan exists that costs less, but a P1 plan exists: P1 wins."""
    result = _plan("tidy-strata-cheap")
    assert result.stratum == 1
    assert all(s.stratum == 1 for s in result.steps)
    cheaper = _plan("tidy-strata-cheap", max_stratum=2)
    assert cheaper.stratum == 1  # restricting from above does not change the ranking
    # Without the ranking (all operators at once) the cheaper P2 plan is found.
    flat = _plan("tidy-strata-cheap", planner="optimal", strata=False)
    assert flat.score.cost < result.score.cost
    assert flat.stratum == 2
    assert "possible_ego_pose_adjustment" in {s.name for s in flat.steps}


@pytest.mark.slow
def test_no_plan_within_p1_exits_as_no_plan():
    result = _plan("tidy-p3", max_stratum=1)
    assert result.status is Status.NO_PLAN
    assert "P1 unsolvable" in result.message


def test_plan_by_strata_stops_at_the_first_solved_stratum():
    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    task = compile_task(domain, prob)
    seen = []

    def solve(sub):
        k = max(task.info[a.name].stratum for a in sub.domain.actions)
        seen.append(k)
        return (Outcome.SOLVED, f"plan@{k}", 0.0) if k == 2 else (Outcome.UNSOLVABLE, None, 0.0)

    result, stratum, attempts = plan_by_strata(task, solve)
    assert (result, stratum, seen) == ("plan@2", 2, [1, 2])
    assert [a.outcome for a in attempts] == [Outcome.UNSOLVABLE, Outcome.SOLVED]


def test_a_search_that_gives_up_moves_on_but_says_so():
    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    task = compile_task(domain, prob)
    outcomes = iter([Outcome.GAVE_UP, Outcome.SOLVED])
    _, stratum, attempts = plan_by_strata(task, lambda sub: (next(outcomes), "p", 0.0))
    assert stratum == 2
    assert attempts[0].outcome is Outcome.GAVE_UP


def test_a_stratum_out_of_time_never_hands_over():
    # Occam's razor: P2 only once P1 is proven empty, never because P1 was slow
    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    task = compile_task(domain, prob)
    for escalate in (True, False):
        outcomes = iter([Outcome.OUT_OF_TIME, Outcome.SOLVED])
        result, stratum, attempts = plan_by_strata(
            task, lambda sub, o=outcomes: (next(o), "p", 0.0), None, escalate
        )
        assert (result, stratum) == (None, None)
        assert [a.outcome for a in attempts] == [Outcome.OUT_OF_TIME]


def test_an_incomplete_search_hands_over_only_when_escalation_is_allowed():
    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    task = compile_task(domain, prob)
    outcomes = iter([Outcome.GAVE_UP, Outcome.SOLVED])
    result, stratum, attempts = plan_by_strata(task, lambda sub: (next(outcomes), "p", 0.0), None, False)
    assert (result, stratum) == (None, None)
    assert [a.outcome for a in attempts] == [Outcome.GAVE_UP]
    outcomes = iter([Outcome.UNSOLVABLE, Outcome.SOLVED])
    _, stratum, _ = plan_by_strata(task, lambda sub: (next(outcomes), "p", 0.0), None, False)
    assert stratum == 2  # a proof still hands over


def test_table_one_transitions():
    assert transition(1, 2) == "p_d unreachable"
    assert transition(2, 3) == "p_i unreachable"
    assert transition(3, 1) == "object delivered"
    assert transition(None, 1) is None


def _searches_ending(monkeypatch, ending):
    """Every Fast Downward search of the planner ends so, without a plan."""
    import tidyplan.planning.fastdownward as fastdownward
    import tidyplan.planning.planner as planner

    calls = []

    def search(sas, searches, first_deadline, improve, patience=None):
        calls.append(sas)
        return fastdownward.Result(ending, None)

    monkeypatch.setattr(planner.fastdownward, "search", search)
    return calls


def test_an_incomplete_search_that_finds_nothing_proves_nothing(monkeypatch):
    """An incomplete search that ends without a plan is no proof: 'unknown', not 'no plan'."""
    from tidyplan.planning.fastdownward import Ending

    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    _searches_ending(monkeypatch, Ending.GAVE_UP)
    result = plan(domain, prob)
    assert result.status is Status.UNKNOWN
    assert [a.outcome for a in result.attempts] == [Outcome.GAVE_UP] * 3
    _searches_ending(monkeypatch, Ending.UNSOLVABLE)
    assert plan(domain, prob).status is Status.NO_PLAN


def test_no_first_plan_in_time_is_its_own_status_and_stays_in_p1(monkeypatch):
    from tidyplan.planning.fastdownward import Ending

    domain, prob = read(TIDY, ROOT / "problems" / "tidy-p1.pddl")
    calls = _searches_ending(monkeypatch, Ending.OUT_OF_TIME)
    result = plan(domain, prob)
    assert result.status is Status.TIMEOUT and result.status.value == "not-found-in-time"
    assert [(a.stratum, a.outcome) for a in result.attempts] == [(1, Outcome.OUT_OF_TIME)]
    assert len(calls) == 1 and "no plan found within 60 s" in result.message


def test_the_mission_hands_over_unproven_only_after_an_incomplete_search(monkeypatch):
    """The mission's call holds escalation back; only where an incomplete search ended without a
    plan (nothing proven, nothing more to wait for) is it made again letting P2 plan. Out of time
    it is not made again: the limit was spent."""
    import tidyplan.loop.mission as mission

    calls = []

    def fake(status):
        def planned(*args, escalate_unproven=True, **kwargs):
            calls.append(escalate_unproven)
            return SimpleNamespace(status=status if len(calls) == 1 else Status.SOLVED)

        return planned

    settings = mission.Settings()
    for status, expected in (
        (Status.UNKNOWN, [False, True]),
        (Status.TIMEOUT, [False]),
        (Status.SOLVED, [False]),
    ):
        calls.clear()
        monkeypatch.setattr(mission, "plan", fake(status))
        mission.mission_plan(None, SimpleNamespace(init=()), settings, None)  # a problem of no facts
        assert calls == expected
