"""Which goals the loop plans for, in the order it tries them (docs/loop.md, "Goals").

Narrowing the goal is how the loop keeps tidying when the whole goal has no plan, or none whose
commitment is likely enough: an item out of reach, unseen items no viewpoint can reveal. In a
room with more items than one plan should hold, the first goal is a horizon: the items nearest
the robot, as many as the paper's room; against the clock, the route worth the most score in
the time left comes before it (``tidyplan.loop.deadline``).
"""

from __future__ import annotations

from tidyplan.belief.mapfacts import MapFacts
from tidyplan.belief.problem import robot_waypoint
from tidyplan.belief.state import Belief
from tidyplan.loop.deadline import Deadline

# Items one plan is made for, at most: the paper's room. The commitment is one delivery, so a plan
# over the nearest dozen serves as well as one over the whole room, and planning time stays that
# of a 12-object room (a 48-object problem took Fast Downward 110 s here to plan for all at once).
HORIZON = 12

Goal = tuple[str, list[str], list[tuple[str, str]]]  # (label, items, virtual objects among them)


def goals(belief: Belief, facts: MapFacts, against: Deadline | None = None) -> list[Goal]:
    """The goals to try (item names, and the names of closed drawers to open): ``deadline``
    first where the robot is ``against`` the clock (``tidyplan.loop.deadline``: the route's first
    HORIZON items, and the drawers it opens); ``horizon`` (in a
    room of more than HORIZON items: the HORIZON seen items nearest the robot, those it can drive
    to now first, then unseen ones up to HORIZON, a few of each category); ``all``; ``seen`` (when
    ``all`` has virtual objects); last the seen items, from which the loop keeps those that have a
    plan on their own (``feasible``: nearest first in a room of more than HORIZON items, so the
    loop can stop once it has HORIZON of them)."""
    seen = [k.name for k in belief.untidied() if k.state == "held" or k.name in facts.grasp]
    virtual = belief.virtual() if belief.exploration.p_item_near(facts) else []
    # the drawers still closed, to be opened (the WRS rulebook's +50 for opening every drawer):
    # in the whole goal and the horizon, never in the narrower ones, which must not fail for them
    opens = sorted(d for d in belief.closed if d not in belief.undeliverable)
    out: list[Goal] = [("all", seen + [v for v, _ in virtual] + opens, virtual)]
    order = seen  # the order feasible items are looked for in
    if len(seen) + len(virtual) > HORIZON:
        here = robot_waypoint(facts, belief)

        def distance(g: str) -> tuple[int, float]:
            if g == belief.holding:
                return (0, 0.0)
            w = facts.grasp[g]
            if (here, w) in facts.path:
                return (0, facts.path[(here, w)])
            return (1, facts.distance(here, w) or float("inf"))

        order = sorted(seen, key=lambda g: (distance(g), g))
        near = order[:HORIZON]
        by_number = sorted(virtual, key=lambda v: (int(v[0].rsplit("-", 1)[1]), v[1]))
        some = by_number[: HORIZON - len(near)]
        out.insert(0, ("horizon", near + [v for v, _ in some] + opens, some))
    if against is not None and against.route:
        out.insert(0, ("deadline", list(against.route[:HORIZON]) + list(against.drawers), []))
    if virtual:
        out.append(("seen", seen, []))
    return out + [("feasible", order, [])]
