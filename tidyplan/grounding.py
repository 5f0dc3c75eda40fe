"""Ground a compiled task straight into Fast Downward's SAS format, from the model.

Fast Downward's translator is general (axioms, disjunctions, invariant synthesis) and built for
one task per process: at 96 objects it took 3.5-5 s of a replan whose search took 0.3 s, and
unified-planning's conversion before it 3.3 s more (docs/planner.md). The loop's problems stay
in a small fragment, which is grounded here from the model, without text:

- preconditions, effect conditions and goals: conjunctions of atoms, negated atoms, equalities;
- effects: literals, `when`, `forall` (its condition's static atoms are looked up, not
  enumerated), `(increase (total-cost) n)` with n a number or a static function;
- typing with single types (the compiler removes `either`).

`fragment_gap` says why a task is outside it; the planner then hands the PDDL text to Fast
Downward's translator (`tidyplan.fastdownward.translate`). The grounding is relaxed reachability
from the initial state, as the translator's; each reachable fluent atom is one binary variable
(on the tidy domain the translator's mutex groups made no difference to the plans or the search
time, docs/planner.md); static atoms are evaluated away.

Between replans, the bindings of each action's static preconditions (the map: paths, distances,
what blocks what) are the same unless those facts changed: `Grounder` keeps them, keyed by the
static facts they were computed from, so a replan grounds only what the new state reaches.
"""

from __future__ import annotations

import io
import itertools
from collections.abc import Iterable
from dataclasses import dataclass

from .pddl import model as m

Fact = tuple[str, ...]  # (predicate, arg, ...)


class OutsideFragment(Exception):
    """The task uses something this grounder does not (the translator is used instead)."""


@dataclass(frozen=True, slots=True)
class _Lit:
    predicate: str
    args: tuple[str, ...]
    negated: bool


@dataclass(frozen=True, slots=True)
class _Eff:
    variables: tuple[m.Typed, ...]  # a forall's, else ()
    condition: tuple[_Lit, ...]
    literal: _Lit


@dataclass(frozen=True, slots=True)
class _Schema:
    name: str
    parameters: tuple[m.Typed, ...]
    precondition: tuple[_Lit, ...]
    effects: tuple[_Eff, ...]
    cost: float | m.FunctionTerm | None


# ---------------------------------------------------------------------- the fragment
def _literals(f: m.Formula, where: str) -> tuple[_Lit, ...]:
    if isinstance(f, m.Atom):
        return (_Lit(f.predicate, f.args, False),)
    if isinstance(f, m.Not) and isinstance(f.part, m.Atom):
        return (_Lit(f.part.predicate, f.part.args, True),)
    if isinstance(f, m.And):
        return tuple(x for p in f.parts for x in _literals(p, where))
    raise OutsideFragment(f"{where}: {type(f).__name__.lower()} is not a conjunction of literals")


def _effects(e: m.Effect, where: str, variables=(), condition=()) -> tuple[list[_Eff], list]:
    out: list[_Eff] = []
    costs: list = []
    if isinstance(e, m.Literal):
        out.append(_Eff(tuple(variables), tuple(condition), _Lit(e.atom.predicate, e.atom.args, e.negated)))
    elif isinstance(e, m.AndEffect):
        for part in e.parts:
            o, c = _effects(part, where, variables, condition)
            out += o
            costs += c
    elif isinstance(e, m.When):
        o, c = _effects(e.effect, where, variables, (*condition, *_literals(e.condition, where)))
        if c:
            raise OutsideFragment(f"{where}: a conditional cost")
        out += o
    elif isinstance(e, m.ForallEffect):
        if any(len(v.types) != 1 for v in e.variables):
            raise OutsideFragment(f"{where}: an either type")
        o, c = _effects(e.effect, where, (*variables, *e.variables), condition)
        if c:
            raise OutsideFragment(f"{where}: a cost under forall")
        out += o
    elif isinstance(e, m.Increase):
        if e.target.name != "total-cost" or variables or condition:
            raise OutsideFragment(f"{where}: a numeric effect other than total-cost")
        costs.append(e.amount)
    else:
        raise OutsideFragment(f"{where}: effect {type(e).__name__}")
    return out, costs


def _schemas(domain: m.Domain) -> tuple[_Schema, ...]:
    out = []
    for a in domain.actions:
        where = f"action {a.name}"
        if any(len(p.types) != 1 for p in a.parameters):
            raise OutsideFragment(f"{where}: an either type")
        effects, costs = _effects(a.effect, where)
        if len(costs) > 1:
            raise OutsideFragment(f"{where}: two cost increases")
        out.append(_Schema(a.name, a.parameters, _literals(a.precondition, where), tuple(effects),
                           costs[0] if costs else None))  # fmt: skip
    return tuple(out)


