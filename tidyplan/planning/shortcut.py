"""Plans without detours: two steps of one action whose arguments chain, replaced by one.

LAMA's plans on the tidy domain drive through places where the robot does nothing: from an item
to a deposit by way of another deposit, ``(move a b) (move b c)`` where ``(move a c)`` is open
and shorter. Its improving searches leave many such detours within a mission's second: in
WRS Task 1's room they were 45 m of the 170-220 m a mission drove (docs/results.md). This is
plan post-processing in the manner of action elimination: a local rewrite, kept only where the
simulation proves it sound and it costs less.

Steps ``(op x.. y..)`` then ``(op y.. z..)`` (the first's last arguments the second's first)
become ``(op x.. z..)`` where that step is applicable where the first was, leaves exactly the
state the two left (so the rest of the plan runs as before), costs less than the two together
and is at least as likely to succeed as both. A ``keep`` object is never passed over: the
mission keeps its stops at viewpoints (a look there is what the model does not price).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from tidyplan.pddl.compile import CompiledTask
from tidyplan.pddl.simulate import Simulator

EPSILON = 1e-9


def shortcut(steps, task: CompiledTask, keep: Callable[[str], bool] = lambda obj: False) -> list:
    """The plan ``steps`` (``tidyplan.planning.planner.Step``) with its detours taken out."""
    if len(steps) < 2:
        return list(steps)
    compiled: dict[str, list[str]] = {}
    for name, info in task.info.items():
        compiled.setdefault(info.name, []).append(name)
    sim = Simulator(task.source_domain, task.source_problem)
    state = sim.initial_state(task.source_problem)
    # Where no two steps in a row could merge even by the facts that never change (a visit-all
    # plan's moves, whose cells are not adjacent), nothing is simulated: on a 1,600-step plan
    # over 8,000 facts the simulation was 0.97 s of 7.9 s (docs/planner.md)
    pairs = ((a, _merged(a, b, compiled, keep)) for a, b in zip(steps, steps[1:], strict=False))
    if not any(m is not None and sim.statically_possible(state, a.name, m[0]) for a, m in pairs):
        return list(steps)
    out: list = []
    before: list = []  # the state each step of ``out`` is applied in
    for step in steps:
        if out and (merged := _merged(out[-1], step, compiled, keep)) is not None:
            one = _one(out[-1], step, *merged, before[-1], state, sim, task)
            if one is not None:
                out[-1], state = one, sim.apply(state, step.name, step.args)
                continue
        out.append(step)
        before.append(state)
        state = sim.apply(state, step.name, step.args)
    return out


def _one(a, b, args, name, before, between, sim: Simulator, task: CompiledTask):
    """The step ``args`` in place of ``a`` then ``b`` (``a`` applied in ``before``, ``b`` in
    ``between``), where it is sound and better; else None."""
    if not sim.applicable(before, a.name, args):
        return None
    if sim.apply(before, a.name, args) != sim.apply(between, b.name, b.args):
        return None
    cost, probability = task.step_cost(name, args), task.step_probability(name, args)
    if cost >= a.cost + b.cost - EPSILON or probability < a.probability * b.probability - EPSILON:
        return None
    return replace(a, args=args, cost=cost, probability=probability)


def _merged(a, b, compiled: dict[str, list[str]], keep) -> tuple[tuple[str, ...], str] | None:
    """The one step's arguments and compiled name for ``a`` then ``b``, or None where they do
    not chain (or the action has more than one compiled form, whose costs differ)."""
    if a.name != b.name or a.assumption or b.assumption or len(compiled.get(a.name, ())) != 1:
        return None
    k = len(a.args)
    for p in range(1, k):
        shared = a.args[p:]
        if shared == b.args[: k - p] and not any(keep(o) for o in shared):
            args = a.args[:p] + b.args[k - p :]
            if args != a.args:
                return args, compiled[a.name][0]
    return None
