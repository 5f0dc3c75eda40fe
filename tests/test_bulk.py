"""tidyplan/pddl/bulk.py: the fast path for `:init` reads what lark reads, positions and all.

Differential: each text is read twice, by `parse` (the fast path wherever it applies) and by
`parse(..., fast=False)` (lark alone); the two must give the same model, compared field by field
with the fields that equality leaves out (positions), or the same diagnostic. On the corpus's
problems and on seeded random problems (seeded), some made only of flat facts (the fast path must take
them), some with things it must leave to lark.
"""

from __future__ import annotations

import dataclasses
import random

import pytest

from tidyplan.errors import PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.bulk import split_init
from tidyplan.pddl.reader import parse, read_text, token_patterns


def _fields(x):
    """A value with every field spelt out, positions too (equality skips some of them)."""
    if dataclasses.is_dataclass(x):
        return (type(x).__name__, tuple((f.name, _fields(getattr(x, f.name))) for f in dataclasses.fields(x)))
    if isinstance(x, (tuple, list)):
        return tuple(_fields(i) for i in x)
    return x


def _outcome(text: str, fast: bool):
    try:
        return "model", _fields(parse(text, "p.pddl", fast=fast))
    except PddlError as e:
        return "error", str(e)


def _fast_applies(text: str) -> bool:
    return split_init(text, token_patterns()) is not None


def test_corpus_problem_read_alike_by_both_paths(corpus_pair):
    text = read_text(corpus_pair.problem)
    assert _fast_applies(text)
    fast = parse(text, str(corpus_pair.problem))
    assert fast.init  # the fast path's facts are there, not an empty section
    assert _fields(fast) == _fields(parse(text, str(corpus_pair.problem), fast=False))


# ------------------------------------------------------------ random problems
_NAMES = ["at", "and", "domain", "init", "either", "define", "Connected", "not-yet", "x"]
_NAME_START = "abcxyzAQZ_"
_NAME_REST = _NAME_START + "0189-_"
# Lark's WS and COMMENT, and no separator at all (two names then run together, for both).
_SEPS = [" ", "  ", "\t", "\n", "\r\n", "\n\n  ", " ; (p a) note\n", "\n;(:init (q))\n", ""]
_NUMBERS = ["3", "-2.5", "+1e3", ".5", "7.", "0", "\u0661\u0662"]
# What the fast path must not take: not flat, not a fact, not lark's characters, not closed.
_ODD_ITEMS = [
    "(not (p a))", "(p 3)", "(p (q))", "(p a", "p", "()", "(:init)", "(= (f) x)", "(= f 3)",
    "(p\u00a0a)", "(p\va)", "(p \u00e9)", "(p a))", "(= (f a) 1e)", "(and (p a))", "(p - a)",
]  # fmt: skip
_OPENINGS = ["(:init", "(:INIT", "( :init", "(\n; c\n:Init", "(:initial"]
_OTHER = ["", "(:init (p z))", "; (:init (p z))\n", "(:metric minimize (total-cost))"]
# A mistake outside the facts, found by lark reading the rest or the whole.
_ODD_SECTIONS = ["", "(:goal 3)", "(:objects - )", ")", "(:init"]


def _name(rng: random.Random) -> str:
    if rng.random() < 0.5:
        return rng.choice(_NAMES)
    return rng.choice(_NAME_START) + "".join(rng.choices(_NAME_REST, k=rng.randint(0, 5)))


def _item(rng: random.Random) -> str:
    """An atom or a value, laid out as a file might."""
    s = lambda: rng.choice(_SEPS)  # noqa: E731
    terms = [("?" if rng.random() < 0.3 else "") + _name(rng) for _ in range(rng.randint(0, 4))]
    args = "".join(rng.choice([" ", "\n", "\t", " ; c\n"]) + t for t in terms)
    if rng.random() < 0.2:
        return f"({s()}={s()}({s()}{_name(rng)}{args}{s()}){s()} {rng.choice(_NUMBERS)}{s()})"
    return f"({s()}{_name(rng)}{args}{s()})"


def _problem(rng: random.Random, odd: bool) -> str:
    items = [_item(rng) for _ in range(rng.randint(0, 12))]
    other = ["(:objects a b - t c)", "(:goal (and (p a) (q ?x)))", rng.choice(_OTHER)]
    if odd:
        for _ in range(rng.randint(0, 2)):
            items.insert(rng.randint(0, len(items)), rng.choice(_ODD_ITEMS))
        other.append(rng.choice(_ODD_SECTIONS))
    init = rng.choice(_OPENINGS) + "".join(rng.choice(_SEPS) + i for i in items) + rng.choice(_SEPS) + ")"
    sections = [init, *other]
    rng.shuffle(sections)
    before = rng.choice(["", "; (:init (p y))\n", "\n\n   "])
    return f"{before}(define (problem P) (:domain d)\n  " + "\n  ".join(sections) + ")\n"


@pytest.mark.parametrize("odd", [False, True], ids=["flat", "odd"])
def test_random_problems_read_or_refused_alike_by_both_paths(odd):
    rng = random.Random(33 + odd)
    texts = [_problem(rng, odd) for _ in range(400)]
    for text in texts:
        assert _outcome(text, fast=True) == _outcome(text, fast=False), text
    # The seeds reach each way through: facts taken, and refused by lark after them or before.
    taken = [t for t in texts if _fast_applies(t)]
    assert len(taken) > (50 if odd else 200)
    if odd:
        assert any(_outcome(t, fast=True)[0] == "error" for t in taken)
        assert any(_outcome(t, fast=True)[0] == "error" for t in texts if t not in taken)


# ------------------------------------------------------------- what is taken
def test_flat_facts_are_taken_with_their_positions():
    text = "(define (problem p) (:domain d)\n (:init (AT a ?X) ; x\n\t(=  (Fuel a) -2.5) (p a?x)))"
    assert _fast_applies(text)
    problem = parse(text)
    assert [(a.predicate, a.args, a.pos) for a in problem.init] == [
        ("at", ("a", "?x"), m.Pos(2, 10)),
        ("p", ("a", "?x"), m.Pos(3, 22)),
    ]
    [(term, value)] = problem.values
    assert (term.name, term.args, term.pos, value) == ("fuel", ("a",), m.Pos(3, 7), -2.5)


@pytest.mark.parametrize(
    "init",
    [
        "(:init (p a)) (:init (q b))",  # two sections: the reader keeps the last, lark decides
        "(:init (p a) (not (q b)))",
        "(:init (p a) (p 3))",
    ],
)
def test_what_is_not_flat_is_left_to_lark(init):
    text = f"(define (problem p) (:domain d) {init})"
    assert not _fast_applies(text)
    assert _outcome(text, fast=True) == _outcome(text, fast=False)


def test_an_error_after_the_facts_is_lark_s_own():
    text = "(define (problem p) (:domain d)\n (:init (p a)\n (p b))\n (:goal (and (p a)) 3))"
    assert _fast_applies(text)
    with pytest.raises(PddlError) as e:
        parse(text, "p.pddl")
    assert str(e.value).startswith("p.pddl:4:21: ")
    assert _outcome(text, fast=True) == _outcome(text, fast=False)
