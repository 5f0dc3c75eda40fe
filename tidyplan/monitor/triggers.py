"""Why the loop replans: the five causes, and nothing else (Brenner & Nebel's monitoring).

(i) the next action's precondition is false in the belief; (ii) the rest of the plan no longer
reaches the goal from the belief; (iii) an assumption the plan relies on is contradicted by an
observation; (iv) the execution layer reports that recovery is exhausted; (v) an observation
brings an object that the plan can use and that binds to no virtual object in it.
"""

from __future__ import annotations

from enum import Enum


class Cause(Enum):
    INITIAL = "initial"  # the first plan of a mission, not a replan
    PRECONDITION = "precondition_failed"  # (i)
    PLAN_INVALID = "plan_invalid"  # (ii)
    ASSUMPTION = "assumption_contradicted"  # (iii)
    RECOVERY = "recovery_exhausted"  # (iv)
    NEW_OBJECT = "new_object"  # (v)


REPLAN_CAUSES = tuple(c for c in Cause if c is not Cause.INITIAL)
