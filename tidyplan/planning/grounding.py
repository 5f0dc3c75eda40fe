"""Ground a compiled task straight into Fast Downward's SAS format, from the model.

Fast Downward's translator is general (axioms, disjunctions, invariant synthesis) and built for
one task per process: at 96 objects it took 3.5-5 s of a replan whose search took 0.3 s, and
unified-planning's conversion before it 3.3 s more (docs/planner.md). The loop's problems stay
in a small fragment (`tidyplan.planning.fragment`), which is grounded here from the model, without text;
a task outside it goes to Fast Downward's translator (`tidyplan.planning.fastdownward.translate`). The
grounding is relaxed reachability from the initial state, as the translator's; each reachable
fluent atom is one binary variable (on the tidy domain the translator's mutex groups made no
difference to the plans or the search time, docs/planner.md); static atoms are evaluated away.

Between replans most ground operators are the same (the map's moves, at their distances):
`Grounder` keeps each one with what it was computed from (its schema, its cost, the static facts
its `forall` conditions match), so a replan makes only those whose part of the map changed; the
reachability from the new state is computed every time.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Iterable

from tidyplan.pddl import model as m
from tidyplan.pddl.simulate import ancestors
from tidyplan.planning import fragment
from tidyplan.planning.fragment import Eff, Fact, Lit, OutsideFragment, Schema, fragment_gap, literals
from tidyplan.planning.sas import Grounded, Operator, final, keep, sas

__all__ = ["Grounded", "Grounder", "Operator", "OutsideFragment", "fragment_gap", "ground", "sas"]


# ---------------------------------------------------------------------- grounding
class _Index:
    """Facts by predicate and by the values at some positions."""

    def __init__(self) -> None:
        self.by_predicate: dict[str, set[tuple[str, ...]]] = {}
        self._tables: dict[tuple[str, tuple[int, ...]], dict[tuple[str, ...], list[tuple[str, ...]]]] = {}

    def add(self, predicate: str, args: tuple[str, ...]) -> bool:
        have = self.by_predicate.setdefault(predicate, set())
        if args in have:
            return False
        have.add(args)
        for (p, at), table in self._tables.items():
            if p == predicate:
                table.setdefault(tuple(args[i] for i in at), []).append(args)
        return True

    def __contains__(self, fact: Fact) -> bool:
        return fact[1:] in self.by_predicate.get(fact[0], ())

    def matching(self, predicate: str, at: tuple[int, ...], values: tuple[str, ...]) -> list[tuple[str, ...]]:
        key = (predicate, at)
        table = self._tables.get(key)
        if table is None:
            table = self._tables[key] = {}
            for args in self.by_predicate.get(predicate, ()):
                table.setdefault(tuple(args[i] for i in at), []).append(args)
        return table.get(values, [])


def _bind(
    literals: Iterable[Lit], binding: dict[str, str], index: _Index, objects, variables
) -> Iterable[dict]:
    """Every extension of `binding` to `variables` under which each positive literal is in
    `index` (joined one at a time, the most bound first); variables no atom binds range over
    their type's objects. Negative literals and equalities are the caller's."""
    todo = [lit for lit in literals if not lit.negated and lit.predicate != "="]

    def step(binding: dict, todo: list[Lit]):
        if not todo:
            free = [v for v in variables if v.name not in binding]
            for values in itertools.product(*(objects.get(v.types[0], ()) for v in free)):
                yield {**binding, **{v.name: o for v, o in zip(free, values, strict=True)}}
            return
        best = max(range(len(todo)), key=lambda i: sum(_bound(a, binding) for a in todo[i].args))
        lit, rest = todo[best], todo[:best] + todo[best + 1 :]
        at = tuple(i for i, a in enumerate(lit.args) if _bound(a, binding))
        values = tuple(binding.get(lit.args[i], lit.args[i]) for i in at)
        for args in index.matching(lit.predicate, at, values):
            extended = dict(binding)
            if all(extended.setdefault(a, v) == v for a, v in zip(lit.args, args, strict=True)):
                yield from step(extended, rest)

    yield from step(binding, todo)


def _bound(arg: str, binding: dict) -> bool:
    return not arg.startswith("?") or arg in binding


def _ground(args: tuple[str, ...], binding: dict) -> tuple[str, ...]:
    return tuple([binding.get(a, a) for a in args])


def _typed(binding: dict, variables, members) -> bool:
    return all(binding[v.name] in members[v.types[0]] for v in variables)


class Grounder:
    """Grounds the tasks of a loop, one after another, keeping each ground operator while what
    it was computed from holds: its schema, its cost, and the static facts its effects look up
    (a `forall`'s condition). The map's moves are the same from one replan to the next; only
    the reachability from the new state is computed again (docs/planner.md)."""

    def __init__(self) -> None:
        # by the names of the domain's actions (each stratum's restriction has its own): the
        # actions, their schemas, and the operators kept
        self._kept: dict[tuple[str, ...], tuple[tuple, tuple[Schema, ...], dict]] = {}
        self.reused = self.made = 0

    def ground(self, domain: m.Domain, problem: m.Problem, deadline: float | None = None) -> Grounded:
        """Relaxed-reachable ground operators of a compiled task (raises OutsideFragment); raises
        OutOfTime once `deadline` (a time.perf_counter() time) has passed."""
        clock = _Clock(deadline)
        names = tuple(a.name for a in domain.actions)
        kept = self._kept.get(names)
        if kept is None or kept[0] != domain.actions:  # the same schemas while the actions are the same
            kept = self._kept[names] = (domain.actions, fragment.schemas(domain), {})
        _, schemas, kept_operators = kept
        goal = literals(problem.goal, "the goal")
        parents = domain.type_parents
        objects: dict[str, list[str]] = {}
        for obj in (*domain.constants, *problem.all_objects):
            for t in ancestors(obj.types, parents):
                objects.setdefault(t, []).append(obj.name)
        members = {t: set(names) for t, names in objects.items()}
        fluent = {e.literal.predicate for s in schemas for e in s.effects}
        values = problem.value_table()
        static, reached = _Index(), _Index()
        init: set[Fact] = set()
        for a in problem.init:
            (reached if a.predicate in fluent else static).add(a.predicate, a.args)
            if a.predicate in fluent:
                init.add((a.predicate, *a.args))
        found = _reachable(schemas, static, reached, fluent, objects, members, clock)
        # What an operator's effects looked up: it is kept while these are the same.
        everything = {(p, *args) for p, have in reached.by_predicate.items() for args in have}
        every_object = tuple((t, tuple(names)) for t, names in sorted(objects.items()))
        over_types = {s.name: _ranges_over_types(s, fluent) for s in schemas}
        guards = {s.name: _guards(s, fluent) for s in schemas}
        operators = []
        self.reused = self.made = 0
        # only this task's operators are kept for the next: what a task no longer reaches (an
        # item's takes once it is put away) would otherwise stay for the whole mission
        # (docs/planner.md: at 96 objects, most of the mission's memory growth)
        now: dict = {}
        for (name, args), (s, b) in found.items():
            clock.tick()
            cost = (0 if s.cost is None else _cost(s, b, values)) if domain.has_costs else 1
            # what its effects look up: the static facts its forall conditions match, for its own
            # arguments (where one item blocks a path, the takes of the others are kept)
            looked = tuple(
                frozenset(static.matching(p, at, _ground(args_of, b))) for p, at, args_of in guards[s.name]
            )
            seen = (s, cost, looked, every_object if over_types[s.name] else None)
            had = kept_operators.get((name, args))
            if had is not None and had[0] == seen:
                generic = had[1]
                self.reused += 1
            else:
                generic = keep(_generic(s, name, args, b, static, fluent, objects, members, cost))
                had = (seen, generic)
                self.made += 1
            now[(name, args)] = had
            op = final(generic, everything) if generic is not None else None
            if op is not None:
                operators.append(op)
        kept_operators.clear()
        kept_operators.update(now)
        goal_facts: list[tuple[Fact, bool]] = []
        unsolvable = False
        for lit in goal:
            if lit.predicate == "=" or lit.predicate not in fluent:
                unsolvable |= not _holds_static(lit, {}, static)
                continue
            fact = (lit.predicate, *lit.args)
            if fact in reached:
                goal_facts.append((fact, not lit.negated))
            elif not lit.negated:
                unsolvable = True
        facts = sorted((p, *args) for p, have in reached.by_predicate.items() for args in have)
        # sorted: the joins follow sets, whose order changes from one process to the next, and the
        # search breaks ties by operator order (the same seed must give the same plan)
        operators.sort(key=lambda op: op.name)
        return Grounded(operators, facts, init, goal_facts, domain.has_costs, unsolvable)


def _guards(s: Schema, fluent) -> list[tuple[str, tuple[int, ...], tuple[str, ...]]]:
    """The static atoms of the schema's effect conditions, each as (predicate, the positions the
    action's own parameters or constants fill, those arguments): what its operators look up."""
    out = []
    for e in s.effects:
        local = {v.name for v in e.variables}
        for x in e.condition:
            if x.predicate not in fluent and x.predicate != "=":
                at = tuple(i for i, a in enumerate(x.args) if a not in local)
                out.append((x.predicate, at, tuple(x.args[i] for i in at)))
    return out


def _ranges_over_types(s: Schema, fluent) -> bool:
    """Has a forall of the schema a variable no static atom of its condition binds (so that its
    instances depend on the objects of its type)?"""
    for e in s.effects:
        bound = {a for x in e.condition if not x.negated and x.predicate not in fluent for a in x.args}
        if any(v.name not in bound for v in e.variables):
            return True
    return False


def ground(domain: m.Domain, problem: m.Problem) -> Grounded:
    """One task, nothing kept."""
    return Grounder().ground(domain, problem)


class OutOfTime(Exception):
    """The grounding reached its deadline."""


class _Clock:
    """A look at the clock every 1024 ticks (a tick is one operator or binding: microseconds)."""

    def __init__(self, deadline: float | None) -> None:
        self.deadline = deadline
        self.n = 0

    def tick(self) -> None:
        self.n += 1
        if self.deadline is not None and not self.n & 1023 and time.perf_counter() >= self.deadline:
            raise OutOfTime


def _reachable(schemas, static, reached, fluent, objects, members, clock: _Clock) -> dict:
    """Relaxed reachability: every operator whose positive preconditions can become true, with
    the facts their add effects reach added to `reached`. A schema is enumerated again only when
    a predicate of its preconditions gained facts; an effect whose condition is not reached yet
    waits for the next round."""

    def ok(lit: Lit, binding: dict) -> bool:
        if lit.predicate == "=" or lit.predicate not in fluent:
            return _holds_static(lit, binding, static)
        return lit.negated or (lit.predicate, *_ground(lit.args, binding)) in reached

    both = _Both(static, reached, fluent)
    found: dict[tuple[str, tuple[str, ...]], tuple[Schema, dict]] = {}
    watched = {
        s.name: sorted({x.predicate for x in s.precondition if not x.negated and x.predicate in fluent})
        for s in schemas
    }
    last: dict[str, tuple[int, ...]] = {}
    waiting: list[tuple[Eff, dict]] = []
    changed = True
    while changed:
        changed = False
        for s in schemas:
            sizes = _sizes(reached, watched[s.name])
            if last.get(s.name) == sizes:
                continue
            last[s.name] = sizes
            names = tuple(p.name for p in s.parameters)
            # the join matched every positive atom: what is left to test
            tests = [
                x for x in s.precondition if x.predicate == "=" or (x.negated and x.predicate not in fluent)
            ]
            bindings = []
            for b in _bind(s.precondition, {}, both, objects, s.parameters):
                clock.tick()
                bindings.append(b)
            for b in bindings:
                clock.tick()
                key = (s.name, _ground(names, b))
                if key in found or not _typed(b, s.parameters, members):
                    continue
                if not all(ok(x, b) for x in tests):
                    continue
                found[key] = (s, b)
                for e in s.effects:
                    if not e.literal.negated:
                        waiting += ((e, eb) for eb in _effect_bindings(e, b, both, objects, members, True))
        still = []
        for e, eb in waiting:
            if all(ok(x, eb) for x in e.condition):
                changed |= reached.add(e.literal.predicate, _ground(e.literal.args, eb))
            else:
                still.append((e, eb))
        waiting = still
        if not changed:
            # a new fact may let a schema bind more, though no waiting effect changed anything
            changed = any(last.get(s.name) != _sizes(reached, watched[s.name]) for s in schemas)
    return found


def _sizes(index: _Index, predicates) -> tuple[int, ...]:
    return tuple(len(index.by_predicate.get(p, ())) for p in predicates)


class _Both:
    """The static and the reached facts as one index, for joins."""

    def __init__(self, static: _Index, reached: _Index, fluent: set[str]) -> None:
        self.static, self.reached, self.fluent = static, reached, fluent

    def matching(self, predicate, at, values):
        return (self.reached if predicate in self.fluent else self.static).matching(predicate, at, values)


def _effect_bindings(e: Eff, binding: dict, index, objects, members, static_only=False) -> Iterable[dict]:
    if not e.variables:
        yield binding
        return
    # The forall's variables: bound by its condition's positive atoms where it has them (only
    # its static ones for an operator kept across states: the fluent ones are conditions).
    condition = [x for x in e.condition if x.predicate not in index.fluent] if static_only else e.condition
    for b in _bind(condition, binding, index, objects, e.variables):
        if _typed(b, e.variables, members):
            yield b


def _generic(s, name, args, b, static, fluent, objects, members, cost) -> Operator | None:
    """The operator with its static parts evaluated; its fluent facts all kept (`_finalize`
    drops those the current state cannot reach)."""
    pre: dict[Fact, bool] = {}
    for lit in s.precondition:
        if lit.predicate == "=" or lit.predicate not in fluent:
            continue  # held in the relaxed search; static, so held here too
        fact = (lit.predicate, *_ground(lit.args, b))
        if pre.get(fact, not lit.negated) != (not lit.negated):
            return None  # requires a fact and its negation
        pre[fact] = not lit.negated
    both = _Both(static, _Index(), fluent)
    effects: list[tuple[list, Fact, bool]] = []
    for e in s.effects:
        for eb in _effect_bindings(e, b, both, objects, members, static_only=True):
            condition = []
            for lit in e.condition:
                if lit.predicate == "=" or lit.predicate not in fluent:
                    if not _holds_static(lit, eb, static):
                        break
                else:
                    condition.append(((lit.predicate, *_ground(lit.args, eb)), not lit.negated))
            else:
                effects.append(
                    (condition, (e.literal.predicate, *_ground(e.literal.args, eb)), not e.literal.negated)
                )
    return Operator(" ".join((name, *args)), sorted(pre.items()), effects, cost)


def _holds_static(lit: Lit, binding: dict, static: _Index) -> bool:
    args = _ground(lit.args, binding)
    if lit.predicate == "=":
        return (args[0] == args[1]) != lit.negated
    return ((lit.predicate, *args) in static) != lit.negated


def _cost(s: Schema, b: dict, values) -> int:
    if isinstance(s.cost, m.FunctionTerm):
        args = _ground(s.cost.args, b)
        try:
            amount = values[s.cost.name][args]
        except KeyError:
            raise OutsideFragment(f"no value for ({s.cost.name} {' '.join(args)})") from None
    else:
        amount = s.cost
    if amount != int(amount) or amount < 0:
        raise OutsideFragment(f"action {s.name}: cost {amount} is not a natural number")
    return int(amount)