def fragment_gap(domain: m.Domain, problem: m.Problem) -> str | None:
    """Why the task is outside the grounder's fragment, or None."""
    try:
        _schemas(domain)
        _literals(problem.goal, "the goal")
    except OutsideFragment as e:
        return str(e)
    return None


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
    literals: Iterable[_Lit], binding: dict[str, str], index: _Index, objects, variables
) -> Iterable[dict]:
    """Every extension of `binding` to `variables` under which each positive literal is in
    `index` (joined one at a time, the most bound first); variables no atom binds range over
    their type's objects. Negative literals and equalities are the caller's."""
    todo = [lit for lit in literals if not lit.negated and lit.predicate != "="]

    def step(binding: dict, todo: list[_Lit]):
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


@dataclass
class Operator:
    name: str  # "action arg ..."
    precondition: list[tuple[Fact, bool]]  # (fluent fact, required value)
    effects: list[tuple[list[tuple[Fact, bool]], Fact, bool]]  # (condition, fact, value set)
    cost: int


@dataclass
class Grounded:
    operators: list[Operator]
    facts: list[Fact]  # the reachable fluent facts, one binary variable each
    init: set[Fact]
    goal: list[tuple[Fact, bool]]
    metric: bool
    unsolvable: bool = False  # a goal fact is unreachable (or a static one false)


class Grounder:
    """Grounds the tasks of a loop, one after another, keeping each ground operator while what
    it was computed from holds: its schema, its cost, and the static facts its effects look up
    (a `forall`'s condition). The map's moves are the same from one replan to the next; only
    the reachability from the new state is computed again (docs/planner.md)."""

    def __init__(self) -> None:
        # by the names of the domain's actions (each stratum's restriction has its own): the
        # actions, their schemas, and the operators kept
        self._kept: dict[tuple[str, ...], tuple[tuple, tuple[_Schema, ...], dict]] = {}
        self.reused = self.made = 0

    def ground(self, domain: m.Domain, problem: m.Problem) -> Grounded:
        """Relaxed-reachable ground operators of a compiled task (raises OutsideFragment)."""
        names = tuple(a.name for a in domain.actions)
        kept = self._kept.get(names)
        if kept is None or kept[0] != domain.actions:  # the same schemas while the actions are the same
            kept = self._kept[names] = (domain.actions, _schemas(domain), {})
        _, schemas, kept_operators = kept
        goal = _literals(problem.goal, "the goal")
        parents = domain.type_parents
        objects: dict[str, list[str]] = {}
        for obj in (*domain.constants, *problem.all_objects):
            for t in _ancestors(obj.types, parents):
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
        found = _reachable(schemas, static, reached, fluent, objects, members)
        # What an operator's effects looked up: it is kept while these are the same.
        everything = {(p, *args) for p, have in reached.by_predicate.items() for args in have}
        every_object = tuple((t, tuple(names)) for t, names in sorted(objects.items()))
        over_types = {s.name: _ranges_over_types(s, fluent) for s in schemas}
        guards = {s.name: _guards(s, fluent) for s in schemas}
        operators = []
        self.reused = self.made = 0
        for (name, args), (s, b) in found.items():
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
                generic = _keep(_generic(s, name, args, b, static, fluent, objects, members, cost))
                kept_operators[(name, args)] = (seen, generic)
                self.made += 1
            op = _final(generic, everything) if generic is not None else None
            if op is not None:
                operators.append(op)
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


def _guards(s: _Schema, fluent) -> list[tuple[str, tuple[int, ...], tuple[str, ...]]]:
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


def _ranges_over_types(s: _Schema, fluent) -> bool:
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


def _reachable(schemas, static, reached, fluent, objects, members) -> dict:
    """Relaxed reachability: every operator whose positive preconditions can become true, with
    the facts their add effects reach added to `reached`. A schema is enumerated again only when
    a predicate of its preconditions gained facts; an effect whose condition is not reached yet
    waits for the next round."""

    def ok(lit: _Lit, binding: dict) -> bool:
        if lit.predicate == "=" or lit.predicate not in fluent:
            return _holds_static(lit, binding, static)
        return lit.negated or (lit.predicate, *_ground(lit.args, binding)) in reached

    both = _Both(static, reached, fluent)
    found: dict[tuple[str, tuple[str, ...]], tuple[_Schema, dict]] = {}
    watched = {
        s.name: sorted({x.predicate for x in s.precondition if not x.negated and x.predicate in fluent})
        for s in schemas
    }
    last: dict[str, tuple[int, ...]] = {}
    waiting: list[tuple[_Eff, dict]] = []
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
            for b in list(_bind(s.precondition, {}, both, objects, s.parameters)):
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


def _effect_bindings(e: _Eff, binding: dict, index, objects, members, static_only=False) -> Iterable[dict]:
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


@dataclass(frozen=True, slots=True)
class _Kept:
    generic: Operator
    facts: frozenset  # every fluent fact it names
    whole: Operator | None  # as it is where all of them can be reached (most operators, mostly)


