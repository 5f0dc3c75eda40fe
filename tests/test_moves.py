"""Moves only to where there is work (`tidyplan.planning.moves`): found in a domain's own words, the same
optimum as with every move open, and left alone wherever the argument for it does not hold."""

from __future__ import annotations

import itertools
import math
import random
from pathlib import Path

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.reader import read
from tidyplan.pddl.simulate import Simulator
from tidyplan.planning.moves import reduce_moves
from tidyplan.planning.planner import Status, plan

# A fetch domain of its own words: the robot's place is a two-argument fluent (the robot is a
# parameter), items are fetched into boxes, and one action reads the place without a constant.
FETCH = """
(define (domain fetch)
  (:requirements :typing :action-costs)
  (:types bot spot thing box)
  (:predicates (stands ?r - bot ?s - spot) (lies ?t - thing ?s - spot) (has ?r - bot ?t - thing)
               (empty ?r - bot) (box-at ?b - box ?s - spot) (fits ?t - thing ?b - box)
               (road ?a ?b - spot) (boxed ?t - thing))
  (:functions (total-cost) - number (length ?a ?b - spot) - number)
  (:action go
    :parameters (?r - bot ?a ?b - spot)
    :precondition (and (stands ?r ?a) (road ?a ?b))
    :effect (and (not (stands ?r ?a)) (stands ?r ?b) (increase (total-cost) (length ?a ?b))))
  (:action fetch
    :parameters (?r - bot ?t - thing ?s - spot)
    :precondition (and (stands ?r ?s) (lies ?t ?s) (empty ?r))
    :effect (and (has ?r ?t) (not (lies ?t ?s)) (not (empty ?r)) (increase (total-cost) 1)))
  (:action box
    :parameters (?r - bot ?t - thing ?b - box ?s - spot)
    :precondition (and (has ?r ?t) (fits ?t ?b) (box-at ?b ?s) (stands ?r ?s))
    :effect (and (not (has ?r ?t)) (empty ?r) (boxed ?t) (increase (total-cost) 1))))
"""


def _problem(seed: int, n_things: int = 4, n_spots: int = 7, home: bool = False, skew: float = 0.0) -> str:
    """Spots at random points, every road open at its straight-line length (a metric), things
    on random spots, two boxes. `skew` lengthens one road past the way round (no metric)."""
    rng = random.Random(seed)
    spots = [f"s{i}" for i in range(n_spots)]
    xy = {s: (rng.uniform(0, 4), rng.uniform(0, 3.5)) for s in spots}
    init = ["(= (total-cost) 0)", "(stands bot1 s0)", "(empty bot1)", "(box-at b0 s1)", "(box-at b1 s2)"]
    for k in range(n_things):
        init += [f"(lies t{k} {rng.choice(spots[3:])})", f"(fits t{k} b{k % 2})"]
    for a, b in itertools.permutations(spots, 2):
        d = math.dist(xy[a], xy[b]) + (skew if (a, b) == ("s0", "s1") else 0.0)
        init += [f"(road {a} {b})", f"(= (length {a} {b}) {d:.2f})"]
    goal = [f"(boxed t{k})" for k in range(n_things)] + (["(stands bot1 s0)"] if home else [])
    return f"""(define (problem fetch-{seed}) (:domain fetch)
  (:objects bot1 - bot {" ".join(spots)} - spot {" ".join(f"t{k}" for k in range(n_things))} - thing
            b0 b1 - box)
  (:init {" ".join(init)})
  (:goal (and {" ".join(goal)}))
  (:metric minimize (total-cost)))"""


def _read(tmp_path, domain: str, problem: str):
    (tmp_path / "d.pddl").write_text(domain)
    (tmp_path / "p.pddl").write_text(problem)
    return read(tmp_path / "d.pddl", tmp_path / "p.pddl")


