"""The success-probability threshold applies to what the robot commits to next (docs/loop.md):
the plan's steps up to its first goal fact, never the product over a whole room."""

from __future__ import annotations

import json

import pytest

from tests.test_loop import EXACT, _events, _plans, _scenario
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.state import Belief
from tidyplan.exec.bindings import MonitoredExecutor
from tidyplan.generate import rooms as wrs  # noqa: E402
from tidyplan.loop.loop import LoopConfig, Mission
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.loop.scenarios import DOMAIN
from tidyplan.loop.triggers import Cause
from tidyplan.pddl.reader import parse
from tidyplan.pddl.simulate import Simulator
from tidyplan.planning.commitment import commitment, probability
from tidyplan.planning.planner import Step, plan
from tidyplan.trace.writer import TraceWriter
from tidyplan.worlds.symbolic import SymbolicWorld

DOMAIN_TEXT = """
(define (domain toys)
  (:requirements :strips :typing)
  (:types toy)
  (:predicates (here ?t - toy) (held ?t - toy) (away ?t - toy) (free))
  (:action take :parameters (?t - toy) :probability 0.9
    :precondition (and (here ?t) (free)) :effect (and (held ?t) (not (here ?t)) (not (free))))
  (:action put :parameters (?t - toy) :probability 0.8
    :precondition (held ?t) :effect (and (away ?t) (free) (not (held ?t))))
  (:assumption guess :parameters (?t - toy) :probability 0.5
    :precondition (here ?t) :effect (here ?t)))
"""
PROBLEM_TEXT = """
(define (problem two) (:domain toys)
  (:objects a b - toy)
  (:init (here a) (here b) (free))
  (:goal (and (away a) (away b))))
"""


def _step(name: str, *args: str, p: float) -> Step:
    return Step(name, args, False, 1, p, 1.0)


def test_the_commitment_ends_at_the_first_step_that_achieves_a_goal_fact():
    domain, problem = parse(DOMAIN_TEXT, "d.pddl"), parse(PROBLEM_TEXT, "p.pddl")
    sim = Simulator(domain, problem)
    steps = [
        _step("take", "a", p=0.9),
        _step("put", "a", p=0.8),
        _step("take", "b", p=0.9),
        _step("put", "b", p=0.8),
    ]
    committed = commitment(steps, sim, sim.initial_state(problem), problem.goal)
    assert [s.text for s in committed] == ["(take a)", "(put a)"]
    assert probability(committed) == pytest.approx(0.72)
    assert probability(steps) == pytest.approx(0.72**2)


def test_a_plan_under_the_threshold_as_a_whole_is_adopted_when_its_commitment_is_not(tmp_path):
    # Four toys: the whole plan succeeds with (0.95 * 0.98)^4 = 0.75, each delivery's part with
    # 0.93. With the threshold at 0.8 the old rule gave up at once; the mission now tidies all.
    toys = [("t1", 1.8, 0.8), ("t2", 1.8, 1.4), ("t3", 1.8, 2.0), ("t4", 1.8, 2.5)]
    trace = tmp_path / "t.jsonl"
    rates = EXACT
    summary = run(
        _scenario("four", toys),
        trace,
        Settings(world="symbolic", rates=rates, planner="lama-first", time_budget=0.5, min_probability=0.8),
    )
    first = _plans(_events(trace))[0]
    assert first["probability"] < 0.8 <= first["commitment_probability"] and first["adopted"]
    assert summary["success"] and summary["delivered"] == 4


def test_a_commitment_under_the_threshold_ends_the_mission_with_the_rule_named(tmp_path):
    summary, events = None, None
    trace = tmp_path / "t.jsonl"
    summary = run(
        _scenario("one", [("t1", 1.8, 1.0)]),
        trace,
        Settings(world="symbolic", rates=EXACT, planner="lama-first", min_probability=0.99),
    )
    events = _events(trace)
    assert not summary["success"]
    assert summary["reason"].startswith("no plan whose next commitment is likely enough")
    assert all(not p["adopted"] for p in _plans(events))


@pytest.mark.slow
@pytest.mark.parametrize("per_room", [3, 12], ids=["24 objects", "96 objects"])
def test_two_room_wrs_rooms_of_24_and_96_objects_do_not_give_up_at_the_start(tmp_path, per_room):
    scenario = wrs.generate("two", 1, per_room=per_room)
    room = RoomMap(scenario)
    world = SymbolicWorld(scenario, room, seed=0)
    belief = Belief(scenario, room)

    def planner(d, p, k):
        return plan(d, p, "lama-first", 60.0, k)

    with TraceWriter(tmp_path / "t.jsonl", clock=lambda: 0.0) as trace:
        mission = Mission(
            DOMAIN, belief, MonitoredExecutor(world, trace.emit), world, planner, trace, LoopConfig()
        )
        mission._observe(world.look(), "wp-entrance")
        assert mission._replan(Cause.INITIAL) is None  # a plan adopted: the mission goes on
    plans = [
        json.loads(line) for line in open(tmp_path / "t.jsonl") if '"kind":"plan"' in line.replace(" ", "")
    ]
    adopted = [p for p in plans if p["adopted"]]
    assert adopted and adopted[0]["commitment_probability"] >= 1e-4
    assert len(scenario.items) == 8 * per_room


def test_assumptions_about_objects_the_committed_actions_do_not_use_are_not_committed_to():
    domain, problem = parse(DOMAIN_TEXT, "d.pddl"), parse(PROBLEM_TEXT, "p.pddl")
    sim = Simulator(domain, problem)
    guess_b = Step("guess", ("b",), True, 1, 0.01, 0.0)  # an assumption the planner put first
    guess_a = Step("guess", ("a",), True, 1, 0.5, 0.0)
    steps = [guess_b, guess_a, _step("take", "a", p=0.9), _step("put", "a", p=0.8), _step("take", "b", p=0.9)]
    committed = commitment(steps, sim, sim.initial_state(problem), problem.goal)
    assert committed == (guess_a, steps[2], steps[3])
