"""Moves only to where there is work: a reduction of the state space, found in the domain.

A tidy-up is mostly an order of visits, and a cost-optimal search pays for every place the robot
could stand idle: with every move open, 12-object problems have 573k states, of which the
robot standing where it has nothing to do are most (docs/planner.md). `tidy.pddl` says so in
its own words (`(shortest-paths)`); this module finds the same reduction in any domain, so that
a domain nobody tuned gets it too.

A *pure move* is an action whose precondition is one fluent atom `L(.. ?from ..)` plus static
facts, and whose effects are only `not L(.. ?from ..)`, `L(.. ?to ..)` and its cost. Where the
move's ground costs are a metric over the places (a move a→c exists, costing no more than a→b
then b→c, wherever a→b and b→c do: path lengths on a map are), any run of moves in a plan can be
replaced by one, and a move followed by an action that does not read `L` can be put after it
(neither touches what the other reads). So some optimal plan moves only to a place where the
next action reads `L` there. The move is replaced by one copy for each such action R, whose
precondition adds R's own, `L` aside: the robot drives to `?to` only where R can then be done.

Sound only when nothing else reads or writes `L` in another way: every other mention of `L` is
a positive atom of a conjunctive precondition (a reader; a reader may change `L` itself), or of
the goal (the robot may be asked to end somewhere). Anything else, and the task is left as it is.
Costs are integers after compilation, so a metric may be broken by rounding: `TOLERANCE` units
are allowed, and a plan then costs at most that much more per move than the optimum.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from tidyplan.pddl import model as m
from tidyplan.pddl.compile import CompiledTask
from tidyplan.planning.move_metric import TOLERANCE, is_metric

__all__ = ["TOLERANCE", "Reduced", "reduce_moves"]


@dataclass(frozen=True)
class Reduced:
    """A task whose moves go only to where there is work, and how to read its plans back."""

    task: CompiledTask
    projection: dict[str, tuple[str, int]]  # a copy's name -> (the move's name, its arguments)
    moves: tuple[str, ...]  # the moves reduced (compiled names)

    def original(self, step: tuple[str, ...]) -> tuple[str, ...]:
        """A plan step of the reduced task as the compiled task's step."""
        if step[0] not in self.projection:
            return step
        move, arity = self.projection[step[0]]
        return (move, *step[1 : 1 + arity])


def reduce_moves(task: CompiledTask) -> Reduced | None:
    """The task with each pure move copied per reader (module doc), or None where no move
    qualifies (the task is then planned as it is)."""
    domain = task.domain
    if domain.derived:
        return None  # a rule may read the place anywhere: the readers' argument does not hold
    fluent = _written(domain)
    # a negated fluent no action adds and the problem leaves false holds throughout
    never = _never_added(domain) - {a.predicate for a in task.problem.init}
    moves = [mv for a in domain.actions if (mv := _pure_move(a, fluent, never)) is not None]
    by_location: dict[str, list[_Move]] = {}
    for mv in moves:
        by_location.setdefault(mv.location, []).append(mv)
    # one move a place predicate: another pure move of it (a pose adjustment between two
    # waypoints, say) is then one more reader, and runs of the chosen one alone are merged
    reduced: list[_Move] = []
    for loc, group in by_location.items():
        chosen = next((mv for mv in group if _is_metric_move(mv, task)), None)
        if chosen is not None and _only_read(loc, chosen, domain, task.problem):
            reduced.append(chosen)
    if not reduced:
        return None
    taken = {a.name for a in domain.actions}
    actions: list[m.Action] = []
    info = dict(task.info)
    projection: dict[str, tuple[str, int]] = {}
    gone = {mv.action.name for mv in reduced}
    for a in domain.actions:
        if a.name not in gone:
            actions.append(a)
            continue
        mv = next(x for x in reduced if x.action is a)
        for reader, precondition, parameters in _copies(mv, domain, task.problem):
            name = _fresh(f"{a.name}-to-{reader}", taken)
            actions.append(replace(a, name=name, parameters=parameters, precondition=precondition))
            stratum = max(task.info[a.name].stratum, task.info[reader].stratum if reader in info else 1)
            info[name] = replace(task.info[a.name], stratum=stratum)
            projection[name] = projection[name.lower()] = (a.name, len(a.parameters))  # FD lower-cases
    predicates, init = domain.predicates, task.problem.init
    for mv in reduced:
        if goal := _goal_places(mv, task.problem):
            name = _goal_predicate(mv, domain)
            predicates += (replace(domain.predicate(mv.location), name=name),)
            init += tuple(replace(a, predicate=name) for a in goal)
    smaller = replace(
        task,
        domain=replace(domain, actions=tuple(actions), predicates=predicates),
        problem=replace(task.problem, init=init),
        info=info,
    )
    return Reduced(smaller, projection, tuple(sorted(gone)))


