"""Why the loop replans: the five causes, and nothing else (Brenner & Nebel's monitoring).

(i) the next action's precondition is false in the belief; (ii) the rest of the plan no longer
reaches the goal from the belief; (iii) an assumption the plan relies on is contradicted by an
observation; (iv) the execution layer reports that recovery is exhausted; (v) an observation
brings an object that the plan can use and that binds to no virtual object in it. A plan for a
horizon (the nearest dozen items of a larger room, ``monitor.goals``) has no use for one more:
there the new item waits for the next goal, and (v) does not apply.
"""

from __future__ import annotations

from dataclasses import replace
from enum import Enum


class Cause(Enum):
    INITIAL = "initial"  # the first plan of a mission, not a replan
    PRECONDITION = "precondition_failed"  # (i)
    PLAN_INVALID = "plan_invalid"  # (ii)
    ASSUMPTION = "assumption_contradicted"  # (iii)
    RECOVERY = "recovery_exhausted"  # (iv)
    NEW_OBJECT = "new_object"  # (v)


REPLAN_CAUSES = tuple(c for c in Cause if c is not Cause.INITIAL)


def check_assumptions(pending, belief) -> list[tuple[object, bool, str]]:
    """(assumption, holds, why) for each pending ``assume-item-near o w`` the belief decides, in
    order, up to the first contradicted (cause (iii)): it holds when o (bound) is grasped from w;
    it is contradicted when o is bound elsewhere, or when the robot has looked from w without
    finding o. The others wait."""
    facts = belief.poses()  # where each item is grasped from: no pair of the map needed
    out = []
    for a in pending:
        item, w = a.args
        known = belief.items.get(item)
        if known is not None:
            ok = facts.grasp.get(item) == w
            why = f"{a.text}: {item} is at {facts.grasp.get(item)}"
        elif w in belief.exploration.looked_from:
            ok, why = False, f"{a.text}: not seen from {w}"
        else:
            continue
        out.append((a, ok, why))
        if not ok:
            break
    return out


def bind(new, steps, pending, goal, virtual, bound, belief, emit):
    """Goebelbecker's binding: each new item of a category that a virtual object of the plan
    stands for (one the steps still use, not bound yet) takes its place, in the steps, the
    pending assumptions and the goal; the plan's assumption about it, still ahead, becomes
    pending, to be checked at once. ``bound`` (virtual -> item) is updated in place. Returns
    (steps, pending, goal, unbound): the new items left that the plan could use (a category the
    room should hold), each a cause (v)."""
    unbound = []
    planned = {a for s in steps + pending for a in s.args}
    for name in new:
        cat = belief.items[name].category
        match = [v for v, c in virtual if c == cat and v in planned and v not in bound]
        if match:
            v = match[0]
            bound[v] = name
            steps = [_rename(s, v, name) for s in steps]
            pending = [_rename(s, v, name) for s in pending]
            ahead = [s for s in steps if s.assumption and name in s.args]
            steps = [s for s in steps if s not in ahead]
            pending += ahead
            goal = [name if g == v else g for g in goal]
            emit("bind", virtual=v, item=name)
        elif cat in belief.categories:
            unbound.append(name)
    return steps, pending, goal, unbound


def _rename(step, old: str, new: str):
    return replace(step, args=tuple(new if a == old else a for a in step.args))
