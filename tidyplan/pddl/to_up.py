"""Plain PDDL model to a unified-planning `Problem`.

Built directly from our model rather than through unified-planning's PDDL
reader, which rejects real files that Fast Downward accepts (docs/dialect.md) and
takes seconds on large problems. It uses unified-planning's global environment:
up-fast-downward's optimal engine builds expressions there whatever problem it
is given, so a private environment breaks it. Engine credits are silenced so
that they never mix with our output.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass

from unified_planning.environment import Environment, get_environment
from unified_planning.model import (
    Fluent,
    InstantaneousAction,
    MinimizeActionCosts,
    Object,
    Problem,
    Variable,
)

from tidyplan.errors import Diagnostic, PddlError, PlannerError
from tidyplan.pddl import model as m
from tidyplan.pddl.check import COST

UNDEFINED_COST = 10**7  # cost of a grounding whose cost the file leaves undefined


class SparseProblem(Problem):
    """A UP problem whose `initial_values` are the explicit ones only.

    UP's property enumerates every grounding of every fluent to add defaults
    (617,000 for nomystery p01: 15 s in its PDDL writer). Under PDDL's closed
    world the defaults here are `false` or an undefined cost, which a PDDL file
    leaves unwritten anyway, so the explicit values say the same thing.
    """

    @property
    def initial_values(self):
        return dict(self._initial_value)


@dataclass
class UpTask:
    problem: Problem
    environment: Environment


class _Converter:
    def __init__(self, domain: m.Domain, problem: m.Problem) -> None:
        self.env = get_environment()
        self.env.credits_stream = None
        self.tm, self.em = self.env.type_manager, self.env.expression_manager
        self.domain, self.pddl_problem = domain, problem
        self.types = self._types()
        self.objects: dict[str, Object] = {}
        self.fluents: dict[str, Fluent] = {}

    def _types(self):
        root = self.tm.UserType(m.ROOT_TYPE)
        parents = self.domain.type_parents
        types = {m.ROOT_TYPE: root}

        def make(name: str, trail: tuple[str, ...] = ()):
            if name not in types:
                parent = parents.get(name, (m.ROOT_TYPE,))[0]
                father = make(parent, trail + (name,)) if parent not in trail else root
                types[name] = self.tm.UserType(name, father)
            return types[name]

        for name in parents:
            make(name)
        return types

    def type_of(self, typed: m.Typed):
        # `either` narrows nothing for unified-planning: use the root type.
        return self.types[typed.types[0]] if len(typed.types) == 1 else self.types[m.ROOT_TYPE]

    def params(self, items: tuple[m.Typed, ...]) -> OrderedDict:
        out: OrderedDict = OrderedDict()
        for i, t in enumerate(items):
            name = t.name.lstrip("?").replace("-", "_")
            out[name if name not in out else f"{name}_{i}"] = self.type_of(t)
        return out

    def term(self, name: str, scope: dict):
        if name.startswith("?"):
            return scope[name]
        return self.objects[name]

    def formula(self, f: m.Formula, scope: dict):
        em = self.em
        if isinstance(f, m.Atom):
            args = [self.term(a, scope) for a in f.args]
            if f.predicate == "=":
                return em.Equals(args[0], args[1])
            return self.fluents[f.predicate](*args)
        if isinstance(f, m.And):
            return em.And(*[self.formula(p, scope) for p in f.parts]) if f.parts else em.TRUE()
        if isinstance(f, m.Or):
            return em.Or(*[self.formula(p, scope) for p in f.parts]) if f.parts else em.FALSE()
        if isinstance(f, m.Not):
            return em.Not(self.formula(f.part, scope))
        if isinstance(f, m.Imply):
            return em.Implies(self.formula(f.condition, scope), self.formula(f.consequence, scope))
        variables, inner = self._variables(f.variables, scope)
        body = self.formula(f.body, inner)
        return em.Exists(body, *variables) if isinstance(f, m.Exists) else em.Forall(body, *variables)

    def _variables(self, items: tuple[m.Typed, ...], scope: dict):
        inner = dict(scope)
        variables = []
        for t in items:
            v = Variable(f"{t.name.lstrip('?').replace('-', '_')}_{len(inner)}", self.type_of(t), self.env)
            inner[t.name] = v
            variables.append(v)
        return variables, inner

    def effects(self, action: InstantaneousAction, e: m.Effect, scope: dict, condition, forall: tuple):
        """Flatten nested and/when/forall into UP's (fluent, value, condition, forall)."""
        if isinstance(e, m.Literal):
            fl = self.formula(e.atom, scope)
            action.add_effect(fl, not e.negated, condition, forall)
        elif isinstance(e, m.AndEffect):
            for part in e.parts:
                self.effects(action, part, scope, condition, forall)
        elif isinstance(e, m.When):
            cond = self.em.And(condition, self.formula(e.condition, scope))
            self.effects(action, e.effect, scope, cond, forall)
        elif isinstance(e, m.ForallEffect):
            variables, inner = self._variables(e.variables, scope)
            self.effects(action, e.effect, inner, condition, forall + tuple(variables))
        # `increase` effects are read apart, as the action's cost

    def convert(self) -> Problem:
        d, p = self.domain, self.pddl_problem
        problem = SparseProblem(p.name, self.env)
        for o in d.constants + p.all_objects:
            if o.name not in self.objects:
                self.objects[o.name] = Object(o.name, self.type_of(o), self.env)
        problem.add_objects(list(self.objects.values()))
        for pred in d.predicates:
            self.fluents[pred.name] = Fluent(
                pred.name, self.tm.BoolType(), self.params(pred.parameters), self.env
            )
            problem.add_fluent(self.fluents[pred.name], default_initial_value=False)
        cost_fluents: dict[str, Fluent] = {}
        for fn in d.functions:
            if fn.name != COST:
                cost_fluents[fn.name] = Fluent(
                    fn.name, self.tm.IntType(), self.params(fn.parameters), self.env
                )
                problem.add_fluent(cost_fluents[fn.name], default_initial_value=UNDEFINED_COST)
        costs = {}
        for a in d.actions:
            action = InstantaneousAction(a.name, self.params(a.parameters), self.env)
            scope = {t.name: action.parameters[i] for i, t in enumerate(a.parameters)}
            pre = self.formula(a.precondition, scope)
            if not pre.is_true():
                action.add_precondition(pre)
            self.effects(action, a.effect, scope, self.em.TRUE(), ())
            costs[action] = self._cost(a, scope, cost_fluents)
            problem.add_action(action)
        for atom in p.init:
            problem.set_initial_value(self.formula(atom, {}), True)
        for term, value in p.values:
            if term.name in cost_fluents:
                args = [self.objects[x] for x in term.args]
                problem.set_initial_value(cost_fluents[term.name](*args), int(value))
        problem.add_goal(self.formula(p.goal, {}))
        problem.add_quality_metric(MinimizeActionCosts(costs, default=self.em.Int(0), environment=self.env))
        return problem

    def _cost(self, a: m.Action, scope: dict, cost_fluents: dict):
        amounts = [e.amount for e in _increases(a.effect)]
        if not amounts:
            return self.em.Int(0)
        if len(amounts) > 1:
            raise PlannerError(f"action '{a.name}' has {len(amounts)} cost effects; compile the task first")
        amount = amounts[0]
        if isinstance(amount, m.FunctionTerm):
            return cost_fluents[amount.name](*[self.term(x, scope) for x in amount.args])
        return self.em.Int(int(amount))


def _increases(e: m.Effect):
    if isinstance(e, m.Increase):
        yield e
    elif isinstance(e, m.AndEffect):
        for part in e.parts:
            yield from _increases(part)


def to_up(domain: m.Domain, problem: m.Problem) -> UpTask:
    """Convert a compiled (plain, integer-cost) task to unified-planning."""
    if domain.derived:
        r = domain.derived[0]
        raise PddlError(
            Diagnostic(
                domain.path,
                r.pos.line or None,
                r.pos.col or None,
                "unified-planning's model has no derived predicates: plan this domain with one of"
                " tidyplan's own engines (lama-optimal, lama, lama-first, optimal), which give them"
                " to Fast Downward",
            )
        )
    c = _Converter(domain, problem)
    return UpTask(c.convert(), c.env)
