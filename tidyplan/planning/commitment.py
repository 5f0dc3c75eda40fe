"""What the success-probability threshold is applied to: the part of a plan the robot commits to.

Goebelbecker et al. (Fig. 3(c)) stop when no plan reaches the goal with a success probability
above a threshold. In a tidy-up room p(pi) is the product over every grasp, delivery and
assumption of the whole room: 30 to 50 factors for 12 objects, hundreds for 96, so it falls
under any fixed threshold as the room fills, however good each step is. The criterion
c(pi) + R(1 - p(pi)) still ranks whole plans (the planner minimises it); the threshold is a
different question, "is what I do next worth doing?", and the loop asks it of the plan's
*commitment*: its steps up to and including the first one that achieves a goal fact (in the tidy
domain the first delivery). After that step the loop replans or keeps the plan anyway, so the
rest is never committed to before it is looked at again.

The rule, as the loop applies it (``tidyplan.loop.loop``):
1. plan for the whole goal; adopt the plan when its commitment's p is at least the threshold;
2. otherwise narrow the goal (the items seen; those that have a plan alone) and apply 1 to each;
3. give up only when no narrowed goal has a plan whose commitment passes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from tidyplan.pddl import model as m
from tidyplan.pddl.simulate import Simulator, State
from tidyplan.planning.planner import Step


def goal_atoms(goal: m.Formula) -> list[m.Formula]:
    """The conjuncts of a goal: each is a goal fact the plan achieves at some step."""
    if isinstance(goal, m.And):
        return [a for part in goal.parts for a in goal_atoms(part)]
    return [goal]


def commitment(steps: Sequence[Step], sim: Simulator, state: State, goal: m.Formula) -> tuple[Step, ...]:
    """The plan's steps up to and including the first that makes a goal conjunct true that was
    false before it (the whole plan when no step does), less the assumptions about objects none
    of those actions uses: a planner may put every assumption first, but the robot commits only
    to those its next actions rely on (an assumption's first argument is its object)."""
    open_ = [g for g in goal_atoms(goal) if not sim.holds(g, state)]
    prefix = tuple(steps)
    for i, s in enumerate(steps):
        if not sim.applicable(state, s.name, s.args):
            prefix = tuple(steps[: i + 1])  # an ill-formed plan: commit to nothing beyond this
            break
        state = sim.apply(state, s.name, s.args)
        if any(sim.holds(g, state) for g in open_):
            prefix = tuple(steps[: i + 1])
            break
    used = {a for s in prefix if not s.assumption for a in s.args}
    return tuple(s for s in prefix if not s.assumption or (s.args and s.args[0] in used))


def probability(steps: Sequence[Step]) -> float:
    """The success probability of a sequence of steps: the product of theirs."""
    return math.prod(s.probability for s in steps)
