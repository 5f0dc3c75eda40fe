"""Plans without detours (tidyplan.planning.shortcut): two chained steps of one action become
one only where the simulation proves it sound and it costs less."""

from __future__ import annotations

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read_domain, read_problem
from tidyplan.planning.planner import Step, plan
from tidyplan.planning.shortcut import shortcut

DOMAIN = """
(define (domain roads)
  (:requirements :strips :typing :action-costs)
  (:types place)
  (:predicates (at ?p - place) (road ?a ?b - place) (visited ?p - place) (marks ?p - place))
  (:functions (length ?a ?b - place) (total-cost))
  (:action drive
    :parameters (?a ?b - place)
    :precondition (and (at ?a) (road ?a ?b))
    :effect (and (not (at ?a)) (at ?b) (increase (total-cost) (length ?a ?b))))
  (:action stamp
    :parameters (?a ?b - place)
    :precondition (and (at ?a) (road ?a ?b))
    :effect (and (not (at ?a)) (at ?b) (visited ?b) (increase (total-cost) (length ?a ?b)))))
"""


def _problem(roads: dict[tuple[str, str], float]) -> str:
    init = " ".join(f"(road {a} {b}) (= (length {a} {b}) {d})" for (a, b), d in roads.items())
    return f"""
(define (problem trip) (:domain roads)
  (:objects a b c d - place)
  (:init (at a) {init})
  (:goal (at d))
  (:metric minimize (total-cost)))
"""


ROADS = {("a", "b"): 2, ("b", "c"): 2, ("c", "d"): 2, ("a", "c"): 3, ("a", "d"): 4, ("b", "d"): 3}


def _read(tmp_path, roads=ROADS):
    (tmp_path / "roads.pddl").write_text(DOMAIN)
    (tmp_path / "trip.pddl").write_text(_problem(roads))
    domain = read_domain(tmp_path / "roads.pddl")
    return domain, read_problem(tmp_path / "trip.pddl", domain)


def _task(tmp_path, roads=ROADS):
    return compile_task(*_read(tmp_path, roads))


def _steps(task, *texts: str) -> list[Step]:
    out = []
    for text in texts:
        name, *args = text.strip("()").split()
        out.append(
            Step(
                name,
                tuple(args),
                False,
                1,
                task.step_probability(name, tuple(args)),
                task.step_cost(name, tuple(args)),
            )
        )
    return out


def _texts(steps) -> list[str]:
    return [s.text for s in steps]


def test_a_detour_becomes_one_step_and_a_chain_one_step_too(tmp_path):
    task = _task(tmp_path)
    assert _texts(shortcut(_steps(task, "(drive a b)", "(drive b c)"), task)) == ["(drive a c)"]
    # a -> b -> c -> d (6): a -> c (3) then c -> d (2), then a -> d (4)
    out = shortcut(_steps(task, "(drive a b)", "(drive b c)", "(drive c d)"), task)
    assert sum(s.cost for s in out) < 6 and out[-1].args[-1] == "d"
    assert _texts(out) == ["(drive a d)"]


def test_no_road_no_shortcut_and_never_a_dearer_one(tmp_path):
    no_road = {k: v for k, v in ROADS.items() if k != ("a", "c")}
    task = _task(tmp_path, no_road)
    assert _texts(shortcut(_steps(task, "(drive a b)", "(drive b c)"), task)) == [
        "(drive a b)",
        "(drive b c)",
    ]
    dear = ROADS | {("a", "c"): 4}  # as long as the way round: nothing gained
    task = _task(tmp_path, dear)
    assert _texts(shortcut(_steps(task, "(drive a b)", "(drive b c)"), task)) == [
        "(drive a b)",
        "(drive b c)",
    ]


def test_a_step_whose_effect_the_rest_may_need_is_kept(tmp_path):
    task = _task(tmp_path)
    # stamp marks the place it drives to: a -> c directly would not have visited b
    steps = _steps(task, "(stamp a b)", "(stamp b c)")
    assert _texts(shortcut(steps, task)) == ["(stamp a b)", "(stamp b c)"]
    # two actions of different names never merge
    assert len(shortcut(_steps(task, "(drive a b)", "(stamp b c)"), task)) == 2


def test_a_kept_place_is_never_passed_over(tmp_path):
    task = _task(tmp_path)
    steps = _steps(task, "(drive a b)", "(drive b c)")
    assert _texts(shortcut(steps, task, keep={"b"}.__contains__)) == ["(drive a b)", "(drive b c)"]


def test_the_planner_returns_plans_without_detours_and_keep_none_leaves_them(tmp_path):
    domain, problem = _read(tmp_path)
    result = plan(domain, problem, "lama-first", reduce_moves=False)
    assert result.steps[-1].args[-1] == "d" and "shortcut" in result.phases
    for one, two in zip(result.steps, result.steps[1:], strict=False):  # no chain one road beats
        direct = ROADS.get((one.args[0], two.args[1]))
        assert not (one.name == two.name == "drive" and direct is not None and direct < one.cost + two.cost)
    assert "shortcut" not in plan(domain, problem, "lama-first", reduce_moves=False, keep=None).phases


def test_where_no_road_joins_the_ends_of_two_steps_nothing_is_simulated(tmp_path, monkeypatch):
    """Roads never change: where no road leads from the first step's start to the second's end,
    no two steps can merge, and the plan comes back as it was without a state computed."""
    from tidyplan.pddl.simulate import Simulator

    task = _task(tmp_path, {("a", "b"): 2, ("b", "c"): 2, ("c", "d"): 2})  # no shortcut road
    steps = _steps(task, "(drive a b)", "(drive b c)", "(drive c d)")

    def apply(*_):
        raise AssertionError("simulated")

    monkeypatch.setattr(Simulator, "apply", apply)
    assert shortcut(steps, task) == steps
    # with the road a-c the first two could merge: then it simulates (and would merge them)
    task = _task(tmp_path, {("a", "b"): 2, ("b", "c"): 2, ("c", "d"): 2, ("a", "c"): 3})
    with pytest.raises(AssertionError, match="simulated"):
        shortcut(_steps(task, "(drive a b)", "(drive b c)", "(drive c d)"), task)
