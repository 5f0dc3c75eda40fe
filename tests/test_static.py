"""Static flags folded into the conditions (tidyplan.pddl.static)."""

import subprocess
import sys
from pathlib import Path

import pytest

from tidyplan.pddl import model as m
from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read
from tidyplan.pddl.static import fold, static_flags
from tidyplan.pddl.writer import domain_text, problem_text

ROOT = Path(__file__).resolve().parent.parent

DOMAIN = """
(define (domain flags)
  (:requirements :strips :negative-preconditions :disjunctive-preconditions
                 :conditional-effects :existential-preconditions)
  (:predicates (fast) (slow) (done) (at ?x) (lit))
  (:action go
    :parameters (?x)
    :precondition (and (not (done)) (or (not (fast)) (at ?x)))
    :effect (and (done) (when (slow) (lit)) (when (fast) (at ?x))))
  (:action never-when-slow
    :parameters ()
    :precondition (and (not (slow)) (done))
    :effect (lit)))
"""


def _task(tmp_path, init: str):
    (tmp_path / "d.pddl").write_text(DOMAIN)
    (tmp_path / "p.pddl").write_text(
        f"(define (problem p) (:domain flags) (:objects a b) (:init {init}) (:goal (lit)))"
    )
    return read(tmp_path / "d.pddl", tmp_path / "p.pddl")


def test_only_parameterless_predicates_no_action_changes_are_flags(tmp_path):
    domain, problem = _task(tmp_path, "(slow) (at a)")
    # (done) and (lit) are changed by actions, (at ?x) has a parameter
    assert static_flags(domain, problem) == {"fast": False, "slow": True}


def test_a_false_flag_decides_the_or_and_drops_its_when(tmp_path):
    domain, problem = fold(*_task(tmp_path, ""))
    go = domain.action("go")
    assert go.precondition == m.And((m.Not(m.Atom("done", ())),))
    assert go.effect == m.AndEffect((m.Literal(m.Atom("done", ())), m.NO_EFFECT, m.NO_EFFECT))
    assert {p.name for p in domain.predicates} == {"done", "at", "lit"}


def test_a_true_flag_leaves_the_rest_of_the_or_and_drops_an_action_it_forbids(tmp_path):
    domain, problem = fold(*_task(tmp_path, "(fast) (slow)"))
    go = domain.action("go")
    assert go.precondition == m.And((m.Not(m.Atom("done", ())), m.Or((m.Atom("at", ("?x",)),))))
    assert go.effect.parts[1:] == (m.Literal(m.Atom("lit", ())), m.Literal(m.Atom("at", ("?x",))))
    assert domain.action("never-when-slow") is None
    assert all(a.args for a in problem.init)  # the flags left :init with their declarations


def test_a_tidy_problem_without_shortest_paths_compiles_to_the_domain_without_the_switch(tmp_path):
    # The switch's `or` left for Fast Downward changed LAMA's plans even where the flag was false
    # (docs/planner.md); folded, the move is the plain one.
    domain, problem = read(ROOT / "domains" / "tidy.pddl", ROOT / "problems" / "tidy-p1.pddl")
    assert "shortest-paths" not in {a.predicate for a in problem.init}
    task = compile_task(domain, problem)
    text = domain_text(task.domain) + problem_text(task.problem)
    assert "shortest-paths" not in text and "(or" not in text and "exists" not in text


def test_a_tidy_problem_with_shortest_paths_moves_only_to_where_there_is_work(tmp_path):
    text = (ROOT / "problems" / "tidy-p1.pddl").read_text()
    path = tmp_path / "p.pddl"
    path.write_text(text.replace("(hand-empty)", "(hand-empty) (shortest-paths)", 1))
    task = compile_task(*read(ROOT / "domains" / "tidy.pddl", path))
    move = domain_text(task.domain).split("(:action move")[1].split("(:action")[0]
    assert "(or" in move and "exists" in move and "shortest-paths" not in move


def test_a_flag_left_under_a_quantifier_stays_declared(tmp_path):
    # `(exists (?x) true)` holds only if there is an object: PDDL cannot write the `true`,
    # so the quantifier stays as written and the flag with it
    (tmp_path / "d.pddl").write_text(
        "(define (domain q) (:requirements :adl) (:predicates (flag) (done))"
        " (:action go :parameters () :precondition (exists (?x) (flag)) :effect (done)))"
    )
    (tmp_path / "p.pddl").write_text("(define (problem p) (:domain q) (:init (flag)) (:goal (done)))")
    domain, problem = fold(*read(tmp_path / "d.pddl", tmp_path / "p.pddl"))
    assert domain.predicate("flag") is not None and m.Atom("flag", ()) in problem.init


@pytest.mark.parametrize("goal", ["(or)", "(and (fast) (lit))"])
def test_a_goal_that_folds_to_false_is_reported_as_no_plan(tmp_path, goal):
    # unified-planning's PDDL writer refuses `false` (a traceback from its search thread, and
    # "planner cannot be used" before): the goal becomes an atom no action adds
    (tmp_path / "d.pddl").write_text(DOMAIN)
    (tmp_path / "p.pddl").write_text(f"(define (problem p) (:domain flags) (:init) (:goal {goal}))")
    run = subprocess.run(
        [sys.executable, "-m", "tidyplan", "plan", str(tmp_path / "d.pddl"), str(tmp_path / "p.pddl")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 1, run.stderr
    assert "Traceback" not in run.stderr and "unsolvable" in run.stdout + run.stderr