# ---------------------------------------------------------------------- finding a pure move
@dataclass(frozen=True)
class _Move:
    action: m.Action
    location: str  # the predicate L
    added: m.Atom  # L(.. ?to ..)
    at: int  # the place's position in L
    cost: float | m.FunctionTerm


def _never_added(domain: m.Domain) -> set[str]:
    added = {lit.atom.predicate for a in domain.actions for lit in _literals(a.effect) if not lit.negated}
    return {p.name for p in domain.predicates} - added


def _written(domain: m.Domain) -> set[str]:
    out: set[str] = set()
    for a in domain.actions:
        for lit in _literals(a.effect):
            out.add(lit.atom.predicate)
    return out


def _literals(e: m.Effect):
    if isinstance(e, m.Literal):
        yield e
    elif isinstance(e, m.AndEffect):
        for p in e.parts:
            yield from _literals(p)
    elif isinstance(e, m.When):
        yield from _literals(e.effect)
    elif isinstance(e, m.ForallEffect):
        yield from _literals(e.effect)


def _parts(f: m.Formula) -> tuple[m.Formula, ...]:
    if isinstance(f, m.And):
        return tuple(x for p in f.parts for x in _parts(p))
    return (f,)


def _predicates(f: m.Formula) -> set[str]:
    if isinstance(f, m.Atom):
        return {f.predicate}
    if isinstance(f, (m.And, m.Or)):
        return set().union(*(_predicates(p) for p in f.parts)) if f.parts else set()
    if isinstance(f, m.Not):
        return _predicates(f.part)
    if isinstance(f, m.Imply):
        return _predicates(f.condition) | _predicates(f.consequence)
    return _predicates(f.body)


def _pure_move(a: m.Action, fluent: set[str], never: set[str]) -> _Move | None:
    if a.is_assumption or not isinstance(a.effect, m.AndEffect):
        return None
    dynamic = [p for p in _parts(a.precondition) if _predicates(p) & fluent and not _always(p, never)]
    if len(dynamic) != 1 or not isinstance(dynamic[0], m.Atom):
        return None
    held = dynamic[0]
    deleted = added = cost = None
    for e in a.effect.parts:
        if isinstance(e, m.Increase) and e.target.name == "total-cost" and cost is None:
            cost = e.amount
        elif isinstance(e, m.Literal) and e.negated and deleted is None:
            deleted = e.atom
        elif isinstance(e, m.Literal) and not e.negated and added is None:
            added = e.atom
        else:
            return None
    if deleted != held or added is None or added.predicate != held.predicate or cost is None:
        return None
    differ = [i for i, (x, y) in enumerate(zip(held.args, added.args, strict=True)) if x != y]
    if len(differ) != 1:
        return None
    at = differ[0]
    if not (held.args[at].startswith("?") and added.args[at].startswith("?")):
        return None
    return _Move(a, held.predicate, added, at, cost)


def _is_metric_move(mv: _Move, task: CompiledTask) -> bool:
    parts = _parts(mv.action.precondition)
    held = next(p for p in parts if isinstance(p, m.Atom) and p.predicate == mv.location)
    fluent = _written(task.domain)
    static = [p for p in parts if not _predicates(p) & fluent]
    return is_metric(mv.action, static, held, mv.added, mv.at, mv.cost, task)


def _always(f: m.Formula, never: set[str]) -> bool:
    """`(not (p ...))` where no (p ...) is ever true."""
    return isinstance(f, m.Not) and isinstance(f.part, m.Atom) and f.part.predicate in never


def _only_read(location: str, mv: _Move, domain: m.Domain, problem: m.Problem) -> bool:
    """Is `location` mentioned, outside the move, only as positive atoms of conjunctive
    preconditions and of the goal?"""
    for a in domain.actions:
        if a is mv.action:
            continue
        readers = [p for p in _parts(a.precondition) if isinstance(p, m.Atom) and p.predicate == location]
        rest = [p for p in _parts(a.precondition) if not (isinstance(p, m.Atom) and p.predicate == location)]
        if any(location in _predicates(p) for p in rest):
            return False
        if not readers and any(lit.atom.predicate == location for lit in _literals(a.effect)):
            return False  # changes where the robot is without reading it
        if not _plain_effects(a.effect, location):
            return False
    goal = _parts(problem.goal)
    return not any(
        location in _predicates(p) for p in goal if not (isinstance(p, m.Atom) and p.predicate == location)
    )


