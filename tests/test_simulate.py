"""The monitor's progression (tidyplan.pddl.simulate): a run's conditional effects over a
static predicate, matched from its facts, give what enumerating every binding gives."""

from __future__ import annotations

import random

from tidyplan.pddl.reader import parse
from tidyplan.pddl.simulate import Overlay, Simulator

DOMAIN = """
(define (domain clear)
  (:requirements :typing :conditional-effects :universal-preconditions)
  (:types spot thing - object heavy - thing)
  (:constants hub - spot)
  (:predicates (at ?t - thing ?s - spot) (holding ?t - thing) (blocks ?t - thing ?a ?b - spot)
               (shut ?a ?b - spot) (loop ?t - thing ?a - spot ?b - spot) (mark ?a - spot))
  (:action take
    :parameters (?t - thing ?s - spot)
    :precondition (at ?t ?s)
    :effect (and (holding ?t) (not (at ?t ?s))
                 (forall (?a ?b - spot) (when (blocks ?t ?a ?b) (not (shut ?a ?b))))
                 (forall (?a - spot) (when (loop ?t ?a ?a) (mark ?a)))
                 (forall (?b - spot) (when (blocks ?t hub ?b) (mark ?b)))
                 (forall (?t - heavy) (when (blocks ?t ?s ?s) (mark ?s)))))
)
"""


def _problem(rng: random.Random) -> str:
    spots = [f"s{k}" for k in range(6)]
    things = [f"t{k}" for k in range(5)]
    every = spots + ["hub"]
    init = [f"(at {t} {rng.choice(spots)})" for t in things]
    for _ in range(25):
        t, a, b = rng.choice(things), rng.choice(every), rng.choice(every)
        init.append(f"(blocks {t} {a} {b})")
        init.append(f"(shut {a} {b})")
        init.append(f"(loop {t} {a} {rng.choice([a, b])})")
    # a fact whose first argument is a spot, not a thing: no binding of ?t may take it
    init.append("(blocks s1 hub s2)")
    return f"""
(define (problem p) (:domain clear)
  (:objects {" ".join(spots)} - spot {" ".join(things[:3])} - thing {" ".join(things[3:])} - heavy)
  (:init {" ".join(sorted(set(init)))})
  (:goal (holding t0)))
"""


def test_a_runs_matched_conditional_effects_are_those_of_every_binding_step_by_step():
    domain = parse(DOMAIN)
    for seed in range(40):
        rng = random.Random(seed)
        problem = parse(_problem(rng))
        sim = Simulator(domain, problem)
        state = sim.initial_state(problem)
        steps, now = [], state
        for t in [f"t{k}" for k in rng.sample(range(5), 5)]:
            (spot,) = [f[2] for f in now if f[0] == "at" and f[1] == t]
            steps.append(("take", (t, spot)))
            now = sim.apply(now, "take", (t, spot))  # every binding enumerated
        reached, failed = sim.run(state, steps)
        assert failed is None
        assert reached == now
        assert any(f[0] == "mark" for f in now) and len([f for f in now if f[0] == "shut"]) < len(
            [f for f in state if f[0] == "shut"]
        )  # the conditional effects fired: the comparison is of something


def test_a_forall_of_a_subtype_takes_no_object_of_the_supertype():
    domain = parse(DOMAIN)
    text = """
(define (problem p) (:domain clear)
  (:objects s1 - spot a - thing h - heavy)
  (:init (at a s1) (blocks a s1 s1) (blocks h s1 s1))
  (:goal (holding a)))
"""
    problem = parse(text)
    sim = Simulator(domain, problem)
    state = sim.initial_state(problem)
    reached, failed = sim.run(state, [("take", ("a", "s1"))])
    assert failed is None
    assert ("mark", "s1") in reached  # h is heavy: (blocks h s1 s1) marks s1
    problem = parse(text.replace("(blocks h s1 s1)", ""))
    sim = Simulator(domain, problem)
    reached, _ = sim.run(sim.initial_state(problem), [("take", ("a", "s1"))])
    assert ("mark", "s1") not in reached  # a is a thing, not heavy: its fact is no binding


def test_an_overlay_state_progresses_as_the_plain_state_it_stands_for():
    """The monitor's state is an Overlay: a shared base (the map's atoms) and a small part. Run
    and apply over it give what they give over the same atoms as one frozenset, whatever the
    split; the forall effects kept from run to run (by the facts of their condition they were
    read from) are not those of a run whose small part adds one (a blocks fact the base lacks)."""
    domain = parse(DOMAIN)
    for seed in range(30):
        rng = random.Random(seed)
        problem = parse(_problem(rng))
        sim = Simulator(domain, problem)
        state = sim.initial_state(problem)
        atoms = sorted(state)
        base = frozenset(a for a in atoms if rng.random() < 0.7)
        layered = Overlay(base, state - base)
        assert layered == state and len(layered) == len(state) and set(layered) == set(state)
        takes = [
            (t, f[2])
            for t in (f"t{k}" for k in rng.sample(range(5), 5))
            for f in atoms
            if f[0] == "at" and f[1] == t
        ]
        steps = [("take", args) for args in takes]
        for _ in range(2):  # the second run over the same base reads the kept effects
            plain, broken = sim.run(state, steps)
            over, broken_over = sim.run(layered, steps)
            assert isinstance(over, Overlay) and over.base is base
            assert broken_over == broken and over == plain, seed
        now, now_layered = state, layered
        for args in takes[:3]:
            now, now_layered = sim.apply(now, "take", args), sim.apply(now_layered, "take", args)
            assert now_layered == now
        # one more blocks fact in the small part: the answers kept from the runs above must not
        # serve this one
        t, a, b = "t0", "hub", "s0"
        extra = Overlay(base, (state - base) | {("blocks", t, a, b), ("shut", a, b)})
        plain_extra = state | {("blocks", t, a, b), ("shut", a, b)}
        steps_t0 = [s for s in steps if s[1][0] == "t0"]
        over, _ = sim.run(extra, steps_t0)
        plain, _ = sim.run(plain_extra, steps_t0)
        assert over == plain and ("shut", a, b) not in over
