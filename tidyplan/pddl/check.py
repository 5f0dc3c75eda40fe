"""Semantic checks: what the grammar cannot say (docs/dialect.md).

Every check adds a `Diagnostic` with the place it concerns, so a file with
several mistakes gets one line for each. Warnings (an extension used without
its requirement flag) do not stop reading.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from tidyplan.errors import Diagnostic
from tidyplan.pddl import model as m
from tidyplan.pddl.derived import NotStratified, strata

KNOWN_REQUIREMENTS = frozenset(
    ":strips :typing :negative-preconditions :disjunctive-preconditions :equality "
    ":existential-preconditions :universal-preconditions :quantified-preconditions "
    ":conditional-effects :adl :action-costs :constants :numeric-fluents :fluents "
    ":object-fluents :derived-predicates :probabilities :assumptions :strata".split()
)
COST = "total-cost"


class _Checker:
    def __init__(self, path: str, domain: m.Domain) -> None:
        self.path = path
        self.domain = domain
        self.out: list[Diagnostic] = []
        self.types = set(domain.type_parents)
        self.constants = {c.name for c in domain.constants}

    def error(self, pos: m.Pos, message: str) -> None:
        self.out.append(Diagnostic(self.path, pos.line or None, pos.col or None, message))

    def warn(self, pos: m.Pos, message: str) -> None:
        self.out.append(Diagnostic(self.path, pos.line or None, pos.col or None, message, warning=True))

    # -------------------------------------------------------------- pieces
    def typed(self, items: Iterable[m.Typed], what: str) -> None:
        for item in items:
            for t in item.types:
                if t not in self.types:
                    self.error(item.pos, f"undeclared type '{t}' of {what} '{item.name}'")

    def atom(self, atom: m.Atom, scope: set[str], objects: set[str]) -> None:
        if atom.predicate == "=":
            arity = 2
        else:
            decl = self.domain.predicate(atom.predicate)
            if decl is None:
                self.error(atom.pos, f"undeclared predicate '{atom.predicate}'")
                return
            arity = len(decl.parameters)
        if len(atom.args) != arity:
            self.error(
                atom.pos,
                f"'{atom.predicate}' takes {arity} argument{'s' * (arity != 1)}, given {len(atom.args)}",
            )
        self.terms(atom.args, atom.pos, scope, objects)

    def terms(self, args: Iterable[str], pos: m.Pos, scope: set[str], objects: set[str]) -> None:
        for a in args:
            if a.startswith("?"):
                if a not in scope:
                    self.error(pos, f"undeclared variable '{a}'")
            elif a not in objects:
                self.error(pos, f"undeclared object '{a}'")

    def function_term(self, term: m.FunctionTerm, scope: set[str], objects: set[str]) -> None:
        decl = self.domain.function(term.name)
        if decl is None:
            self.error(term.pos, f"undeclared function '{term.name}'")
            return
        if len(term.args) != len(decl.parameters):
            n = len(decl.parameters)
            self.error(term.pos, f"'{term.name}' takes {n} argument{'s' * (n != 1)}, given {len(term.args)}")
        self.terms(term.args, term.pos, scope, objects)

    def formula(self, f: m.Formula, scope: set[str], objects: set[str]) -> None:
        if isinstance(f, m.Atom):
            self.atom(f, scope, objects)
        elif isinstance(f, (m.And, m.Or)):
            for part in f.parts:
                self.formula(part, scope, objects)
        elif isinstance(f, m.Not):
            self.formula(f.part, scope, objects)
        elif isinstance(f, m.Imply):
            self.formula(f.condition, scope, objects)
            self.formula(f.consequence, scope, objects)
        else:  # Exists, Forall
            self.typed(f.variables, "variable")
            self.formula(f.body, scope | {v.name for v in f.variables}, objects)

    def effect(self, e: m.Effect, scope: set[str], action: m.Action) -> None:
        if isinstance(e, m.Literal):
            self.atom(e.atom, scope, self.constants)
            if e.atom.predicate == "=":
                self.error(e.atom.pos, "equality cannot be an effect")
            elif e.atom.predicate in self.domain.derived_predicates:
                self.error(
                    e.atom.pos,
                    f"derived predicate '{e.atom.predicate}' cannot be an effect of '{action.name}':"
                    " its rules alone make it true",
                )
        elif isinstance(e, m.AndEffect):
            for part in e.parts:
                self.effect(part, scope, action)
        elif isinstance(e, m.When):
            self.formula(e.condition, scope, self.constants)
            self.effect(e.effect, scope, action)
        elif isinstance(e, m.ForallEffect):
            self.typed(e.variables, "variable")
            self.effect(e.effect, scope | {v.name for v in e.variables}, action)
        else:  # Increase
            if action.is_assumption:
                self.error(e.pos, f"assumption '{action.name}' has a cost effect; assumptions cost nothing")
            if e.target.name != COST:
                self.error(e.target.pos, f"only (increase ({COST}) ...) is supported, not '{e.target.name}'")
            else:
                self.function_term(e.target, scope, self.constants)
            if isinstance(e.amount, m.FunctionTerm):
                self.function_term(e.amount, scope, self.constants)
            elif not math.isfinite(e.amount):  # 1e400 reads as inf: no planner sums it
                self.error(e.pos, f"action cost {e.amount:g} of '{action.name}' is not a finite number")
            elif e.amount < 0:
                self.error(e.pos, f"negative action cost {e.amount:g}")

    # ------------------------------------------------------------- domain
    def check_domain(self) -> list[Diagnostic]:
        d = self.domain
        for r in d.requirements:
            if r not in KNOWN_REQUIREMENTS:
                self.warn(m.NOWHERE, f"unknown requirement '{r}'")
        self.typed(d.types, "type")
        self._type_cycles()
        self.typed(d.constants, "constant")
        for p in d.predicates:
            self.typed(p.parameters, "parameter")
        for f in d.functions:
            self.typed(f.parameters, "parameter")
        self._duplicates(d.predicates, "predicate")
        self._duplicates(d.functions, "function")
        self._duplicates(d.actions, "action")
        for a in d.actions:
            self.action(a)
        for r in d.derived:
            self.derived(r)
        self._flags()
        return self.out

    def derived(self, r: m.Derived) -> None:
        """A rule's head is a declared predicate over distinct variables, typed like an action's
        parameters; its body is checked like a precondition over them."""
        self.typed(r.parameters, "parameter")
        decl = self.domain.predicate(r.predicate)
        if decl is None:
            self.error(r.pos, f"undeclared predicate '{r.predicate}'")
        elif len(decl.parameters) != len(r.parameters):
            n = len(decl.parameters)
            given = len(r.parameters)
            self.error(r.pos, f"'{r.predicate}' takes {n} argument{'s' * (n != 1)}, given {given}")
        names = [p.name for p in r.parameters]
        for p in r.parameters:
            if names.count(p.name) > 1:
                self.error(p.pos, f"variable '{p.name}' twice in the head of derived '{r.predicate}'")
                break
        self.formula(r.body, set(names), self.constants)
        if r is self.domain.derived[-1]:
            try:
                strata(self.domain.derived)
            except NotStratified as e:
                self.error(
                    e.rule.pos,
                    f"derived predicate '{e.rule.predicate}' depends on the negation of '{e.on}',"
                    " which depends on it: the rules are not stratified",
                )

    def action(self, a: m.Action) -> None:
        self.typed(a.parameters, "parameter")
        scope = {p.name for p in a.parameters}
        self.formula(a.precondition, scope, self.constants)
        self.effect(a.effect, scope, a)
        if isinstance(a.probability, m.FunctionTerm):
            self.function_term(a.probability, scope, self.constants)
        elif not 0.0 < a.probability <= 1.0:
            self.error(a.probability_pos, f"probability {a.probability:g} of '{a.name}' is outside (0, 1]")
        if a.stratum < 1:
            self.error(a.stratum_pos, f"stratum of '{a.name}' must be a whole number of at least 1")
        elif a.stratum > m.MAX_STRATUM:
            self.error(a.stratum_pos, f"stratum of '{a.name}' must be at most {m.MAX_STRATUM}")

    def _duplicates(self, items, what: str) -> None:
        seen: set[str] = set()
        for item in items:
            if item.name in seen:
                self.error(item.pos, f"{what} '{item.name}' is declared twice")
            seen.add(item.name)

    def _type_cycles(self) -> None:
        parents = self.domain.type_parents
        for t in self.domain.types:
            if t.name == m.ROOT_TYPE:
                continue
            seen, todo = set(), [t.name]
            while todo:
                cur = todo.pop()
                for p in parents.get(cur, ()):
                    if p == t.name:
                        self.error(t.pos, f"type '{t.name}' is its own ancestor")
                        return
                    if p not in seen:
                        seen.add(p)
                        todo.append(p)

    def _flags(self) -> None:
        d, reqs = self.domain, set(self.domain.requirements)
        uses = {
            ":probabilities": [a for a in d.actions if a.probability != 1.0],
            ":assumptions": [a for a in d.actions if a.is_assumption],
            ":strata": [a for a in d.actions if a.stratum != 1],
        }
        for flag, actions in uses.items():
            if actions and flag not in reqs:
                self.warn(
                    actions[0].pos, f"'{actions[0].name}' uses an extension without the requirement {flag}"
                )


def check_domain(domain: m.Domain) -> list[Diagnostic]:
    return _Checker(domain.path, domain).check_domain()


def check_problem(problem: m.Problem, domain: m.Domain) -> list[Diagnostic]:
    c = _Checker(problem.path, domain)
    if problem.domain_name and problem.domain_name != domain.name:
        c.warn(
            problem.domain_pos, f"problem is for domain '{problem.domain_name}', read with '{domain.name}'"
        )
    c.typed(problem.objects, "object")
    c.typed(problem.virtual_objects, "virtual object")
    objects: dict[str, m.Typed] = {t.name: t for t in domain.constants}
    for o in problem.all_objects:
        if o.name in objects and objects[o.name].types != o.types:
            c.error(o.pos, f"object '{o.name}' is declared twice with different types")
        objects[o.name] = o
    names = set(objects)
    for atom in problem.init:
        c.atom(atom, set(), names)
        if atom.predicate in domain.derived_predicates:
            c.error(
                atom.pos,
                f"derived predicate '{atom.predicate}' cannot be given in :init: its rules derive it",
            )
    for term, value in problem.values:
        if term.name != COST:
            c.function_term(term, set(), names)
        if not math.isfinite(value):
            name = " ".join((term.name, *term.args))
            c.error(term.pos, f"value {value:g} of ({name}) is not a finite number")
    c.formula(problem.goal, set(), names)
    reward = problem.goal_reward
    if reward is not None and not (math.isfinite(reward) and reward > 0):
        c.error(problem.goal_reward_pos, f"goal reward must be a positive finite number, not {reward:g}")
    if problem.virtual_objects and ":assumptions" not in set(domain.requirements) | set(problem.requirements):
        c.warn(problem.virtual_objects[0].pos, "virtual objects without the requirement :assumptions")
    return c.out