def test_a_pure_move_goes_only_to_where_a_reader_can_act(tmp_path):
    task = compile_task(*_read(tmp_path, FETCH, _problem(0)))
    reduced = reduce_moves(task)
    assert reduced is not None and reduced.moves == ("go",)
    names = [a.name for a in reduced.task.domain.actions]
    assert "go" not in names
    assert sorted(n for n in names if n.startswith("go")) == ["go-to-box", "go-to-fetch"]
    go_fetch = reduced.task.domain.action("go-to-fetch")
    # the move's own parameters first (a plan step reads back by them), then the reader's rest
    assert [p.name for p in go_fetch.parameters][:3] == ["?r", "?a", "?b"]
    assert reduced.original(("go-to-fetch", "bot1", "s0", "s4", "t2")) == ("go", "bot1", "s0", "s4")
    assert reduced.original(("fetch", "bot1", "t2", "s4")) == ("fetch", "bot1", "t2", "s4")


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("home", [False, True])
def test_reduced_and_open_moves_have_the_same_optimum(tmp_path, seed, home):
    """Differential: the optimal search on the task with every move open, and on the reduced
    one; the reduced plan is a plan of the original task (simulated step by step)."""
    domain, problem = _read(tmp_path, FETCH, _problem(seed, home=home))
    task = compile_task(domain, problem)
    assert reduce_moves(task) is not None
    full = plan(domain, problem, planner="optimal", reduce_moves=False)
    small = plan(domain, problem, planner="optimal")
    assert full.status is Status.SOLVED and small.status is Status.SOLVED
    moves = sum(s.name == "go" for s in small.steps)
    # costs are rounded to whole units of 1/scale once each: a metric may be off by one unit
    assert full.score.cost <= small.score.cost <= full.score.cost + moves / task.scale + 1e-9
    sim = Simulator(task.domain, task.problem)
    state, failed = sim.run(sim.initial_state(task.problem), [(s.name, s.args) for s in small.steps])
    assert failed is None and sim.holds(task.problem.goal, state)
    if home:
        assert small.steps[-1].name == "go" and small.steps[-1].args[-1] == "s0"
    # only to where there is work: never two moves in a row
    assert not any(a.name == b.name == "go" for a, b in zip(small.steps, small.steps[1:], strict=False))


def test_moves_that_are_not_a_metric_are_left_open(tmp_path):
    """One road longer than the way round through another spot: a stop on the way pays, so
    every move stays open."""
    task = compile_task(*_read(tmp_path, FETCH, _problem(0, skew=10.0)))
    assert reduce_moves(task) is None


def test_a_missing_road_leaves_the_moves_open(tmp_path):
    problem = _problem(0).replace("(road s0 s1)", "")
    task = compile_task(*_read(tmp_path, FETCH, problem))
    assert reduce_moves(task) is None  # s0 -> s2 -> s1 has no direct road to replace it


@pytest.mark.parametrize(
    "change",
    [
        # the place read negatively: a stop somewhere may be what makes an action possible
        ("(has ?r ?t) (fits ?t ?b)", "(has ?r ?t) (fits ?t ?b) (not (stands ?r ?s))"),
        # a move that does more than move
        ("(stands ?r ?b) (increase", "(stands ?r ?b) (empty ?r) (increase"),
        # another fluent in the move's precondition (a door that may close)
        ("(stands ?r ?a) (road ?a ?b))", "(stands ?r ?a) (road ?a ?b) (empty ?r))"),
    ],
)
def test_where_the_argument_fails_the_task_is_left_as_it_is(tmp_path, change):
    old, new = change
    assert old in FETCH
    task = compile_task(*_read(tmp_path, FETCH.replace(old, new), _problem(0)))
    assert reduce_moves(task) is None


