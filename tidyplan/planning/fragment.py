"""The fragment of PDDL the loop's grounder takes (`tidyplan.planning.grounding`), read from the model.

Preconditions, effect conditions and goals: conjunctions of atoms, negated atoms and equalities.
Effects: literals, `when`, `forall`, and `(increase (total-cost) n)` with n a number or a static
function. Typing: single types (the compiler removes `either`). Anything else raises
`OutsideFragment`, and the planner hands the PDDL text to Fast Downward's translator.
"""

from __future__ import annotations

from dataclasses import dataclass

from tidyplan.pddl import model as m

Fact = tuple[str, ...]  # (predicate, arg, ...)


class OutsideFragment(Exception):
    """The task uses something this grounder does not (the translator is used instead)."""


@dataclass(frozen=True, slots=True)
class Lit:
    predicate: str
    args: tuple[str, ...]
    negated: bool


@dataclass(frozen=True, slots=True)
class Eff:
    variables: tuple[m.Typed, ...]  # a forall's, else ()
    condition: tuple[Lit, ...]
    literal: Lit


@dataclass(frozen=True, slots=True)
class Schema:
    name: str
    parameters: tuple[m.Typed, ...]
    precondition: tuple[Lit, ...]
    effects: tuple[Eff, ...]
    cost: float | m.FunctionTerm | None


# ---------------------------------------------------------------------- the fragment
def literals(f: m.Formula, where: str) -> tuple[Lit, ...]:
    if isinstance(f, m.Atom):
        return (Lit(f.predicate, f.args, False),)
    if isinstance(f, m.Not) and isinstance(f.part, m.Atom):
        return (Lit(f.part.predicate, f.part.args, True),)
    if isinstance(f, m.And):
        return tuple(x for p in f.parts for x in literals(p, where))
    raise OutsideFragment(f"{where}: {type(f).__name__.lower()} is not a conjunction of literals")


def _effects(e: m.Effect, where: str, variables=(), condition=()) -> tuple[list[Eff], list]:
    out: list[Eff] = []
    costs: list = []
    if isinstance(e, m.Literal):
        out.append(Eff(tuple(variables), tuple(condition), Lit(e.atom.predicate, e.atom.args, e.negated)))
    elif isinstance(e, m.AndEffect):
        for part in e.parts:
            o, c = _effects(part, where, variables, condition)
            out += o
            costs += c
    elif isinstance(e, m.When):
        o, c = _effects(e.effect, where, variables, (*condition, *literals(e.condition, where)))
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


def schemas(domain: m.Domain) -> tuple[Schema, ...]:
    if domain.derived:
        raise OutsideFragment("derived predicates")
    out = []
    for a in domain.actions:
        where = f"action {a.name}"
        if any(len(p.types) != 1 for p in a.parameters):
            raise OutsideFragment(f"{where}: an either type")
        effects, costs = _effects(a.effect, where)
        if len(costs) > 1:
            raise OutsideFragment(f"{where}: two cost increases")
        out.append(Schema(a.name, a.parameters, literals(a.precondition, where), tuple(effects),
                           costs[0] if costs else None))  # fmt: skip
    return tuple(out)


def fragment_gap(domain: m.Domain, problem: m.Problem) -> str | None:
    """Why the task is outside the grounder's fragment, or None."""
    try:
        schemas(domain)
        literals(problem.goal, "the goal")
    except OutsideFragment as e:
        return str(e)
    return None
