"""The grounder (`tidyplan.planning.grounding`) against Fast Downward's own translator, and what it keeps
from one task to the next; the translator run in this process (`tidyplan.planning.fastdownward`)."""

import os
import sys
import tempfile
from pathlib import Path

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read
from tidyplan.pddl.simulate import Simulator
from tidyplan.pddl.writer import domain_text, problem_text
from tidyplan.planning import fastdownward as fd
from tidyplan.planning import grounding
from tidyplan.planning.planner import Status, plan

ROOT = Path(__file__).parent.parent
TIDY = ROOT / "domains" / "tidy.pddl"
from tidyplan.generate import tasks as tidygen  # noqa: E402

# Cost-optimal and complete: two encodings of one task must give the same optimum.
OPTIMAL = fd.Search(("--search", "astar(blind())"), anytime=False)


def _search(sas: str):
    """The optimal plan, or None where the search proved there is none."""
    result = fd.search(sas, [OPTIMAL], 1e18, 0.0)  # no first-plan limit: the search ends
    assert result.ending in (fd.Ending.SOLVED, fd.Ending.UNSOLVABLE), result.message
    return result.plan


def _valid(task, actions) -> bool:
    sim = Simulator(task.domain, task.problem)
    names = {a.name.lower(): a.name for a in task.domain.actions}
    objects = {o.name.lower(): o.name for o in (*task.problem.all_objects, *task.domain.constants)}
    steps = [(names[a[0].lower()], [objects[x.lower()] for x in a[1:]]) for a in actions]
    state, broken = sim.run(sim.initial_state(task.problem), steps)
    return broken is None and sim.holds(task.problem.goal, state)


def _both_optima(task):
    """The optimal plan from our SAS task and from the translator's; each checked by progression."""
    grounded = grounding.ground(task.domain, task.problem)
    ours = None if grounded.unsolvable else _search(grounding.sas(grounded))
    theirs = _search(fd.sas_text(fd.translate(domain_text(task.domain), problem_text(task.problem))))
    assert all(_valid(task, x.actions) for x in (ours, theirs) if x is not None)
    return (ours and ours.cost), (theirs and theirs.cost)


@pytest.mark.parametrize("name", ["tidy-p1", "tidy-p2", "tidy-p3"])
def test_the_grounder_and_the_translator_give_the_same_optimum_on_the_shipped_problems(name):
    domain, problem = read(TIDY, ROOT / "problems" / f"{name}.pddl")
    optima = [_both_optima(compile_task(domain, problem).restrict(k)) for k in (1, 2, 3)]
    assert all(ours == theirs for ours, theirs in optima)
    assert optima[-1][0] is not None  # P3 plans each of them


CORPUS_SMALL = [
    "gripper/prob01",
    "blocks/probBLOCKS-4-0",
    "depot/p01",
    "miconic-simpleadl/s1-0",
    "rovers/p01",
]


@pytest.mark.parametrize("pair_id", CORPUS_SMALL)
def test_the_grounder_and_the_translator_give_the_same_optimum_on_ipc_problems(corpus_pairs_by_id, pair_id):
    # miconic-simpleadl: conditional effects under forall whose condition is fluent (boarded)
    pair = corpus_pairs_by_id[pair_id]
    domain, problem = read(pair.domain, pair.problem)
    task = compile_task(domain, problem)
    assert grounding.fragment_gap(task.domain, task.problem) is None
    ours, theirs = _both_optima(task)
    assert ours == theirs


def test_an_unreachable_goal_is_unsolvable_without_a_search():
    # nothing closes a deposit, and tray1 is not closed at the start
    text = (ROOT / "problems" / "tidy-p1.pddl").read_text()
    assert "(:goal (and" in text
    domain, problem = read(TIDY, _write(text.replace("(:goal (and", "(:goal (and (closed tray1)")))
    task = compile_task(domain, problem)
    assert grounding.ground(task.domain, task.problem).unsolvable
    assert plan(domain, problem, grounder=grounding.Grounder()).status is Status.NO_PLAN


def _write(text: str) -> Path:
    folder = Path(tempfile.mkdtemp())
    path = folder / "p.pddl"
    path.write_text(text)
    return path


def test_a_task_outside_the_fragment_goes_to_the_translator():
    # a disjunctive precondition: no conjunction of literals
    domain_file = _write(
        """(define (domain d) (:requirements :disjunctive-preconditions)
          (:predicates (a ?x) (b ?x) (c ?x))
          (:action go :parameters (?x) :precondition (or (a ?x) (b ?x)) :effect (c ?x)))"""
    )
    problem_file = domain_file.with_name("q.pddl")
    problem_file.write_text("(define (problem q) (:domain d) (:objects x) (:init (b x)) (:goal (c x)))")
    domain, problem = read(domain_file, problem_file)
    task = compile_task(domain, problem)
    assert "or is not a conjunction of literals" in grounding.fragment_gap(task.domain, task.problem)
    result = plan(domain, problem, grounder=grounding.Grounder())
    assert result.status is Status.SOLVED and [s.name for s in result.steps] == ["go"]
    assert "translated by Fast Downward" in result.message


