"""docs/dialect.md: what the reader accepts and what lands in the model.

Keyword-looking names are names, letter case does not matter, layout quirks
of real files are read, and each extension arrives with the value written.
"""

from __future__ import annotations

import pytest

from tidyplan.errors import Diagnostic, InputError, PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.reader import parse, read, read_domain, read_problem

KEYWORDS_DOMAIN = """\
; Names that start like keywords, in a file written in capitals.
(DEFINE (DOMAIN Keys) ; the name is `keys`
  (:REQUIREMENTS :STRIPS :TYPING)
  (:TYPES vehicle place - object aircraft - vehicle either-y - object)
  (:PREDICATES (at ?x - (either vehicle either-y) ?p - place)
               (and-gate ?x) (or-else ?x) (not-yet ?x) (AND-Upper ?x)
               (forall-x ?x) (exists-x ?x) (when-x ?x) (increase ?x))
  (:ACTION Foo
    :PARAMETERS (?A - aircraft?P - place)
    :PRECONDITION (AND (at ?a ?P) (and-gate ?a) (or-else ?a) (NOT (not-yet ?a)) (and-upper ?A)
                       (forall-x ?a) (exists-x ?a) (when-x ?a) (increase ?a))
    :EFFECT (and (not (at ?a ?p)) (AND-GATE ?a))))
"""

KEYWORDS_PROBLEM = """\
(define (problem P1) (:domain KEYS)
  (:objects either-x and-x define - aircraft Home - place)
  (:init (at either-x home) (and-gate and-x) (AT define HOME))
  (:goal (and (not (at either-x home)))))
"""


@pytest.fixture
def keys(write):
    return read(write("keys.pddl", KEYWORDS_DOMAIN), write("keys-p.pddl", KEYWORDS_PROBLEM))


# --------------------------------------------------------------- names
def test_predicate_named_at_is_a_predicate(keys):
    domain, problem = keys
    at = domain.predicate("at")
    assert at is not None and [p.name for p in at.parameters] == ["?x", "?p"]
    assert m.Atom("at", ("either-x", "home")) in problem.init


@pytest.mark.parametrize(
    "name", ["and-gate", "or-else", "not-yet", "and-upper", "forall-x", "exists-x", "when-x", "increase"]
)
def test_names_that_begin_like_keywords_are_predicates(keys, name):
    domain, _ = keys
    assert domain.predicate(name) is not None
    pre = domain.action("foo").precondition
    assert isinstance(pre, m.And)
    atoms = {p.predicate if isinstance(p, m.Atom) else p.part.predicate for p in pre.parts}
    assert name in atoms


def test_objects_named_like_keywords_are_objects(keys):
    _, problem = keys
    assert [(o.name, o.types) for o in problem.objects] == [
        ("either-x", ("aircraft",)),
        ("and-x", ("aircraft",)),
        ("define", ("aircraft",)),
        ("home", ("place",)),
    ]
    assert m.Atom("and-gate", ("and-x",)) in problem.init


def test_type_named_like_either_is_a_type(keys):
    domain, _ = keys
    assert "either-y" in domain.type_parents


def test_letter_case_is_folded_to_lower_case(keys):
    domain, problem = keys
    assert domain.name == "keys"
    assert domain.requirements == (":strips", ":typing")
    assert [a.name for a in domain.actions] == ["foo"]
    assert [(p.name, p.types) for p in domain.action("foo").parameters] == [
        ("?a", ("aircraft",)),
        ("?p", ("place",)),
    ]
    assert problem.name == "p1" and problem.domain_name == "keys"
    assert m.Atom("at", ("define", "home")) in problem.init
    eff = domain.action("foo").effect
    assert m.Literal(m.Atom("and-gate", ("?a",))) in eff.parts


def test_variable_glued_to_a_type_name_is_split(keys):
    """`?A - aircraft?P - place`: zenotravel writes `(aircraft?a)` the same way."""
    domain, _ = keys
    assert [p.name for p in domain.action("foo").parameters] == ["?a", "?p"]


def test_variable_glued_to_a_predicate_name_is_split():
    text = (
        "(define (domain z) (:predicates (aircraft ?a) (done))"
        " (:action fly :parameters (?a) :precondition (aircraft?a) :effect (done)))"
    )
    domain = parse(text, "z.pddl")
    assert domain.action("fly").precondition == m.Atom("aircraft", ("?a",))


