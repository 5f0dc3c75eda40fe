"""Derived predicates (`(:derived ...)`, Fast Downward's axioms): their strata and their closure.

A derived predicate is never an effect and never in `:init`: in every state it holds of exactly
the tuples its rules derive from that state's basic facts. Rules may use derived predicates,
negated ones only where they can be computed first: the rules are *stratified* (PDDL 2.2,
Thiébaux, Hoffmann and Nebel 2005), so the truth of each stratum is the least fixpoint of its
rules over the strata below it, with negation read against those finished strata.

`strata()` orders the predicates (or names the one that cannot be ordered); `close()` adds the
derived facts to a state, stratum by stratum, each by a fixpoint of its rules.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from tidyplan.pddl import model as m


class NotStratified(Exception):
    """A derived predicate depends negatively on itself, through its rules."""

    def __init__(self, rule: m.Derived, on: str) -> None:
        super().__init__(rule.predicate)
        self.rule = rule
        self.on = on


def dependencies(f: m.Formula, derived: frozenset[str], positive: bool = True) -> Iterable[tuple[str, bool]]:
    """(derived predicate, read positively?) for each derived atom of `f`: under a `not` or in
    an `imply`'s condition an atom is read negatively (its growth can make `f` false)."""
    if isinstance(f, m.Atom):
        if f.predicate in derived:
            yield f.predicate, positive
    elif isinstance(f, (m.And, m.Or)):
        for p in f.parts:
            yield from dependencies(p, derived, positive)
    elif isinstance(f, m.Not):
        yield from dependencies(f.part, derived, not positive)
    elif isinstance(f, m.Imply):
        yield from dependencies(f.condition, derived, not positive)
        yield from dependencies(f.consequence, derived, positive)
    else:  # Exists, Forall: monotone in their body
        yield from dependencies(f.body, derived, positive)


def strata(rules: tuple[m.Derived, ...]) -> list[list[str]]:
    """The derived predicates in strata, lowest first: a predicate's stratum is at least that of
    each one its rules read, and above that of each one they read negatively. Raises
    `NotStratified` where no such order exists."""
    derived = frozenset(r.predicate for r in rules)
    level = dict.fromkeys(sorted(derived), 0)
    edges = [(r, d, positive) for r in rules for d, positive in dependencies(r.body, derived)]
    # The least levels with level(head) >= level(dep) (+ 1 when read negatively): at most
    # n - 1 for n predicates where they exist, so a level of n means a cycle through a negation.
    moved = True
    while moved:
        moved = False
        for rule, dep, positive in edges:
            need = level[dep] + (0 if positive else 1)
            if level[rule.predicate] < need:
                if need >= len(derived):
                    raise NotStratified(rule, dep)
                level[rule.predicate] = need
                moved = True
    out: list[list[str]] = [[] for _ in range(max(level.values(), default=-1) + 1)]
    for name, k in level.items():
        out[k].append(name)
    return [s for s in out if s]


Holds = Callable[[m.Formula, set, dict[str, str]], bool]
Bindings = Callable[[tuple[m.Typed, ...]], Iterable[dict[str, str]]]


class Closure:
    """The derived facts of a domain's rules over one problem's objects."""

    def __init__(self, rules: tuple[m.Derived, ...], holds: Holds, bindings: Bindings) -> None:
        by_predicate: dict[str, list[m.Derived]] = {}
        for r in rules:
            by_predicate.setdefault(r.predicate, []).append(r)
        self.predicates = frozenset(by_predicate)
        self._strata = [[r for p in layer for r in by_predicate[p]] for layer in strata(rules)]
        self._holds = holds
        # each rule's ground heads with their bindings, enumerated once
        self._ground = {
            id(r): [(b, (r.predicate, *(b[p.name] for p in r.parameters))) for b in bindings(r.parameters)]
            for r in rules
        }

    def close(self, facts: set[tuple[str, ...]]) -> set[tuple[str, ...]]:
        """`facts` (basic facts; derived ones there are dropped) with every derived fact added, in
        place; returns it."""
        for fact in [f for f in facts if f[0] in self.predicates]:
            facts.discard(fact)
        for layer in self._strata:
            grew = True
            while grew:  # the least fixpoint of this stratum's rules
                grew = False
                for rule in layer:
                    for binding, head in self._ground[id(rule)]:
                        if head not in facts and self._holds(rule.body, facts, binding):
                            facts.add(head)
                            grew = True
        return facts

    def basic(self, facts: Iterable[tuple[str, ...]]) -> frozenset[tuple[str, ...]]:
        """The facts without the derived ones: what actions change."""
        return frozenset(f for f in facts if f[0] not in self.predicates)
