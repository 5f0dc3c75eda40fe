"""Compile the dialect into plain PDDL with action costs.

What each extension becomes (docs/dialect.md):

- `:probability` and the action's own cost become one integer cost,
  `round(S · (c(a) + R · −ln p(a)))` (see `tidyplan.pddl.criterion`). Where c or p
  depends on the parameters through static functions, the cost becomes a new
  static function `<action>-cost` over those parameters, tabulated from :init.
- `(:assumption ...)` becomes an action; `ActionInfo.is_assumption` remembers.
- `:stratum K` is kept in `ActionInfo`; `restrict()` drops the actions above
  a stratum (the lexicographic ranking lives in `tidyplan.planning.strata`).
- `(:virtual-objects ...)` become objects; `(:goal-reward R)` enters the costs.
- Names that clash (a type and a predicate both called `cart`, an action and
  a predicate both called `up`) are renamed so that unified-planning, whose
  elements share one namespace, can take them; `ActionInfo.name` and the kept
  object names carry plans back to the file's own names.
- Static flags (predicates without parameters that no action changes) are
  folded into the conditions (`tidyplan.pddl.static`).
- `(:derived ...)` rules are kept as they are (renamed, `either` compiled away), for Fast
  Downward's translator (its axioms) and VAL.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from tidyplan.errors import Diagnostic, PddlError
from tidyplan.pddl import model as m
from tidyplan.pddl.check import COST
from tidyplan.pddl.criterion import DEFAULT_REWARD, choose_scale, integer_cost
from tidyplan.pddl.either import compile_either
from tidyplan.pddl.static import _effect_predicates, fold

EXTENSION_FLAGS = (":probabilities", ":assumptions", ":strata")


@dataclass(frozen=True, slots=True)
class ActionInfo:
    """What the compiled action was in the dialect."""

    name: str  # the file's own name
    stratum: int
    is_assumption: bool
    cost_terms: tuple[float | m.FunctionTerm, ...]  # c(a) = their sum
    probability: float | m.FunctionTerm


@dataclass(frozen=True)
class CompiledTask:
    """A dialect task as plain PDDL, and what is needed to read plans back."""

    source_domain: m.Domain
    source_problem: m.Problem
    domain: m.Domain
    problem: m.Problem
    info: dict[str, ActionInfo]  # by compiled action name
    reward: float
    scale: int
    values: dict[str, dict[tuple[str, ...], float]]  # the source problem's numeric :init

    def step_cost(self, action: str, args: tuple[str, ...]) -> float:
        """c(a) of a grounded compiled action, in the file's units."""
        info = self.info[action]
        binding = self._binding(action, args)
        return sum(_value(t, binding, self.values) for t in info.cost_terms)

    def step_probability(self, action: str, args: tuple[str, ...]) -> float:
        info = self.info[action]
        return _value(info.probability, self._binding(action, args), self.values)

    def _binding(self, action: str, args: tuple[str, ...]) -> dict[str, str]:
        params = self.domain.action(action).parameters
        return {p.name: a for p, a in zip(params, args, strict=True)}

    @property
    def strata(self) -> tuple[int, ...]:
        return tuple(sorted({i.stratum for i in self.info.values()}))

    def restrict(self, max_stratum: int) -> CompiledTask:
        """The task with only the operators of strata 1..max_stratum."""
        keep = tuple(a for a in self.domain.actions if self.info[a.name].stratum <= max_stratum)
        return replace(self, domain=replace(self.domain, actions=keep))


def _value(term: float | m.FunctionTerm, binding: dict[str, str], values) -> float:
    if not isinstance(term, m.FunctionTerm):
        return float(term)
    key = tuple(binding.get(a, a) for a in term.args)
    return values[term.name][key]


# ------------------------------------------------------------------ naming
def _unique_names(domain: m.Domain, problem: m.Problem) -> dict[tuple[str, str], str]:
    """(kind, name) → a name no element of another kind has.

    Objects keep their names first, then actions (plans speak both), then
    types, predicates and functions.
    """
    taken: set[str] = set()
    out: dict[tuple[str, str], str] = {}
    groups = [
        ("object", [o.name for o in domain.constants + problem.all_objects]),
        ("action", [a.name for a in domain.actions]),
        ("type", [m.ROOT_TYPE] + [t.name for t in domain.types]),
        ("predicate", [p.name for p in domain.predicates]),
        ("function", [f.name for f in domain.functions]),
    ]
    for kind, names in groups:
        mine: set[str] = set()
        for name in names:
            new = name
            if name in taken and name not in mine:
                new, n = f"{name}-{kind}", 2
                while new in taken:
                    new, n = f"{name}-{kind}{n}", n + 1
            out[(kind, name)] = new
            mine.add(new)
        taken |= mine
    return out


