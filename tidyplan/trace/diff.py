"""What changed at a replan: the plan against the rest of the plan before it, and the belief.

At replan N the loop drops what was left of the plan it was executing and adopts a new one. To
say what changed, the rest of the old plan is rebuilt from the trace: the old plan's steps,
less the assumptions passed (``assume``) and the actions executed (``action``), with the
virtual objects renamed as they were bound (``bind``), less the assumptions set aside by a
bind. The new plan is then matched against that rest in order (``difflib``): steps in both are
*kept*, steps only in the rest are *dropped*, steps only in the new plan are *added*.

The belief is compared through the problems the loop wrote from it (``replan-NNN.pddl``, the
trace's PDDL folder): the facts and values of the two ``:init`` sections. Virtual objects are
numbered afresh for each problem, so ``unseen-tool-1`` in two problems need not be one object.
"""

from __future__ import annotations

from collections import defaultdict
from difflib import SequenceMatcher

from tidyplan.errors import Diagnostic, InputError, TidyplanError
from tidyplan.trace.read import Trace, adopted

# the map's facts: many, summed up in text
BULK = ("path", "distance", "travel-time", "pose-adjustment", "blocks")


def replan_diff(trace: Trace, n: int) -> dict:
    """The problem and plan of replan ``n`` (0: the initial plan) against the plan before it."""
    plans = trace.of("plan")
    group = [p for p in plans if p.get("replan") == n]
    if not group:
        numbers = sorted({p.get("replan") for p in plans if isinstance(p.get("replan"), int)})
        known = f"{numbers[0]}..{numbers[-1]}" if numbers else "none"
        raise InputError(
            Diagnostic(str(trace.path), None, None, f"--replan {n}: no such replan (it has {known})")
        )
    chosen = adopted(trace)
    new = next((p for p in group if any(p is c for c in chosen)), group[-1])
    first = _index(trace, group[0])
    before = [c for c in chosen if _index(trace, c) < first]
    out = {
        "replan": n,
        "cause": new.get("cause"),
        "why": new.get("why", ""),
        "sim_s": new.get("sim_s"),
        "attempts": [_attempt(p) for p in group],
        "adopted": any(new is c for c in chosen),
        "plan": list(new.get("plan") or []),
        "problem": new.get("problem"),
        "previous": None,
        "executed": [],
        "rest": [],
        "kept": [],
        "dropped": [],
        "added": list(new.get("plan") or []),
        "diff": [["+", step] for step in new.get("plan") or []],
        "facts": None,
        "facts_note": "",
    }
    if not before:
        out["facts_note"] = "the initial plan: nothing before it"
        return out
    old = before[-1]
    rest, executed = _rest(trace, old, first)
    out.update(previous=_attempt(old) | {"problem": old.get("problem")}, rest=rest, executed=executed)
    out.update(_match(rest, out["plan"]))
    try:
        out["facts"] = _facts_diff(trace, old.get("problem"), new.get("problem"))
    except _Missing as e:
        out["facts_note"] = str(e)
    return out


def _attempt(p: dict) -> dict:
    keys = ("replan", "goal_kind", "status", "stratum", "cost", "probability", "planning_time_s", "message")
    return {k: p.get(k) for k in keys} | {"steps": len(p.get("plan") or [])}


def _rest(trace: Trace, old: dict, until: int) -> tuple[list[str], list[str]]:
    """The steps of ``old`` not yet passed when the event at index ``until`` was written, and
    the actions executed in between, as the loop went through them (see the module's doc)."""
    rest = [_split(s) for s in old.get("plan") or []]
    executed = []
    for e in trace.events[_index(trace, old) + 1 : until]:
        kind = e["kind"]
        if kind in ("assume", "action"):
            step = _split(e.get("action", "()"))
            if step in rest:
                rest.remove(step)
            if kind == "action":
                executed.append(e.get("action"))
        elif kind == "bind":
            v, item = e.get("virtual"), e.get("item")
            rest = [tuple(item if a == v else a for a in s) for s in rest]
            rest = [s for s in rest if not (s[0].startswith("assume") and item in s[1:])]
    return [_join(s) for s in rest], executed


def _match(rest: list[str], plan: list[str]) -> dict:
    """``diff`` interleaves the three as [mark, step] lines: " " kept, "-" dropped, "+" added."""
    kept, dropped, added, lines = [], [], [], []
    for op, i1, i2, j1, j2 in SequenceMatcher(a=rest, b=plan, autojunk=False).get_opcodes():
        if op == "equal":
            kept += rest[i1:i2]
            lines += [[" ", s] for s in rest[i1:i2]]
        if op in ("delete", "replace"):
            dropped += rest[i1:i2]
            lines += [["-", s] for s in rest[i1:i2]]
        if op in ("insert", "replace"):
            added += plan[j1:j2]
            lines += [["+", s] for s in plan[j1:j2]]
    return {"kept": kept, "dropped": dropped, "added": added, "diff": lines}


def _index(trace: Trace, event: dict) -> int:
    return next(i for i, e in enumerate(trace.events) if e is event)


def _split(step: str) -> tuple[str, ...]:
    return tuple(step.strip().strip("()").split())


def _join(step: tuple[str, ...]) -> str:
    return "(" + " ".join(step) + ")"


# ------------------------------------------------------------------ the belief
class _Missing(Exception):
    """A problem file of the trace's PDDL folder cannot be read: said in one line."""


def _facts_diff(trace: Trace, old_rel: str | None, new_rel: str | None) -> dict:
    old, new = _init(trace, old_rel), _init(trace, new_rel)
    added = sorted(new[0] - old[0])
    removed = sorted(old[0] - new[0])
    values = [
        [term, old[1].get(term), new[1].get(term)]
        for term in sorted(old[1].keys() | new[1].keys())
        if old[1].get(term) != new[1].get(term)
    ]
    return {"from": old_rel, "to": new_rel, "added": added, "removed": removed, "values": values}


def _init(trace: Trace, relative: str | None) -> tuple[set[str], dict[str, float]]:
    """The facts and numeric values of a problem's ``:init``, as text."""
    from tidyplan.pddl import model as m
    from tidyplan.pddl.reader import parse, read_text

    if not relative:
        raise _Missing("the plan event names no problem file: belief facts not compared")
    path = trace.beside(relative)
    try:
        there = path.is_file()
    except OSError as e:  # a name the OS refuses (too long, say): Path.is_file raises
        raise _Missing(
            f"the plan event's problem file cannot be had ({e.strerror}): belief facts not compared"
        ) from None
    if not there:
        folder = path.parent if path.parent != trace.path.parent else path
        raise _Missing(f"{folder}: gone (the trace's PDDL folder): belief facts not compared")
    try:
        problem = parse(read_text(path), str(path))
    except TidyplanError as e:
        raise _Missing(
            f"{path}: cannot read it ({str(e).splitlines()[0]}): belief facts not compared"
        ) from None
    if not isinstance(problem, m.Problem):
        raise _Missing(f"{path}: not a problem: belief facts not compared")
    facts = {"(" + " ".join((a.predicate, *a.args)) + ")" for a in problem.init}
    values = {"(" + " ".join((t.name, *t.args)) + ")": v for t, v in problem.values}
    return facts, values


def by_predicate(facts: list[str]) -> dict[str, list[str]]:
    """Facts grouped by predicate, in order: the text view shows the map's facts as counts."""
    groups: dict[str, list[str]] = defaultdict(list)
    for f in facts:
        groups[f.strip("()").split()[0]].append(f)
    return dict(groups)
