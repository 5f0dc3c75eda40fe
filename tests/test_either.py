"""`either` types are kept when planning: a parameter of `(either truck plane)` never takes a package."""

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read
from tidyplan.planning.planner import Status, plan

DOMAIN = """(define (domain carriers)
  (:requirements :typing :existential-preconditions)
  (:types truck plane - vehicle vehicle package place)
  (:predicates (at ?x - (either vehicle package) ?p - place) (moved ?x - (either vehicle package)))
  (:action go
    :parameters (?v - (either truck plane) ?from ?to - place)
    :precondition (at ?v ?from)
    :effect (and (at ?v ?to) (not (at ?v ?from)) (moved ?v))))
"""
PROBLEM = """(define (problem p) (:domain carriers)
  (:objects t1 - truck a1 - plane pk - package l1 l2 - place)
  (:init (at t1 l1) (at a1 l1) (at pk l1))
  (:goal (and (at t1 l2) (at a1 l2) GOAL)))
"""


def _task(tmp_path, goal: str):
    (tmp_path / "d.pddl").write_text(DOMAIN)
    (tmp_path / "p.pddl").write_text(PROBLEM.replace("GOAL", goal))
    return tmp_path / "d.pddl", tmp_path / "p.pddl"


def test_an_either_parameter_does_not_take_other_types(tmp_path):
    domain, problem = read(*_task(tmp_path, "(moved pk)"))
    result = plan(domain, problem, planner="lama-first", time_budget=30)
    assert result.status is Status.NO_PLAN  # a package cannot `go`


def test_membership_facts_cover_subtypes(tmp_path):
    domain, problem = read(*_task(tmp_path, "(moved t1)"))
    task = compile_task(domain, problem)
    facts = {(a.predicate, a.args) for a in task.problem.init if a.predicate.startswith("is-")}
    assert facts == {("is-truck", ("t1",)), ("is-plane", ("a1",))}


@pytest.mark.slow
def test_either_in_a_quantifier_and_the_plan_is_valid(tmp_path, val):
    d, p = _task(tmp_path, "(exists (?x - (either truck package)) (moved ?x))")
    domain, problem = read(d, p)
    result = plan(domain, problem, planner="lama-first", time_budget=30)
    assert result.status is Status.SOLVED
    assert all(step.args[0] in ("t1", "a1") for step in result.steps)
    verdict = val(d, p, [str(s) for s in result.steps])
    assert verdict.valid, verdict.output