class _Renamer:
    def __init__(self, names: dict[tuple[str, str], str]) -> None:
        self.names = names

    def typed(self, items: tuple[m.Typed, ...]) -> tuple[m.Typed, ...]:
        return tuple(replace(t, types=tuple(self.names.get(("type", x), x) for x in t.types)) for t in items)

    def atom(self, a: m.Atom) -> m.Atom:
        if a.predicate == "=":
            return a
        name = self.names[("predicate", a.predicate)]
        return a if name == a.predicate else replace(a, predicate=name)

    def formula(self, f: m.Formula) -> m.Formula:
        return m.map_formula(f, self.atom, lambda q, body: type(q)(self.typed(q.variables), body))

    def effect(self, e: m.Effect) -> m.Effect:
        """Renamed, with every `increase` left out (costs are compiled apart)."""
        if isinstance(e, m.Literal):
            return m.Literal(self.atom(e.atom), e.negated)
        if isinstance(e, m.AndEffect):
            return m.AndEffect(tuple(self.effect(p) for p in e.parts if not isinstance(p, m.Increase)))
        if isinstance(e, m.When):
            return m.When(self.formula(e.condition), self.effect(e.effect))
        if isinstance(e, m.ForallEffect):
            return m.ForallEffect(self.typed(e.variables), self.effect(e.effect))
        return m.NO_EFFECT  # a lone increase


# ------------------------------------------------------------------- costs
def _cost_terms(action: m.Action, unit_costs: bool, path: str) -> tuple[float | m.FunctionTerm, ...]:
    if action.is_assumption:
        return ()
    if unit_costs:
        return (1.0,)
    terms: list[float | m.FunctionTerm] = []
    todo: list[m.Effect] = [action.effect]
    while todo:
        e = todo.pop()
        if isinstance(e, m.AndEffect):
            todo.extend(e.parts)
        elif isinstance(e, m.Increase):
            terms.append(e.amount)
        elif isinstance(e, (m.When, m.ForallEffect)) and _has_increase(e):
            p = action.pos
            raise PddlError(
                Diagnostic(path, p.line, p.col, f"'{action.name}': conditional costs are not supported")
            )
    return tuple(terms)


def _has_increase(e: m.Effect) -> bool:
    if isinstance(e, m.Increase):
        return True
    if isinstance(e, m.AndEffect):
        return any(_has_increase(p) for p in e.parts)
    if isinstance(e, (m.When, m.ForallEffect)):
        return _has_increase(e.effect)
    return False


def _rows(terms: list[m.FunctionTerm], values) -> list[dict[str, str]]:
    """Bindings of the terms' variables for which every term has a value."""
    rows: list[dict[str, str]] = [{}]
    for term in terms:
        table = values.get(term.name, {})
        joined = []
        for row in rows:
            for args in table:
                new = dict(row)
                if all(_bind(new, t, a) for t, a in zip(term.args, args, strict=True)):
                    joined.append(new)
        rows = joined
    return rows


def _bind(row: dict[str, str], term_arg: str, value: str) -> bool:
    if not term_arg.startswith("?"):
        return term_arg == value
    if row.setdefault(term_arg, value) != value:
        return False
    return True


