"""Fold static flags into the conditions before a planner sees them.

A static flag is a predicate without parameters that no action (nor assumption)
adds or deletes: its truth is the problem's :init for the whole plan. Each
precondition, `when` condition and the goal is simplified with those truth values
(an empty `or` is false, an empty `and` true, flags or not); an action whose
precondition becomes false is left out, and a goal that does becomes an atom no
action adds (PDDL cannot write `false`).

Why: a domain may switch an encoding on and off with such a flag, as `tidy.pddl`
does with `(shortest-paths)`. Left for Fast Downward, the `or` that tests the
flag is split into several operators (and its `exists` into axioms) even where
the flag is false, and that alone changes LAMA's plans; folded here, a problem
without the flag compiles to exactly the domain without the switch.
"""

from __future__ import annotations

from dataclasses import replace

from tidyplan.pddl import model as m


def static_flags(domain: m.Domain, problem: m.Problem) -> dict[str, bool]:
    """Each static flag of the domain and its truth value in the problem."""
    changed: set[str] = set()
    for a in domain.actions:
        _effect_predicates(a.effect, changed)
    changed |= domain.derived_predicates  # rules make them, state by state
    init = {atom.predicate for atom in problem.init if not atom.args}
    return {p.name: p.name in init for p in domain.predicates if not p.parameters and p.name not in changed}


def fold(domain: m.Domain, problem: m.Problem) -> tuple[m.Domain, m.Problem]:
    """The domain and problem with every static flag replaced by its value, and the conditions
    simplified (an empty `or` is false, an empty `and` true, as written or as left by a flag)."""
    flags = static_flags(domain, problem)
    actions = []
    for a in domain.actions:
        pre = simplify(a.precondition, flags)
        if pre is not False:
            actions.append(replace(a, precondition=_formula(pre), effect=_effect(a.effect, flags)))
    goal = simplify(problem.goal, flags)
    derived = []
    for r in domain.derived:
        body = simplify(r.body, flags)
        if body is not False:  # a rule that can never fire derives nothing
            derived.append(replace(r, body=_formula(body)))
    used: set[str] = set()
    for f in [problem.goal if goal is False else _formula(goal)] + [a.precondition for a in actions]:
        _formula_predicates(f, used)
    for r in derived:
        _formula_predicates(r.body, used)
    for a in actions:
        _effect_predicates(a.effect, used, conditions=True)
    gone = set(flags) - used  # a flag left only under a quantifier stays declared
    predicates = tuple(p for p in domain.predicates if p.name not in gone)
    if goal is False:
        # PDDL cannot write `false`: a goal no action adds says the same to any planner
        name = "impossible-goal"
        while domain.predicate(name) is not None:
            name += "-"
        predicates += (m.Predicate(name, ()),)
        goal = m.Atom(name, ())
    domain = replace(domain, actions=tuple(actions), predicates=predicates, derived=tuple(derived))
    problem = replace(
        problem,
        init=tuple(a for a in problem.init if a.args or a.predicate not in gone),
        goal=_formula(goal),
    )
    return domain, problem


def _formula(value: m.Formula | bool) -> m.Formula:
    return m.TRUE if value is True else value  # never False: callers leave that out


def simplify(f: m.Formula, flags: dict[str, bool]) -> m.Formula | bool:
    """`f` with the flags' values put in; True or False where that decides it."""
    if isinstance(f, m.Atom):
        return flags[f.predicate] if not f.args and f.predicate in flags else f
    if isinstance(f, m.Not):
        part = simplify(f.part, flags)
        return (not part) if isinstance(part, bool) else m.Not(part)
    if isinstance(f, (m.And, m.Or)):
        absorbing = isinstance(f, m.Or)  # True decides an `or`, False an `and`
        parts = []
        for p in f.parts:
            value = simplify(p, flags)
            if value is absorbing:
                return absorbing
            if value is not (not absorbing):
                parts.append(value)
        if not parts:
            return not absorbing
        return type(f)(tuple(parts))
    if isinstance(f, m.Imply):
        condition = simplify(f.condition, flags)
        if condition is False:
            return True
        consequence = simplify(f.consequence, flags)
        if condition is True or consequence is True:
            return consequence
        if consequence is False:
            return m.Not(condition)
        return m.Imply(condition, consequence)
    body = simplify(f.body, flags)
    if isinstance(f, m.Exists) and body is False:
        return False
    if isinstance(f, m.Forall) and body is True:
        return True
    # `exists` of a true body, `forall` of a false one: true or false as the type has objects,
    # and PDDL has no `true` or `false` to write in the body: left as it was
    return f if isinstance(body, bool) else replace(f, body=body)


def _effect(e: m.Effect, flags: dict[str, bool]) -> m.Effect:
    """`e` with its `when` conditions simplified: one that is false is left out."""
    if isinstance(e, m.AndEffect):
        return m.AndEffect(tuple(_effect(p, flags) for p in e.parts))
    if isinstance(e, m.ForallEffect):
        return replace(e, effect=_effect(e.effect, flags))
    if isinstance(e, m.When):
        condition = simplify(e.condition, flags)
        if condition is False:
            return m.NO_EFFECT
        inner = _effect(e.effect, flags)
        return inner if condition is True else m.When(condition, inner)
    return e


def changed_predicates(domain: m.Domain) -> set[str]:
    """The predicates some action (not an assumption) adds or deletes: the rest are static."""
    out: set[str] = set()
    for a in domain.actions:
        if not a.is_assumption:
            _effect_predicates(a.effect, out)
    return out


def _effect_predicates(e: m.Effect, out: set[str], conditions: bool = False) -> None:
    """The predicates `e` changes; with `conditions`, those its `when` tests too."""
    if isinstance(e, m.Literal):
        out.add(e.atom.predicate)
    elif isinstance(e, m.AndEffect):
        for p in e.parts:
            _effect_predicates(p, out, conditions)
    elif isinstance(e, (m.When, m.ForallEffect)):
        if conditions and isinstance(e, m.When):
            _formula_predicates(e.condition, out)
        _effect_predicates(e.effect, out, conditions)


def _formula_predicates(f: m.Formula, out: set[str]) -> None:
    def note(atom: m.Atom) -> m.Atom:
        out.add(atom.predicate)
        return atom

    m.map_formula(f, note, lambda q, body: q)