def _keep(op: Operator | None) -> _Kept | None:
    if op is None:
        return None
    facts = frozenset([f for f, _ in op.precondition] + [f for _, f, _ in op.effects]
                      + [c for cond, _, _ in op.effects for c, _ in cond])  # fmt: skip
    return _Kept(op, facts, _finalize(op, facts))


def _final(kept: _Kept, reached: set) -> Operator | None:
    return kept.whole if kept.facts <= reached else _finalize(kept.generic, reached)


def _finalize(op: Operator, reached) -> Operator | None:
    """The operator over the facts reached: a fact never true makes its negation always hold."""
    pre = {}
    for fact, value in op.precondition:
        if fact in reached:
            pre[fact] = value
        elif value:
            return None
    effects = []
    for condition, fact, value in op.effects:
        if fact not in reached:
            continue  # a delete of a fact never true (an add's fact is reached, or its condition is not)
        kept = []
        for c, cv in condition:
            if c in reached:
                kept.append((c, cv))
            elif cv:
                break  # its condition can never hold
        else:
            effects.append((kept, fact, value))
    resolved = _resolve(sorted(effects, key=lambda e: (e[1], e[2], e[0])), pre)
    if resolved is None:
        raise OutsideFragment(f"({op.name}): a fact both added and deleted under conditions")
    if not resolved:
        return None
    return Operator(op.name, sorted(pre.items()), resolved, op.cost)


def _holds_static(lit: _Lit, binding: dict, static: _Index) -> bool:
    args = _ground(lit.args, binding)
    if lit.predicate == "=":
        return (args[0] == args[1]) != lit.negated
    return ((lit.predicate, *args) in static) != lit.negated


def _resolve(effects, pre: dict[Fact, bool]):
    """PDDL's rule that an add wins over a delete of the same fact; effects that set what the
    precondition already requires are dropped, as the translator does. None where an add and a
    delete of one fact have different conditions (SAS cannot say which wins)."""
    if len({f for _, f, _ in effects}) == len(effects):  # each fact once: nothing to decide
        return [(sorted(c) if len(c) > 1 else c, f, v) for c, f, v in effects if c or pre.get(f) != v]
    by_fact: dict[Fact, list] = {}
    for condition, fact, value in effects:
        by_fact.setdefault(fact, []).append((condition, value))
    out = []
    for fact, options in by_fact.items():
        adds = [c for c, v in options if v]
        deletes = [c for c, v in options if not v]
        if adds and deletes:
            if not any(not c for c in adds):
                return None
            deletes = []  # an unconditional add wins over every delete
        for condition, value in [(c, True) for c in adds] + [(c, False) for c in deletes]:
            if not condition and pre.get(fact) == value:
                continue  # already so
            out.append((sorted(condition), fact, value))
    return out


def _cost(s: _Schema, b: dict, values) -> int:
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


def _ancestors(types, parents) -> set[str]:
    seen: set[str] = set()
    todo = list(types)
    while todo:
        t = todo.pop()
        if t not in seen:
            seen.add(t)
            todo.extend(parents.get(t, ()))
    seen.add(m.ROOT_TYPE)
    return seen


# ---------------------------------------------------------------------- SAS
def sas(g: Grounded) -> str:
    """Fast Downward's SAS format (version 3): one binary variable per fact, value 0 true."""
    var = {f: i for i, f in enumerate(g.facts)}
    out = io.StringIO()
    w = out.write
    w(f"begin_version\n3\nend_version\nbegin_metric\n{int(g.metric)}\nend_metric\n{len(g.facts)}\n")
    for i, f in enumerate(g.facts):
        text = f"{f[0]}({', '.join(f[1:])})"
        w(f"begin_variable\nvar{i}\n-1\n2\nAtom {text}\nNegatedAtom {text}\nend_variable\n")
    w("0\nbegin_state\n")
    w("".join("0\n" if f in g.init else "1\n" for f in g.facts))
    w(f"end_state\nbegin_goal\n{len(g.goal)}\n")
    w("".join(f"{var[f]} {0 if v else 1}\n" for f, v in g.goal))
    w(f"end_goal\n{len(g.operators)}\n")
    for op in g.operators:
        pre = {var[f]: 0 if v else 1 for f, v in op.precondition}
        touched = {var[f] for _, f, _ in op.effects}
        prevail = [(x, v) for x, v in pre.items() if x not in touched]
        w(f"begin_operator\n{op.name}\n{len(prevail)}\n")
        w("".join(f"{x} {v}\n" for x, v in prevail))
        w(f"{len(op.effects)}\n")
        for condition, f, value in op.effects:
            x = var[f]
            cond = " ".join(f"{var[c]} {0 if cv else 1}" for c, cv in condition)
            w(f"{len(condition)}{' ' + cond if cond else ''} {x} {pre.get(x, -1)} {0 if value else 1}\n")
        w(f"{op.cost}\nend_operator\n")
    w("0\n")
    return out.getvalue()