def test_either_types_in_parameters_and_predicates(keys):
    domain, _ = keys
    assert domain.predicate("at").parameters[0].types == ("vehicle", "either-y")
    text = (
        "(define (domain e) (:requirements :typing) (:types a b c)"
        " (:predicates (p ?x - (either a b)))"
        " (:action go :parameters (?x - (EITHER a b) ?y - c) :precondition (p ?x) :effect (not (p ?x))))"
    )
    domain = parse(text, "e.pddl")
    assert [(p.name, p.types) for p in domain.action("go").parameters] == [("?x", ("a", "b")), ("?y", ("c",))]
    assert domain.action("go").parameters[0].type_text == "(either a b)"


# -------------------------------------------------------------- layout
def test_comments_anywhere_are_ignored():
    text = (
        "; header ( with an open paren\n"
        "(define (domain c) ; name )\n"
        "  (:predicates ; the facts\n"
        "     (p ?x) ; one\n"
        "     (q))\n"
        "  (:action a ; an action\n"
        "    :parameters (?x) ; its parameter\n"
        "    :precondition (p ?x)\n"
        "    :effect (q)))\n"
        "; trailer without a newline"
    )
    domain = parse(text, "c.pddl")
    assert [p.name for p in domain.predicates] == ["p", "q"]
    assert domain.action("a").precondition == m.Atom("p", ("?x",))


def test_crlf_and_tabs_are_read_with_the_same_positions(position):
    text = (
        "(define (domain w)\n"
        "\t(:predicates (p) (q))\n"
        "\t(:action a :parameters () :precondition (r) :effect (q)))\n"
    )
    lf = parse(text, "w.pddl")
    crlf = parse(text.replace("\n", "\r\n"), "w.pddl")
    assert lf == crlf
    assert crlf.action("a").precondition.pos == m.Pos(*position(text, "r) :effect"))


def test_several_objects_sections_are_merged():
    problem = parse(
        "(define (problem p) (:domain d) (:objects a - t) (:objects b c - u) (:init) (:goal (and)))"
    )
    assert [(o.name, o.types) for o in problem.objects] == [("a", ("t",)), ("b", ("u",)), ("c", ("u",))]


def test_untyped_names_are_objects():
    domain = parse("(define (domain u) (:predicates (p ?x ?y)))")
    assert [p.types for p in domain.predicate("p").parameters] == [("object",), ("object",)]


def test_equality_is_a_built_in_predicate(write):
    path = write(
        "eq.pddl",
        "(define (domain eq) (:requirements :equality) (:constants home) (:predicates (at ?x))"
        " (:action go :parameters (?x) :precondition (not (= ?x home)) :effect (at ?x)))",
    )
    domain = read_domain(path)
    assert domain.action("go").precondition == m.Not(m.Atom("=", ("?x", "home")))


# ---------------------------------------------------------- extensions
EXT_DOMAIN = """\
(define (domain ext)
  (:requirements :typing :action-costs :probabilities :assumptions :strata)
  (:types item room)
  (:predicates (in ?o - item ?r - room) (known ?o - item) (held ?o - item))
  (:functions (total-cost) - number (p-in ?o - item ?r - room) - number)
  (:action grab
    :parameters (?o - item ?r - room)
    :probability 0.9
    :stratum 2
    :precondition (in ?o ?r)
    :effect (and (held ?o) (increase (total-cost) 3)))
  (:action look
    :parameters (?r - room)
    :effect (and))
  (:assumption guess
    :parameters (?o - item ?r - room)
    :probability (p-in ?o ?r)
    :precondition (not (known ?o))
    :effect (and (in ?o ?r) (known ?o))))
"""

EXT_PROBLEM = """\
(define (problem extp) (:domain ext)
  (:objects r1 r2 - room)
  (:virtual-objects new1 new2 - item)
  (:init (= (p-in new1 r1) 0.4) (= (p-in new2 r2) 0.5))
  (:goal (held new1))
  (:goal-reward 500))
"""


@pytest.fixture
def ext(write):
    return read(write("ext.pddl", EXT_DOMAIN), write("ext-p.pddl", EXT_PROBLEM))


def test_probability_number_lands_on_the_action(ext, position):
    domain, _ = ext
    assert domain.action("grab").probability == 0.9
    assert domain.action("grab").probability_pos == m.Pos(*position(EXT_DOMAIN, "0.9"))