# ------------------------------------------------------------ compilation
def compile_task(domain: m.Domain, problem: m.Problem, scale: int | None = None) -> CompiledTask:
    """The dialect task as plain PDDL with integer action costs."""
    source_domain, source_problem = domain, problem
    domain, problem = fold(*compile_either(domain, problem))
    names = _unique_names(domain, problem)
    ren = _Renamer(names)
    reward = problem.goal_reward if problem.goal_reward is not None else DEFAULT_REWARD
    values = problem.value_table()
    unit_costs = not domain.has_costs

    infos: dict[str, ActionInfo] = {}
    for a in domain.actions:
        infos[names[("action", a.name)]] = ActionInfo(
            a.name, a.stratum, a.is_assumption, _cost_terms(a, unit_costs, domain.path), a.probability
        )
    if scale is None:
        scale = _scale(domain, infos, values)

    actions, functions, cost_values = [], [m.Function(COST, ())], []
    taken = set(names.values())
    changed: set[str] = set()
    for a in domain.actions:
        _effect_predicates(a.effect, changed)
    for a in domain.actions:
        new_name = names[("action", a.name)]
        amount, table_fn, table = _compile_cost(
            a, infos[new_name], values, reward, scale, taken, problem.path, _applicable(a, changed, problem)
        )
        if table_fn is not None:
            functions.append(table_fn)
            cost_values.extend(table)
        effect = ren.effect(a.effect)
        parts = effect.parts if isinstance(effect, m.AndEffect) else (effect,)
        increase = m.Increase(m.FunctionTerm(COST, ()), amount)
        actions.append(
            m.Action(
                new_name,
                ren.typed(a.parameters),
                ren.formula(a.precondition),
                m.AndEffect(parts + (increase,)),
            )
        )

    plain_reqs = tuple(r for r in domain.requirements if r not in EXTENSION_FLAGS)
    if ":action-costs" not in plain_reqs:
        plain_reqs += (":action-costs",)
    if domain.derived and ":derived-predicates" not in plain_reqs:
        plain_reqs += (":derived-predicates",)  # VAL reads the rules only with it
    plain_domain = m.Domain(
        name=domain.name,
        requirements=plain_reqs,
        types=tuple(replace(t, name=names[("type", t.name)]) for t in ren.typed(domain.types)),
        constants=ren.typed(domain.constants),
        predicates=tuple(
            replace(p, name=names[("predicate", p.name)], parameters=ren.typed(p.parameters))
            for p in domain.predicates
        ),
        functions=tuple(functions),
        actions=tuple(actions),
        path=domain.path,
        derived=tuple(
            m.Derived(names[("predicate", r.predicate)], ren.typed(r.parameters), ren.formula(r.body), r.pos)
            for r in domain.derived
        ),
    )
    plain_problem = m.Problem(
        name=problem.name,
        domain_name=domain.name,
        objects=ren.typed(problem.objects + problem.virtual_objects),
        virtual_objects=(),
        init=tuple(ren.atom(a) for a in problem.init),
        values=((m.FunctionTerm(COST, ()), 0.0),) + tuple(cost_values),
        goal=ren.formula(problem.goal),
        metric=("minimize", m.FunctionTerm(COST, ())),
        path=problem.path,
    )
    return CompiledTask(
        source_domain, source_problem, plain_domain, plain_problem, infos, reward, scale, values
    )


def _scale(domain: m.Domain, infos: dict[str, ActionInfo], values) -> int:
    costs: list[float] = []
    probabilities: list[float] = []
    for info in infos.values():
        for t in info.cost_terms:
            costs.extend(values.get(t.name, {}).values() if isinstance(t, m.FunctionTerm) else [t])
        p = info.probability
        probabilities.extend(values.get(p.name, {}).values() if isinstance(p, m.FunctionTerm) else [p])
    return choose_scale(costs, probabilities)


def _applicable(a: m.Action, changed: set[str], problem: m.Problem):
    """A static atom of the action's precondition and its true tuples, or None: a cost is only
    tabulated where that atom holds (the move costs of the pairs with a path, not of every
    pair of waypoints: half of a 96-object problem's values were never usable)."""
    parts = a.precondition.parts if isinstance(a.precondition, m.And) else (a.precondition,)
    for part in parts:
        if isinstance(part, m.Atom) and part.predicate != "=" and part.predicate not in changed:
            return part, {x.args for x in problem.init if x.predicate == part.predicate}
    return None


def _compile_cost(
    a: m.Action,
    info: ActionInfo,
    values,
    reward: float,
    scale: int,
    taken: set[str],
    path: str,
    applicable=None,
):
    """(amount for the increase, new cost function or None, its :init values)."""
    terms = [t for t in info.cost_terms + (info.probability,) if isinstance(t, m.FunctionTerm)]
    if not terms:
        const_cost = sum(info.cost_terms)  # type: ignore[arg-type]
        return float(integer_cost(const_cost, info.probability, reward, scale)), None, []
    variables = [p for p in a.parameters if any(p.name in t.args for t in terms)]
    fn_name, n = f"{info.name}-cost", 2
    while fn_name in taken:
        fn_name, n = f"{info.name}-cost{n}", n + 1
    taken.add(fn_name)
    fn = m.Function(fn_name, tuple(variables))
    table = []
    for row in _rows(terms, values):
        if applicable is not None:
            atom, true = applicable
            if all(x in row or not x.startswith("?") for x in atom.args):
                if tuple(row.get(x, x) for x in atom.args) not in true:
                    continue  # the action never applies here
        c = sum(_value(t, row, values) for t in info.cost_terms)
        p = _value(info.probability, row, values)
        if not 0.0 < p <= 1.0 or math.isnan(p):
            pos = info.probability.pos if isinstance(info.probability, m.FunctionTerm) else a.pos
            raise PddlError(
                Diagnostic(
                    path,
                    None,
                    None,
                    f"probability {p:g} of '{info.name}' (from {pos.line}:{pos.col}) is outside (0, 1]",
                )
            )
        args = tuple(row[v.name] for v in variables)
        table.append((m.FunctionTerm(fn_name, args), float(integer_cost(c, p, reward, scale))))
    return m.FunctionTerm(fn_name, tuple(v.name for v in variables)), fn, table