def test_a_negated_fluent_nothing_adds_holds_throughout():
    """tidy.pddl's move also needs `(not (blocked ?from ?to))` and `(not (must-move-back))`. In a
    stratum where nothing adds them and a problem where none holds, they hold throughout, and
    the move is pure; where a P3 action can raise must-move-back, or an item blocks a path (a
    stop on the way round may be needed), every move stays open."""
    root = Path(__file__).parent.parent
    open_room = compile_task(*read(root / "domains" / "tidy.pddl", root / "problems" / "tidy-p1.pddl"))
    assert reduce_moves(open_room.restrict(1)).moves == ("move",)
    assert reduce_moves(open_room.restrict(2)).moves == ("move",)  # the pose adjustment reads too
    assert reduce_moves(open_room.restrict(3)) is None  # drop_object raises must-move-back
    blocked = compile_task(*read(root / "domains" / "tidy.pddl", root / "problems" / "tidy-p3.pddl"))
    assert all(reduce_moves(blocked.restrict(k)) is None for k in blocked.strata)


@pytest.mark.parametrize(
    "pair",
    [
        ("gripper", "domain.pddl", "prob01.pddl", "move"),
        ("satellite", "domain.pddl", "p01-pfile1.pddl", "turn_to"),
        ("depot", "domain.pddl", "p01.pddl", "drive"),
        ("logistics00", "domain.pddl", "probLOGISTICS-4-0.pddl", "drive-truck"),
    ],
)
def test_competition_domains_keep_their_optimum(corpus, pair):
    """Moves found in IPC domains nobody wrote for us: the optimal plan costs the same with every
    move open and with moves only to where there is work (unit costs: an exact metric)."""
    folder, domain_file, problem_file, move = pair
    domain, problem = read(corpus / folder / domain_file, corpus / folder / problem_file)
    assert reduce_moves(compile_task(domain, problem)).moves == (move,)
    full = plan(domain, problem, planner="optimal", reduce_moves=False)
    small = plan(domain, problem, planner="optimal")
    assert full.status is small.status is Status.SOLVED
    assert small.score.cost == full.score.cost


def _random_problem(seed: int) -> str:
    """A random room for FETCH: 4-7 spots, one or two robots, 1-4 things, sometimes a robot
    asked to end at a spot (the goal reads the place too)."""
    rng = random.Random(seed)
    spots = [f"s{i}" for i in range(rng.randint(4, 7))]
    bots = [f"r{k}" for k in range(rng.randint(1, 2))]
    things = [f"t{k}" for k in range(rng.randint(1, 4))]
    xy = {s: (rng.uniform(0, 4), rng.uniform(0, 3.5)) for s in spots}
    init = ["(= (total-cost) 0)", "(box-at b0 s1)", "(box-at b1 s2)"]
    init += [f"(stands {r} {rng.choice(spots)}) (empty {r})" for r in bots]
    init += [f"(lies {t} {rng.choice(spots)}) (fits {t} b{rng.randint(0, 1)})" for t in things]
    for a, b in itertools.permutations(spots, 2):
        init.append(f"(road {a} {b}) (= (length {a} {b}) {math.dist(xy[a], xy[b]):.2f})")
    goal = [f"(boxed {t})" for t in things]
    if rng.random() < 0.5:
        goal.append(f"(stands r0 {rng.choice(spots)})")
    return f"""(define (problem fetch-random-{seed}) (:domain fetch)
  (:objects {" ".join(bots)} - bot {" ".join(spots)} - spot {" ".join(things)} - thing b0 b1 - box)
  (:init {" ".join(init)})
  (:goal (and {" ".join(goal)}))
  (:metric minimize (total-cost)))"""


@pytest.mark.parametrize("seed", range(20))
def test_random_rooms_with_one_or_two_robots_keep_the_optimum(tmp_path, seed):
    """Differential, on seeded random rooms: the same status and optimum either way (two robots:
    each robot's runs of moves are merged, the other's moves are readers of nothing of it)."""
    domain, problem = _read(tmp_path, FETCH, _random_problem(seed))
    task = compile_task(domain, problem)
    assert reduce_moves(task) is not None
    full = plan(domain, problem, planner="optimal", reduce_moves=False)
    small = plan(domain, problem, planner="optimal")
    assert full.status is small.status is Status.SOLVED
    moves = sum(s.name == "go" for s in small.steps)
    assert full.score.cost <= small.score.cost <= full.score.cost + moves / task.scale + 1e-9
