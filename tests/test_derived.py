"""Derived predicates (`(:derived ...)`, docs/dialect.md): read with positions, checked, compiled
to plain PDDL with their rules, planned by Fast Downward, held to VAL, and closed by the simulator.

The domain of our own (tests/data/derived/) has recursive rules (where the robot can get to),
a negated basic predicate (a dark room), the negation of a derived one (a second stratum) and a
derived goal over every item. The corpus's domains with `:derived` are planned and validated
where the corpus has them.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tidyplan.errors import PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.derived import NotStratified, strata
from tidyplan.pddl.reader import parse, read
from tidyplan.pddl.simulate import Simulator
from tidyplan.pddl.writer import domain_text, formula, problem_text
from tidyplan.planning.planner import Status, plan

DATA = Path(__file__).parent / "data" / "derived"
DOMAIN, PROBLEM = DATA / "domain.pddl", DATA / "problem.pddl"

PLAN = [
    ("open-door", "d1", "hall", "kitchen"),
    ("go", "hall", "kitchen"),
    ("open-door", "d2", "kitchen", "store"),
    ("switch-on", "lamp1", "store"),
    ("go", "kitchen", "store"),
    ("take", "cup", "store"),
    ("go", "store", "kitchen"),
    ("put", "cup", "kitchen"),
    ("take", "book", "kitchen"),
    ("go", "kitchen", "hall"),
    ("put", "book", "hall"),
]


def _lines(steps) -> list[str]:
    return ["(" + " ".join(s) + ")" for s in steps]


def _compiled(tmp_path: Path) -> tuple[Path, Path]:
    domain, problem = read(DOMAIN, PROBLEM)
    task = compile_task(domain, problem)
    d, p = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    d.write_text(domain_text(task.domain))
    p.write_text(problem_text(task.problem))
    return d, p


# ------------------------------------------------------------------ reading
def test_derived_rules_are_read_with_their_positions(position):
    domain, _ = read(DOMAIN, PROBLEM)
    text = DOMAIN.read_text()
    assert [r.predicate for r in domain.derived] == ["reachable", "reachable", "dark", "cut-off", "tidy"]
    assert domain.derived_predicates == {"reachable", "dark", "cut-off", "tidy"}
    first = domain.derived[0]
    assert (first.pos.line, first.pos.col) == position(text, "reachable ?r - room) (robot-in")
    assert first.parameters == (m.Typed("?r", ("room",), first.parameters[0].pos),)
    assert first.body == m.Atom("robot-in", ("?r",))
    assert isinstance(domain.derived[1].body, m.Exists)


def test_strata_put_a_negated_derived_predicate_above_the_one_it_negates():
    domain, _ = read(DOMAIN, PROBLEM)
    layers = strata(domain.derived)
    level = {p: k for k, layer in enumerate(layers) for p in layer}
    assert level["cut-off"] > level["reachable"]
    assert level["dark"] == 0  # it negates a basic predicate only


def test_a_derived_predicate_through_its_own_negation_is_not_stratified():
    domain = parse(
        "(define (domain d) (:predicates (p) (q) (b)) (:derived (p) (not (q))) (:derived (q) (and (b) (p))))"
    )
    with pytest.raises(NotStratified):
        strata(domain.derived)


# ------------------------------------------------------------------ errors
HEADER = (
    "(define (domain d) (:requirements :derived-predicates) (:types t) (:predicates (p ?x - t) (q ?x - t))\n"
)


@pytest.mark.parametrize(
    "rest, needle, message",
    [
        (
            "(:derived (p ?x - t) (q ?x))\n(:action a :parameters (?x - t) :effect (p ?x)))",
            "p ?x))",
            r"derived predicate 'p' cannot be an effect of 'a': its rules alone make it true",
        ),
        (
            "(:derived (p ?x - t) (q ?x))\n(:action a :parameters (?x - t)"
            " :effect (when (q ?x) (not (p ?x)))))",
            "p ?x)))",
            r"derived predicate 'p' cannot be an effect of 'a': its rules alone make it true",
        ),
        ("(:derived (r ?x - t) (q ?x)))", "r ?x", r"undeclared predicate 'r'"),
        ("(:derived (p ?x - u) (q ?x)))", "?x - u", r"undeclared type 'u' of parameter '\?x'"),
        ("(:derived (p ?x ?y - t) (q ?x)))", "p ?x ?y", r"'p' takes 1 argument, given 2"),
        ("(:derived (p ?x - t) (q ?y)))", "q ?y", r"undeclared variable '\?y'"),
        ("(:derived (p ?x - t) (q ?x ?x)))", "q ?x ?x", r"'q' takes 1 argument, given 2"),
        (
            "(:derived (p ?x - t) (not (q ?x))) (:derived (q ?x - t) (p ?x)))",
            "p ?x - t) (not",
            r"derived predicate 'p' depends on the negation of 'q', which depends on it: the rules"
            r" are not stratified",
        ),
        ("(:derived (p ?x - t) :probability 0.5 (q ?x)))", ":probability", r"unexpected .*"),
    ],
)
def test_a_bad_derived_rule_is_one_located_message(
    rest, needle, message, write, tidyplan_cmd, position, expect_lines
):
    text = HEADER + rest
    path = write("domain.pddl", text)
    done = subprocess.run([*tidyplan_cmd, "check", str(path)], capture_output=True, text=True)
    assert done.returncode == 2
    line, col = position(text, needle)
    expect_lines(done.stderr, [(str(path), line, col, message)])


def test_a_derived_predicate_in_init_is_refused_where_it_is_written(
    write, tidyplan_cmd, position, expect_lines
):
    d = write("domain.pddl", HEADER + "(:derived (p ?x - t) (q ?x)))")
    text = "(define (problem q) (:domain d) (:objects a - t) (:init (q a) (p a)) (:goal (p a)))"
    p = write("problem.pddl", text)
    done = subprocess.run([*tidyplan_cmd, "check", str(d), str(p)], capture_output=True, text=True)
    assert done.returncode == 2
    line, col = position(text, "p a)) (:goal")
    expect_lines(
        done.stderr,
        [(str(p), line, col, r"derived predicate 'p' cannot be given in :init: its rules derive it")],
    )


# -------------------------------------------------------------- compilation
def test_compilation_keeps_the_rules_and_reads_back(tmp_path):
    d, p = _compiled(tmp_path)
    text = d.read_text()
    assert ":derived-predicates" in text
    assert text.count("(:derived ") == 5
    back, _ = read(d, p)
    source, _ = read(DOMAIN, PROBLEM)

    def rules(domain):
        return [
            (r.predicate, [(t.name, t.types) for t in r.parameters], formula(r.body)) for r in domain.derived
        ]

    assert rules(back) == rules(source)


def test_either_in_a_rule_becomes_a_membership_condition():
    domain = parse(
        "(define (domain d) (:types a b c) (:predicates (p ?x - (either a b)) (q ?x))"
        " (:derived (p ?x - (either a b)) (q ?x))"
        " (:action act :parameters (?x - c) :precondition (p ?x) :effect (q ?x)))",
        "d.pddl",
    )
    problem = parse("(define (problem q) (:domain d) (:objects i - a j - c) (:init (q i)) (:goal (p i)))")
    task = compile_task(domain, problem)
    (rule,) = task.domain.derived
    assert rule.parameters[0].types == (m.ROOT_TYPE,)
    assert "(or (is-a ?x) (is-b ?x))" in domain_text(task.domain)


def test_unified_planning_engines_are_told_they_cannot_take_rules():
    from tidyplan.pddl.to_up import to_up

    domain, problem = read(DOMAIN, PROBLEM)
    task = compile_task(domain, problem)
    with pytest.raises(PddlError, match="no derived predicates"):
        to_up(task.domain, task.problem)


# ---------------------------------------------------------------- planning
@pytest.mark.parametrize("engine", ["lama-optimal", "lama-first", "optimal"])
def test_the_domain_with_rules_is_planned_and_valid_under_val(engine, tmp_path, val):
    domain, problem = read(DOMAIN, PROBLEM)
    result = plan(domain, problem, planner=engine, time_budget=1)
    assert result.status is Status.SOLVED, result.message
    steps = [(s.name, *s.args) for s in result.steps]
    d, p = _compiled(tmp_path)
    verdict = val(d, p, _lines(steps))
    assert verdict.valid, verdict.output
    sim = Simulator(domain, problem)
    end, failed = sim.run(sim.initial_state(problem), [(s[0], s[1:]) for s in steps])
    assert failed is None and sim.holds(problem.goal, end)
    if engine != "lama-first":  # the cost-optimal searches: our hand-made plan is optimal
        assert result.score.cost == 15


def test_val_rejects_a_plan_that_needs_a_rule_not_yet_true(tmp_path, val):
    d, p = _compiled(tmp_path)
    assert val(d, p, _lines(PLAN)).valid
    without_lamp = [s for s in PLAN if s[0] != "switch-on"]  # the store stays dark: no way in
    assert not val(d, p, _lines(without_lamp)).valid


def test_a_goal_that_only_rules_can_reach_is_a_proven_no_plan():
    domain, problem = read(DOMAIN, PROBLEM)
    text = PROBLEM.read_text().replace("(door-between d2 kitchen store) (door-between d2 store kitchen)", "")
    shut = parse(text, str(PROBLEM))
    result = plan(domain, shut, time_budget=1)
    assert result.status is Status.NO_PLAN


# --------------------------------------------------------------- simulation
def test_the_simulator_closes_the_rules_in_every_state():
    domain, problem = read(DOMAIN, PROBLEM)
    sim = Simulator(domain, problem)
    s0 = sim.initial_state(problem)
    assert ("reachable", "hall") in s0 and ("reachable", "kitchen") not in s0
    assert ("cut-off", "kitchen") in s0 and ("dark", "store") in s0 and ("dark", "hall") not in s0
    assert not sim.applicable(s0, "go", ("hall", "kitchen"))
    s1 = sim.apply(s0, "open-door", ("d1", "hall", "kitchen"))
    assert ("reachable", "kitchen") in s1 and ("cut-off", "kitchen") not in s1
    assert sim.applicable(s1, "go", ("hall", "kitchen"))
    # a state given without its derived facts is closed where its truth is asked
    basic = frozenset(f for f in s1 if f[0] not in domain.derived_predicates)
    assert sim.applicable(basic, "go", ("hall", "kitchen"))
    assert sim.holds(m.Atom("reachable", ("kitchen",)), basic)
    assert not sim.holds(m.Atom("tidy", ()), basic)


def test_run_closes_each_step_as_apply_does():
    domain, problem = read(DOMAIN, PROBLEM)
    sim = Simulator(domain, problem)
    state = sim.initial_state(problem)
    for k, (name, *args) in enumerate(PLAN):
        assert sim.applicable(state, name, args), k
        state = sim.apply(state, name, args)
    end, failed = sim.run(sim.initial_state(problem), [(s[0], s[1:]) for s in PLAN])
    assert failed is None and end == state and ("tidy",) in end
    # the lamp left off: the way into the dark store is the first step that fails
    without_lamp = [(s[0], s[1:]) for s in PLAN if s[0] != "switch-on"]
    _, failed = sim.run(sim.initial_state(problem), without_lamp)
    assert without_lamp[failed] == ("go", ("kitchen", "store"))


# ------------------------------------------------------------------ corpus
def test_corpus_domains_with_rules_are_planned_and_valid(corpus_pairs, tmp_path, val):
    """psr-large, optical-telegraphs and philosophers (IPC 2004) use :derived; planned with the
    defaults and their plans given to VAL on the original files."""
    with_rules = [pair for pair in corpus_pairs if ":derived" in pair.domain.read_text().lower()]
    if not with_rules:
        pytest.skip("the corpus has no domain with :derived (no psr-large, optical-telegraphs, philosophers)")
    for pair in with_rules:
        domain, problem = read(pair.domain, pair.problem)
        result = plan(domain, problem)
        assert result.status is Status.SOLVED, (pair.id, result.message)
        verdict = val(pair.domain, pair.problem, [s.text for s in result.steps])
        assert verdict.valid, (pair.id, verdict.output[-2000:])
