"""O-FSM strata as a lexicographic ranking of plans (Yan et al., Sec. IV).

The operator sets are nested, P1 ⊂ P2 ⊂ P3 (`:stratum K` puts an operator in
P_K and every set above). Occam's razor, Eq. (1): prefer the plan that needs the
simplest set. So the planner first plans with strata 1..1; only when that has no
plan does it try 1..2, and so on. A stratum-K+1 operator is never chosen while a
plan within 1..K exists, however much cheaper it would be; within a set, the
Göbelbecker criterion decides (see `tidyplan.pddl.criterion`).

The state-transition table of the paper (Table I) follows: a plan's stratum is
the highest stratum of its operators, and the trace records each change.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import TypeVar

from tidyplan.pddl.compile import CompiledTask

R = TypeVar("R")

STRATEGIES = {"ofsm": None, "greedy": 1}  # a mission's strategy -> the highest stratum it may use


class Outcome(Enum):
    """How one attempt within a stratum ended."""

    SOLVED = "solved"
    UNSOLVABLE = "unsolvable"  # proven: no plan within these strata
    GAVE_UP = "gave-up"  # an incomplete search ended without a plan: none proven impossible
    OUT_OF_TIME = "out-of-time"  # no plan within the first-plan limit: nothing proven
    ERROR = "error"


@dataclass(frozen=True, slots=True)
class Attempt:
    stratum: int
    outcome: Outcome
    seconds: float


def plan_by_strata(
    task: CompiledTask,
    solve: Callable[[CompiledTask], tuple[Outcome, R | None, float]],
    max_stratum: int | None = None,
    escalate_unproven: bool = True,
) -> tuple[R | None, int | None, list[Attempt]]:
    """Solve with strata 1..K for K = 1, 2, ...; return the first plan found.

    `solve` runs one planner call on a restricted task and says how it ended.
    An attempt out of time ends the search: a stratum K+1 plan is never taken because 1..K
    could not be planned in time (Occam's razor: only once 1..K has none). With
    `escalate_unproven`, an incomplete search that ended without a plan (no proof either) moves
    on to the next stratum; the attempts show it (`Attempt.outcome`, `unproven_below`).
    """
    attempts: list[Attempt] = []
    for k in task.strata:
        if max_stratum is not None and k > max_stratum:
            break
        outcome, result, seconds = solve(task.restrict(k))
        attempts.append(Attempt(k, outcome, seconds))
        if outcome is Outcome.SOLVED:
            return result, k, attempts
        if outcome in (Outcome.ERROR, Outcome.OUT_OF_TIME) or (
            outcome is Outcome.GAVE_UP and not escalate_unproven
        ):
            break
    return None, None, attempts


def unproven_below(attempts) -> bool:
    """Did a lower stratum give up without proof before the one that planned? (the plan may not
    be the one Occam's razor picks: Table II counts such deliveries apart)."""
    return any(a.outcome is Outcome.GAVE_UP for a in attempts[:-1])


# Table I of the O-FSM paper: (from plan, to plan) → why the robot switches.
TRANSITIONS: dict[tuple[int, int], str] = {
    (1, 1): "object delivered",
    (1, 2): "p_d unreachable",
    (2, 1): "object delivered",
    (2, 3): "p_i unreachable",
    (3, 1): "object delivered",
}


def transition(previous: int | None, current: int) -> str | None:
    """The paper's reason for moving from plan P_previous to P_current, if it names one."""
    if previous is None:
        return None
    return TRANSITIONS.get((previous, current))