def test_kept_operators_give_the_task_a_fresh_grounding_gives():
    # The same map (seed 1's room), the robot and the items elsewhere: the moves are kept, the
    # takes and deliveries made again where the items moved; the SAS task is the same either way.
    # Every move open, as a mission's problems are ((shortest-paths) leaves an `or` in move).
    text = tidygen.generate(1).replace("    (shortest-paths)\n", "")
    first = read(TIDY, _write(text))
    kept = grounding.Grounder()
    kept.ground(*_compiled(first))
    moved = text.replace("(robot-at wp-entrance)", "(robot-at wp-drawer)")
    assert moved != text
    second = read(TIDY, _write(moved))
    again = kept.ground(*_compiled(second))
    assert kept.reused > 0
    assert grounding.sas(again) == grounding.sas(grounding.ground(*_compiled(second)))


def test_the_operators_kept_are_the_last_tasks_only():
    # An operator the next task does not reach is not kept for the ones after it (an item's takes
    # once it is put away: kept, they made a 96-object mission's memory grow to its end); met
    # again, it is made again, the same as a fresh grounding's.
    domain_file = _write(
        """(define (domain d) (:requirements :strips)
          (:predicates (a ?x) (c ?x))
          (:action go :parameters (?x) :precondition (a ?x) :effect (c ?x)))"""
    )

    def task(*have):
        problem_file = domain_file.with_name("q.pddl")
        init = " ".join(f"(a {x})" for x in have)
        text = f"(define (problem q) (:domain d) (:objects x y) (:init {init}) (:goal (c x)))"
        problem_file.write_text(text)
        return _compiled(read(domain_file, problem_file))

    def kept_keys(grounder):
        return {key for (_actions, _schemas, ops) in grounder._kept.values() for key in ops}

    both, one = task("x", "y"), task("x")
    kept = grounding.Grounder()
    kept.ground(*both)
    assert kept_keys(kept) == {("go", ("x",)), ("go", ("y",))}
    kept.ground(*one)
    assert kept_keys(kept) == {("go", ("x",))}
    again = kept.ground(*both)
    assert (kept.reused, kept.made) == (1, 1)
    assert grounding.sas(again) == grounding.sas(grounding.ground(*both))


def _compiled(pair):
    task = compile_task(*pair)
    return task.domain, task.problem


def test_the_translators_faster_universal_effects_give_the_same_sas_task():
    # tidy.pddl's take_object: (forall (?a ?b - waypoint) (when (blocks ?o ?a ?b) ...))
    import contextlib
    import io

    from fast_downward.translate import main as translator
    from fast_downward.translate import normalize
    from fast_downward.translate.pddl_parser import lisp_parser, parsing_functions

    domain, problem = read(TIDY, ROOT / "problems" / "tidy-p3.pddl")
    task = compile_task(domain, problem)
    d, p = domain_text(task.domain), problem_text(task.problem)
    assert "(forall" in d and "(blocks " in p
    ours = fd.sas_text(fd.translate(d, p))
    with contextlib.redirect_stdout(io.StringIO()):
        parsed = parsing_functions.parse_task(
            lisp_parser.parse_nested_list(io.StringIO(d)), lisp_parser.parse_nested_list(io.StringIO(p))
        )
        normalize.normalize(parsed)
        theirs = fd.sas_text(translator.pddl_to_sas(parsed))
    assert ours == theirs


def test_a_search_that_cannot_start_is_one_message_and_leaves_nothing(monkeypatch, tmp_path):
    from tidyplan.errors import PlannerError

    # a temporary folder of the test's own: another run's searches (a second clone's tests) work
    # in the machine's, and their folders are not this call's litter
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setattr(fd, "SEARCH_BINARY", Path("/nonexistent/downward"))
    with pytest.raises(PlannerError, match="cannot start Fast Downward's search"):
        fd.search("begin_version\n3\nend_version\n", [OPTIMAL], 1e18, 0.0)
    assert os.listdir(tmp_path) == []


def test_the_sas_task_is_the_same_in_every_process():
    # string hashing, and with it the order of sets, changes from one process to the next; the
    # search breaks ties by operator order, so the SAS task must not follow it
    import hashlib
    import subprocess

    script = (
        "import sys, tempfile, pathlib\nfrom tidyplan.generate import tasks as tidygen\n"
        "from tidyplan.planning import grounding\n"
        "from tidyplan.pddl.compile import compile_task\n"
        "from tidyplan.pddl.reader import read\n"
        "p = pathlib.Path(tempfile.mkdtemp()) / 'p.pddl'\n"
        "p.write_text(tidygen.generate(2).replace('    (shortest-paths)\\n', ''))\n"
        "t = compile_task(*read('domains/tidy.pddl', p))\n"
        "sys.stdout.write(grounding.sas(grounding.ground(t.domain, t.problem)))\n"
    )
    outputs = set()
    for seed in ("1", "2", "3"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        done = subprocess.run(
            [sys.executable, "-c", script], cwd=ROOT, env=env, capture_output=True, text=True
        )
        assert done.returncode == 0, done.stderr
        outputs.add(hashlib.sha256(done.stdout.encode()).hexdigest())
    assert len(outputs) == 1
