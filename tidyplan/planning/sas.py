"""Ground operators in Fast Downward's SAS format (version 3): one binary variable per fluent
fact, value 0 true. `keep` prepares an operator to be kept across tasks and `final` fits it to
the facts the current task reaches; `sas` writes the task the search binary reads."""

from __future__ import annotations

import io
from dataclasses import dataclass

from tidyplan.planning.fragment import Fact, OutsideFragment


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


@dataclass(frozen=True, slots=True)
class Kept:
    generic: Operator
    facts: frozenset  # every fluent fact it names
    whole: Operator | None  # as it is where all of them can be reached (most operators, mostly)


def keep(op: Operator | None) -> Kept | None:
    if op is None:
        return None
    facts = frozenset([f for f, _ in op.precondition] + [f for _, f, _ in op.effects]
                      + [c for cond, _, _ in op.effects for c, _ in cond])  # fmt: skip
    return Kept(op, facts, _finalize(op, facts))


def final(kept: Kept, reached: set) -> Operator | None:
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
