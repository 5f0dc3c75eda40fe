"""Moves and looks the loop makes outside any plan (docs/loop.md, "Exploration").

- Before a mission ends, the robot looks into the deposits. An item the belief marked tidied can
  leave its tray without the robot seeing it (knocked out by the next one put in, or by a
  fall). The loop drives to each deposit that should hold items and looks into it, several
  close looks until every item believed there has been seen; an item that none shows is lost
  to the belief, to be found and tidied again. The deposits are visited on the shortest tour
  the robot finds from where it stands (``inspection_tour``): in the scenario's order
  wrs-task1-s000's tour drove 5.89 m, on the shortest 4.35 m (pybullet, ``--planner lama-first``).
- A deposit the robot has just put an item into, when nothing the belief knows of or expects
  is left for it, is looked into there and then: the robot stands at it already, so the tour at
  the end leaves it out, unless something is put into it after that look. The ten Task 1 rooms
  spent 42 s each after their last put, touring the deposits.
- Before it gives up on an item no plan reaches, the robot drives to a waypoint from which a
  look should see it, and looks: a false detection, or an item that moved, is forgotten there.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter

from tidyplan.belief.mapfacts import MapFacts, deposit_waypoint
from tidyplan.belief.percepts import Detection
from tidyplan.belief.problem import robot_waypoint
from tidyplan.belief.state import Belief
from tidyplan.loop.deadline import improve
from tidyplan.planning.planner import Step
from tidyplan.trace import events

# Close looks into a deposit until every item believed there is seen: an item missed by all five
# at the false-negative rate 0.2 happens 1 time in 3125
LOOKS_INTO = 5
# m: one item seen by two looks into a deposit from where the robot stands (nothing moves it
# between them: the detections agree to the millimetre); items in a deposit may stand nearer
# than a centimetre (1.7 cm in the symbolic world's trays, 3 mm leaning in pybullet's)
SAME_PLACE = 0.005
NO_WAY = 1e3  # m: a leg between two waypoints the map has no path for (blocked now), last resort
EXACT_TOUR = 10  # deposits: up to this many, the shortest tour is worked out exactly (0.1 s at 10)


def distinct(shown: list[Detection], look: list[Detection]) -> list[Detection]:
    """The items ``shown`` by earlier looks into a deposit and those of one more ``look``. Each
    of a look's detections is an item of its own, however near another: two markers standing in
    container B 3 mm apart (wrs-task1-s406) were one item by their places rounded to the
    centimetre, and the other was lost to the belief and looked for in three rounds of
    exploration (1794 s for the mission; 1419 s counted as two). A detection is an item shown
    before when the nearest one of its category that no earlier detection of this look took is
    within SAME_PLACE of it."""
    out, matched = list(shown), set()
    for d in look:
        near = [
            (math.dist((s.x, s.y), (d.x, d.y)), i)
            for i, s in enumerate(shown)
            if i not in matched and s.category == d.category
        ]
        best = min(near, default=None)
        if best is not None and best[0] <= SAME_PLACE:
            matched.add(best[1])
        else:
            out.append(d)
    return out


def inspection_tour(facts: MapFacts, start: str, deposits: list[str]) -> list[str]:
    """``deposits`` in the order of the shortest open tour from waypoint ``start``, by the map's
    path lengths: exact (Held and Karp's dynamic programme) for up to EXACT_TOUR of them, else
    nearest neighbour improved by 2-opt and or-opt. From the middle of a row of deposits, the
    best tour goes to the near end first; moving one deposit at a time does not find that."""
    here = [d for d in deposits if deposit_waypoint(d) == start]  # looked into first: no drive
    names = sorted(set(deposits) - set(here))
    stops = [deposit_waypoint(d) for d in names]

    def leg(a: str, b: str) -> float:
        d = 0.0 if a == b else facts.distance(a, b)
        return NO_WAY if d is None else d

    if len(names) <= EXACT_TOUR:
        return here + [names[k] for k in _shortest_open_tour(leg, start, stops)]

    def length(order: list[int]) -> float:
        way = [start] + [stops[k] for k in order]
        return sum(leg(a, b) for a, b in zip(way[:-1], way[1:], strict=True))

    left, at, order = list(range(len(names))), start, []
    while left:
        nearest = min(left, key=lambda k: (leg(at, stops[k]), k))
        left.remove(nearest)
        order.append(nearest)
        at = stops[nearest]
    better = improve(list(range(len(order))), lambda ix: length([order[i] for i in ix]))
    return here + [names[order[i]] for i in better]


def _shortest_open_tour(leg, start: str, stops: list[str]) -> list[int]:
    """Held and Karp: the cheapest way from ``start`` through every stop, ending anywhere."""
    n = len(stops)
    if n == 0:
        return []
    # best[(visited, last)] = (length, previous stop)
    best = {(1 << k, k): (leg(start, stops[k]), -1) for k in range(n)}
    for size in range(2, n + 1):
        for visited in (sum(1 << k for k in ks) for ks in itertools.combinations(range(n), size)):
            for last in (k for k in range(n) if visited >> k & 1):
                before = visited & ~(1 << last)
                best[(visited, last)] = min(
                    (best[(before, k)][0] + leg(stops[k], stops[last]), k)
                    for k in range(n)
                    if before >> k & 1
                )
    full = (1 << n) - 1
    last = min(range(n), key=lambda k: (best[(full, k)][0], k))
    order, visited = [], full
    while last != -1:
        order.append(last)
        visited, last = visited & ~(1 << last), best[(visited, last)][1]
    return order[::-1]


class Excursions:
    """The moves and looks the loop makes outside any plan, each run by the executor (the loop's
    door to the robot) and traced as an action of its own: ``observe(detections, waypoint, why)`` takes
    in what the looks on the way saw, ``emit`` traces, ``count`` counts the actions."""

    def __init__(self, belief: Belief, executor, observe, emit, count) -> None:
        self.belief, self.executor, self.observe, self.emit, self.count = (
            belief,
            executor,
            observe,
            emit,
            count,
        )

    def move(self, to: str, purpose: str, snapshot):
        """Drive to waypoint ``to`` (for ``purpose``: inspect_deposit, look_again); returns the
        executor's report."""
        belief = self.belief
        step = Step("move", (belief.robot_wp, to), False, 1, 1.0, 0.0)
        report = self.executor.drive(to, snapshot, belief, self.observe)
        self.count.action(step, report, belief.holding is not None)
        self.emit("action", **events.action(step.text, None, report, belief.robot, purpose=purpose))
        return report

    def inspect(self, deposit: str, snapshot) -> list[str]:
        """Drive to ``deposit`` and look into it up to LOOKS_INTO times until each item believed
        there is seen; returns the items lost (not there)."""
        report = self.move(deposit_waypoint(deposit), "inspect_deposit", snapshot)
        if not report.ok:
            return []
        return self.look_into(deposit)

    def look_into(self, deposit: str) -> list[str]:
        """Look into ``deposit`` from where the robot stands at it, up to LOOKS_INTO times until
        each item believed there is seen; returns the items lost (not there)."""
        believed = Counter(k.category for k in self.belief.in_deposit(deposit))
        shown: list[Detection] = []  # distinct items over the looks
        for _ in range(LOOKS_INTO):
            shown = distinct(shown, self.executor.look_into(deposit))
            if Counter(d.category for d in shown) >= believed:
                break
        confirmed, lost = self.belief.inspect_deposit(deposit, shown)
        self.emit("inspect_deposit", deposit=deposit, confirmed=confirmed, lost=lost)
        return lost

    def go_and_look(self, went: Counter, most: int, snapshot) -> bool:
        """Drive to the nearest waypoint from which a look should see a believed item (placed,
        looked at fewer than ``most`` times this way, counted in ``went``), and look; False if
        there is none. The look is the executor's, after the move."""
        belief = self.belief
        facts = belief.facts()
        here = robot_waypoint(facts, belief)
        boxes = belief.item_boxes()
        for k in belief.untidied():
            if k.state != "placed" or went[k.name] >= most:
                continue
            views = [
                w
                for w, q in facts.points.items()
                if (here, w) in facts.path and belief.should_see(k, q, boxes)
            ]
            if not views:
                continue
            w = min(views, key=lambda w: (facts.path[(here, w)], w))
            went[k.name] += 1
            self.emit("look_again", looks_left=0, item=k.name, waypoint=w)
            self.move(w, "look_again", snapshot)
            return True
        return False