def _plain_effects(e: m.Effect, location: str) -> bool:
    """No condition of a `when` mentions `location`, and no `forall` or `when` writes it."""
    if isinstance(e, m.AndEffect):
        return all(_plain_effects(p, location) for p in e.parts)
    if isinstance(e, m.When):
        return location not in _predicates(e.condition) and all(
            lit.atom.predicate != location for lit in _literals(e.effect)
        )
    if isinstance(e, m.ForallEffect):
        return all(lit.atom.predicate != location for lit in _literals(e.effect))
    return True


# ---------------------------------------------------------------------- the copies
def _copies(mv: _Move, domain: m.Domain, problem: m.Problem):
    """(the reader's name, the copy's precondition, its parameters) for each action that reads
    L, and each place the goal asks the robot to be (reader name: the move's own)."""
    own = {p.name for p in mv.action.parameters}
    for r in domain.actions:
        if r is mv.action:
            continue
        parts = _parts(r.precondition)
        for k, atom in enumerate(parts):
            if not (isinstance(atom, m.Atom) and atom.predicate == mv.location):
                continue
            rename = _apart(r.parameters, own)
            renamed = _rename(atom, rename)
            unified = _unify(mv.added, renamed)
            if unified is None:
                continue
            substitution, equalities = unified
            rest = [_rename(_rename(p, rename), substitution) for i, p in enumerate(parts) if i != k]
            kept = tuple(
                replace(v, name=rename[v.name]) for v in r.parameters if rename[v.name] not in substitution
            )
            pre = m.And(_parts(mv.action.precondition) + tuple(equalities) + tuple(rest))
            yield r.name, pre, mv.action.parameters + kept
    if _goal_places(mv, problem):
        # the problem's objects cannot be named in the domain: a static predicate says where
        pre = m.And(_parts(mv.action.precondition) + (m.Atom(_goal_predicate(mv, domain), mv.added.args),))
        yield mv.action.name, pre, mv.action.parameters


def _goal_places(mv: _Move, problem: m.Problem) -> list[m.Atom]:
    return [a for a in _parts(problem.goal) if isinstance(a, m.Atom) and a.predicate == mv.location]


def _goal_predicate(mv: _Move, domain: m.Domain) -> str:
    taken = {x.name for x in (*domain.predicates, *domain.actions, *domain.types, *domain.functions)}
    name, n = f"{mv.location}-in-goal", 2
    while name in taken:
        name, n = f"{mv.location}-in-goal-{n}", n + 1
    return name


def _apart(parameters: tuple[m.Typed, ...], taken: set[str]) -> dict[str, str]:
    out = {}
    for v in parameters:
        name, n = v.name, 2
        while name in taken or name in out.values():
            name, n = f"{v.name}-{n}", n + 1
        out[v.name] = name
    return out


def _rename(f: m.Formula, names: dict[str, str]) -> m.Formula:
    def atom(a: m.Atom) -> m.Atom:
        return replace(a, args=tuple(names.get(x, x) for x in a.args))

    def quantified(q, body):
        # a quantifier's own variables are not the action's parameters
        inner = {k: v for k, v in names.items() if k not in {x.name for x in q.variables}}
        return replace(q, body=_rename(q.body, inner) if inner != names else body)

    return m.map_formula(f, atom, quantified)


def _unify(move_atom: m.Atom, reader_atom: m.Atom):
    """(substitution of the reader's variables, equalities) making the two atoms one, or None.
    The reader's variables are apart from the move's (`_apart`)."""
    own = {x for x in move_atom.args if x.startswith("?")}
    substitution: dict[str, str] = {}
    equalities: list[m.Atom] = []
    for x, y in zip(move_atom.args, reader_atom.args, strict=True):
        y = substitution.get(y, y)
        if y.startswith("?") and y not in own:
            substitution[y] = x
        elif x != y:
            if not x.startswith("?") and not y.startswith("?"):
                return None  # two different constants
            equalities.append(m.Atom("=", (x, y)))
    return substitution, equalities


def _fresh(name: str, taken: set[str]) -> str:
    new, n = name, 2
    while new in taken:
        new, n = f"{name}-{n}", n + 1
    taken.add(new)
    return new
