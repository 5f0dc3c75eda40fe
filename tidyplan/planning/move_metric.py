"""Are a move's ground costs a metric over the places? (`tidyplan.planning.moves` merges runs of moves only
where they are: a move a→c exists wherever a→b and b→c do, costing no more than both.)

The move's ground instances are enumerated from its static precondition and the problem's
static facts; its costs are the compiled task's integers.
"""

from __future__ import annotations

import itertools
import math

from tidyplan.pddl import model as m
from tidyplan.pddl.compile import CompiledTask
from tidyplan.pddl.simulate import ancestors

TOLERANCE = 1  # compiled cost units a metric may be broken by (each cost is rounded once)
SPARSE_RUNS = 200_000  # runs of two moves walked one by one, at most (about 0.1 s); more: by matrices


def is_metric(
    action: m.Action,
    static_parts: list[m.Formula],
    held: m.Atom,
    added: m.Atom,
    at: int,
    cost: float | m.FunctionTerm,
    task: CompiledTask,
) -> bool:
    """Are the ground costs of the move `action` (from `held` to `added`, the place at position
    `at`) a metric over the places, within TOLERANCE, for each value of the place predicate's
    other arguments (each robot)? False also where there is no run of two moves to merge."""
    instances = _instances(action, static_parts, task)
    if instances is None:
        return False
    values = {}
    if isinstance(cost, m.FunctionTerm):
        values = {t.args: v for t, v in task.problem.values if t.name == cost.name}
    groups: dict[tuple, dict[tuple[str, str], float]] = {}
    for b in instances:
        key = tuple(b.get(x, x) for i, x in enumerate(added.args) if i != at)
        a, c = b.get(held.args[at], held.args[at]), b.get(added.args[at], added.args[at])
        amount = (
            values.get(tuple(b.get(x, x) for x in cost.args)) if isinstance(cost, m.FunctionTerm) else cost
        )
        if amount is None:
            return False  # a move without a cost: leave the task as it is
        edges = groups.setdefault(key, {})
        edges[(a, c)] = min(amount, edges.get((a, c), math.inf))
    return all(map(_closed, groups.values())) and any(map(_has_run, groups.values()))


def _has_run(edges: dict[tuple[str, str], float]) -> bool:
    """Can two moves follow each other to another place (else there is nothing to merge)?"""
    into: dict[str, set[str]] = {}
    for a, c in edges:
        into.setdefault(c, set()).add(a)
    return any(into.get(b, set()) - {c} for b, c in edges if b != c)


def _closed(edges: dict[tuple[str, str], float]) -> bool:
    """Is every run of two moves a→b→c (a ≠ c) matched by a direct move a→c costing no more,
    within TOLERANCE? Walked edge by edge where the runs are few (a plan task's moves: importing
    numpy would be most of a small task's whole call, 0.1 s), by matrices where they are many."""
    out: dict[str, dict[str, float]] = {}
    into: dict[str, dict[str, float]] = {}
    for (a, c), v in edges.items():
        if a != c:
            out.setdefault(a, {})[c] = v
            into.setdefault(c, {})[a] = v
    runs = sum(len(into.get(b, ())) * len(cs) for b, cs in out.items())
    if runs > SPARSE_RUNS:
        return _closed_dense(edges)
    for b, onward in out.items():
        for a, ab in into.get(b, {}).items():
            direct = out[a]
            for c, bc in onward.items():
                if c != a and direct.get(c, math.inf) > ab + bc + TOLERANCE:
                    return False
    return True


def _closed_dense(edges: dict[tuple[str, str], float]) -> bool:
    """``_closed`` by matrices, one intermediate place at a time."""
    import numpy as np  # here, not at the top: only a task with many moves pays its import

    places = sorted({p for e in edges for p in e})
    index = {p: i for i, p in enumerate(places)}
    n = len(places)
    cost = np.full((n, n), np.inf)
    for (a, c), v in edges.items():
        if a != c:
            cost[index[a], index[c]] = v
    np.fill_diagonal(cost, 0.0)
    # through[a, c] = min over b of cost[a, b] + cost[b, c]: two moves where one would do
    for b in range(n):
        through = cost[:, b : b + 1] + cost[b : b + 1, :]
        if np.any(through + TOLERANCE < cost):  # includes a missing direct move (inf)
            return False
    return True


def _instances(a: m.Action, static_parts: list[m.Formula], task: CompiledTask) -> list[dict] | None:
    """The move's parameter bindings where its static precondition holds (None where that is
    more than atoms, negated atoms and equalities)."""
    static: dict[str, set[tuple[str, ...]]] = {}
    for atom in task.problem.init:
        static.setdefault(atom.predicate, set()).add(atom.args)
    positive, tests = [], []
    for p in static_parts:
        if isinstance(p, m.Atom) and p.predicate != "=":
            positive.append(p)
        elif isinstance(p, m.Atom) or (isinstance(p, m.Not) and isinstance(p.part, m.Atom)):
            tests.append(p)
        else:
            return None
    objects = _objects(task)
    bindings: list[dict[str, str]] = [{}]
    for atom in positive:  # a join, one static atom at a time
        bindings = [
            {**b, **dict(zip(atom.args, args, strict=True))}
            for b in bindings
            for args in static.get(atom.predicate, ())
            if _matches(atom.args, args, b)
        ]
    free = [v for v in a.parameters if not any(v.name in atom.args for atom in positive)]
    out = []
    for b in bindings:
        for values in itertools.product(*(objects.get(v.types[0], ()) for v in free)):
            full = {**b, **{v.name: o for v, o in zip(free, values, strict=True)}}
            typed = all(full[v.name] in objects.get(v.types[0], ()) for v in a.parameters)
            if typed and all(_holds(t, full, static) for t in tests):
                out.append(full)
    return out


def _matches(args: tuple[str, ...], values: tuple[str, ...], binding: dict[str, str]) -> bool:
    """Do the atom's terms match these values, under the binding and with itself?"""
    seen = dict(binding)
    for x, y in zip(args, values, strict=True):
        if (seen.setdefault(x, y) if x.startswith("?") else x) != y:
            return False
    return True


def _holds(f: m.Formula, b: dict[str, str], static) -> bool:
    atom, negated = (f.part, True) if isinstance(f, m.Not) else (f, False)
    args = tuple(b.get(x, x) for x in atom.args)
    value = args[0] == args[1] if atom.predicate == "=" else args in static.get(atom.predicate, ())
    return value != negated


def _objects(task: CompiledTask) -> dict[str, set[str]]:
    parents = task.domain.type_parents
    out: dict[str, set[str]] = {}
    for obj in (*task.domain.constants, *task.problem.all_objects):
        for t in ancestors(obj.types, parents):
            out.setdefault(t, set()).add(obj.name)
    return out