def test_probability_function_lands_as_a_function_term(ext, position):
    domain, _ = ext
    guess = domain.action("guess")
    assert guess.probability == m.FunctionTerm("p-in", ("?o", "?r"))
    assert guess.probability.pos == m.Pos(*position(EXT_DOMAIN, "p-in ?o ?r)"))


def test_stratum_lands_on_the_action(ext):
    domain, _ = ext
    assert domain.action("grab").stratum == 2
    assert domain.strata == (1, 2)


def test_defaults_are_probability_one_and_stratum_one(ext):
    domain, problem = ext
    look = domain.action("look")
    assert (look.probability, look.stratum, look.is_assumption) == (1.0, 1, False)
    no_reward = parse("(define (problem q) (:domain ext) (:objects r - room) (:init) (:goal (and)))")
    assert no_reward.goal_reward is None and no_reward.virtual_objects == ()


def test_assumption_is_an_action_marked_as_assumption(ext):
    domain, _ = ext
    guess = domain.action("guess")
    assert guess.is_assumption and not domain.action("grab").is_assumption
    assert guess.precondition == m.Not(m.Atom("known", ("?o",)))
    assert guess.effect == m.AndEffect(
        (m.Literal(m.Atom("in", ("?o", "?r"))), m.Literal(m.Atom("known", ("?o",))))
    )


def test_virtual_objects_and_goal_reward_land_on_the_problem(ext):
    _, problem = ext
    assert [(o.name, o.types) for o in problem.virtual_objects] == [("new1", ("item",)), ("new2", ("item",))]
    assert [o.name for o in problem.objects] == ["r1", "r2"]
    assert [o.name for o in problem.all_objects] == ["r1", "r2", "new1", "new2"]
    assert problem.goal_reward == 500
    assert problem.value_table() == {"p-in": {("new1", "r1"): 0.4, ("new2", "r2"): 0.5}}


def test_cost_effect_is_kept_as_an_increase(ext):
    domain, _ = ext
    parts = domain.action("grab").effect.parts
    assert m.Increase(m.FunctionTerm("total-cost", ()), 3.0) in parts


@pytest.mark.parametrize(("written", "value"), [("0.5", 0.5), (".5", 0.5), ("5e-1", 0.5), ("1", 1.0)])
def test_probability_number_forms(written, value):
    text = (
        f"(define (domain n) (:predicates (q)) (:action a :parameters () :probability {written} :effect (q)))"
    )
    assert parse(text).action("a").probability == value


# --------------------------------------------------------------- the API
def test_read_without_a_problem_gives_none(write):
    domain, problem = read(write("ext.pddl", EXT_DOMAIN))
    assert problem is None and domain.name == "ext"


def test_read_problem_checks_against_the_given_domain(write):
    domain = read_domain(write("ext.pddl", EXT_DOMAIN))
    problem = read_problem(write("ext-p.pddl", EXT_PROBLEM), domain)
    assert problem.name == "extp" and problem.path.endswith("ext-p.pddl")


def test_parse_does_not_check(write, position):
    """`parse` builds the model only; `read_domain` runs the checks."""
    text = "(define (domain u) (:predicates (p)) (:action a :parameters () :precondition (nope) :effect (p)))"
    assert parse(text, "u.pddl").action("a").precondition == m.Atom("nope", ())
    with pytest.raises(PddlError) as caught:
        read_domain(write("u.pddl", text))
    assert [(d.line, d.col) for d in caught.value.diagnostics] == [position(text, "nope")]


def test_pddl_error_is_an_input_error_with_diagnostics(write, position):
    text = "(define (domain b) (:predicates (p)"
    with pytest.raises(InputError) as caught:
        read_domain(write("bad.pddl", text))
    assert isinstance(caught.value, PddlError)
    (d,) = caught.value.diagnostics
    # Two parens are left open; the innermost, `(:predicates`, is the one reported.
    assert (d.line, d.col, d.warning) == (*position(text, "(:predicates"), False)
    assert d.path.endswith("bad.pddl")


def test_diagnostic_prints_as_path_line_col_message():
    assert str(Diagnostic("f.pddl", 3, 7, "bad thing")) == "f.pddl:3:7: bad thing"
    assert str(Diagnostic("f.pddl", 3, 7, "odd thing", warning=True)) == "f.pddl:3:7: warning: odd thing"
    assert str(Diagnostic("f.pddl", None, None, "no such file")) == "f.pddl: no such file"
