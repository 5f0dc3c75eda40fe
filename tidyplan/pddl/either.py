"""Compile `either` types away, for engines that know single types only.

unified-planning gives each parameter one type. A parameter `?v - (either
truck plane)` becomes `?v - object` plus the condition that `?v` is a truck or
a plane, tested through a static predicate `is-truck` true of every truck
(subtypes included), written into :init. Quantified variables get the same
condition: inside `exists`, as a conjunct; inside `forall`, as an antecedent;
on a universal effect, as a `when`.
"""

from __future__ import annotations

from dataclasses import replace

from tidyplan.pddl import model as m


def _either_types(domain: m.Domain, problem: m.Problem) -> set[str]:
    found: set[str] = set()

    def note(items):
        for t in items:
            if len(t.types) > 1:
                found.update(t.types)

    for a in domain.actions:
        note(a.parameters)
        _walk_formula(a.precondition, note)
        _walk_effect(a.effect, note)
    for r in domain.derived:
        note(r.parameters)
        _walk_formula(r.body, note)
    _walk_formula(problem.goal, note)
    return found


def _walk_formula(f: m.Formula, note) -> None:
    if isinstance(f, (m.And, m.Or)):
        for p in f.parts:
            _walk_formula(p, note)
    elif isinstance(f, m.Not):
        _walk_formula(f.part, note)
    elif isinstance(f, m.Imply):
        _walk_formula(f.condition, note)
        _walk_formula(f.consequence, note)
    elif isinstance(f, (m.Exists, m.Forall)):
        note(f.variables)
        _walk_formula(f.body, note)


def _walk_effect(e: m.Effect, note) -> None:
    if isinstance(e, m.AndEffect):
        for p in e.parts:
            _walk_effect(p, note)
    elif isinstance(e, m.When):
        _walk_formula(e.condition, note)
        _walk_effect(e.effect, note)
    elif isinstance(e, m.ForallEffect):
        note(e.variables)
        _walk_effect(e.effect, note)


class _Rewrite:
    def __init__(self, predicate_of: dict[str, str]) -> None:
        self.predicate_of = predicate_of

    def plain(self, items: tuple[m.Typed, ...]) -> tuple[tuple[m.Typed, ...], list[m.Formula]]:
        """The variables with single types, and the membership conditions they need."""
        out, conditions = [], []
        for t in items:
            if len(t.types) > 1:
                conditions.append(m.Or(tuple(m.Atom(self.predicate_of[x], (t.name,)) for x in t.types)))
                t = replace(t, types=(m.ROOT_TYPE,))
            out.append(t)
        return tuple(out), conditions

    def formula(self, f: m.Formula) -> m.Formula:
        return m.map_formula(f, lambda a: a, self._quantified)

    def _quantified(self, q: m.Exists | m.Forall, body: m.Formula) -> m.Formula:
        variables, conditions = self.plain(q.variables)
        if not conditions:
            return type(q)(variables, body)
        if isinstance(q, m.Exists):
            return m.Exists(variables, m.And((*conditions, body)))
        return m.Forall(variables, m.Imply(m.And(tuple(conditions)), body))

    def effect(self, e: m.Effect) -> m.Effect:
        if isinstance(e, m.AndEffect):
            return m.AndEffect(tuple(self.effect(p) for p in e.parts))
        if isinstance(e, m.When):
            return m.When(self.formula(e.condition), self.effect(e.effect))
        if isinstance(e, m.ForallEffect):
            variables, conditions = self.plain(e.variables)
            inner = self.effect(e.effect)
            return m.ForallEffect(variables, m.When(m.And(tuple(conditions)), inner) if conditions else inner)
        return e

    def action(self, a: m.Action) -> m.Action:
        params, conditions = self.plain(a.parameters)
        pre = self.formula(a.precondition)
        if conditions:
            pre = m.And((*conditions, pre))
        return replace(a, parameters=params, precondition=pre, effect=self.effect(a.effect))

    def derived(self, r: m.Derived) -> m.Derived:
        params, conditions = self.plain(r.parameters)
        body = self.formula(r.body)
        return replace(r, parameters=params, body=m.And((*conditions, body)) if conditions else body)


def _is_a(type_name: str, ancestor: str, parents: dict[str, tuple[str, ...]]) -> bool:
    todo, seen = [type_name], set()
    while todo:
        t = todo.pop()
        if t == ancestor:
            return True
        if t not in seen:
            seen.add(t)
            todo.extend(parents.get(t, ()))
    return False


def compile_either(domain: m.Domain, problem: m.Problem) -> tuple[m.Domain, m.Problem]:
    """The same task with every `either` replaced by a membership condition."""
    types = _either_types(domain, problem)
    if not types:
        return domain, problem
    taken = {p.name for p in domain.predicates} | set(domain.type_parents)
    predicate_of: dict[str, str] = {}
    for t in sorted(types):
        name, n = f"is-{t}", 2
        while name in taken:
            name, n = f"is-{t}-{n}", n + 1
        taken.add(name)
        predicate_of[t] = name
    parents = domain.type_parents
    rewrite = _Rewrite(predicate_of)
    single = lambda items: tuple(replace(t, types=(m.ROOT_TYPE,)) if len(t.types) > 1 else t for t in items)  # noqa: E731
    new_domain = replace(
        domain,
        predicates=tuple(replace(p, parameters=single(p.parameters)) for p in domain.predicates)
        + tuple(m.Predicate(p, (m.Typed("?x"),)) for p in predicate_of.values()),
        functions=tuple(replace(f, parameters=single(f.parameters)) for f in domain.functions),
        actions=tuple(rewrite.action(a) for a in domain.actions),
        derived=tuple(rewrite.derived(r) for r in domain.derived),
    )
    facts = tuple(
        m.Atom(predicate_of[t], (o.name,))
        for o in domain.constants + problem.all_objects
        for t in sorted(types)
        if any(_is_a(own, t, parents) for own in o.types)
    )
    new_problem = replace(problem, init=problem.init + facts, goal=rewrite.formula(problem.goal))
    return new_domain, new_problem
