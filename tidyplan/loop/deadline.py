"""Against the clock: the items worth the most score in the time left (docs/loop.md).

The WRS referee stops a Task 1 run after 15 minutes and counts what is in the deposits then.
Where everything the robot knows of will not fit in the time left, the loop's first goal is the
route that scores most within it: an oversubscription problem (more goals than time), solved as
an orienteering tour before the planner orders its part of it. Each job is one item, taken where
it lies (or already in the hand) and put into the nearest deposit that accepts it; it is worth
the rulebook's points (20: in a deposit of its category; 30 for an orientation item, which
stands in its box). Closed drawers are opened first or not at all: opening every one is worth
the rulebook's 50, and their categories' items can go in only then.

A route is built by the ratio insertion of orienteering heuristics (the job and place in the
route that add the most points per second added, while the route fits), then shortened by 2-opt
and or-opt moves and filled again. Seconds are the robot's: the map's path lengths at its speed,
a stop for each drive, and the means of a take, a put and a pull (``TAKE_S``, ``PUT_S``,
``PULL_S``). The planner gets the route's first ``HORIZON`` items (and the drawers, where the
route opens them) as its goal; the rest are put off, and the trace says so (``deadline``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sim.scenario.model import ORIENTATION
from tidyplan.belief.mapfacts import MapFacts, deposit_waypoint
from tidyplan.belief.problem import STOP_S, robot_waypoint
from tidyplan.belief.state import Belief

# s: what the pybullet HSR took on average in an earlier Task 1 sweep (docs/results.md): a take
# with its close look and base adjustment, a put into a deposit, a pull of a drawer's handle; a
# drive takes STOP_S beyond its length over the base's speed, as the planner's costs have it.
# Neither the domain's costs (5.7 / 10.2 / 13.5) nor today's means (a take 5.3 s): the route has
# no looks or replans in it, and its take's extra second stands for them (with the domain's,
# two of the ten Task 1 rooms of docs/results.md scored less within 900 s in pybullet, 530 to
# 480 and 510 to 490, each again when run alone; the others the same)
TAKE_S, PUT_S, PULL_S = 6.7, 10.3, 13.1
POINTS, ORIENTATION_POINTS, DRAWERS_POINTS = 20.0, 10.0, 50.0  # tidyplan.trace.score's rulebook


@dataclass(frozen=True, slots=True)
class Job:
    item: str
    start: str | None  # the grasp waypoint (None: the item is in the hand)
    category: str
    points: float


@dataclass(frozen=True, slots=True)
class Deadline:
    """The route chosen for the time left, and what it leaves for after."""

    left_s: float  # simulated seconds to the limit
    everything_s: float  # the estimate for every item the robot can reach now
    route: tuple[str, ...]  # items, in the route's order
    drawers: tuple[str, ...]  # closed drawers the route opens first
    put_off: tuple[str, ...]  # seen items left for after the limit
    seconds: float  # the route's estimate
    points: float  # its score, the drawers' 50 included

    def why(self) -> str:
        if not self.route:
            return (
                f"everything known would take {self.everything_s:.0f} s and {self.left_s:.0f} s are left: "
                f"no item fits; {len(self.put_off)} put off"
            )
        return (
            f"everything known would take {self.everything_s:.0f} s and {self.left_s:.0f} s are left: "
            f"{len(self.route)} items{' and the drawers' if self.drawers else ''} worth "
            f"{self.points:g} points in {self.seconds:.0f} s first, {len(self.put_off)} put off"
        )


def deadline(belief: Belief, facts: MapFacts, left_s: float) -> Deadline | None:
    """The route for the ``left_s`` seconds to the limit, or None where everything fits in them
    (the loop then plans for everything) or the robot knows of nothing to take."""
    here = robot_waypoint(facts, belief)
    speed = belief.scenario.robot.speed
    oriented = any(d.category == ORIENTATION for d in belief.scenario.deposits)
    jobs = []
    for k in belief.untidied():
        if k.name in belief.undeliverable:
            continue
        category = ORIENTATION if k.oriented and oriented else k.category
        points = POINTS + (ORIENTATION_POINTS if category == ORIENTATION else 0.0)
        if k.state == "held":
            jobs.append(Job(k.name, None, category, points))
        elif k.state == "placed" and k.name in facts.grasp:
            jobs.append(Job(k.name, facts.grasp[k.name], category, points))
    if not jobs:
        return None

    def drive(a: str, b: str) -> float:
        if a == b:
            return 0.0
        d = facts.path.get((a, b))
        return math.inf if d is None else d / speed + STOP_S

    closed = sorted(belief.closed - belief.undeliverable)
    options = [_Option(belief, jobs, drive, here, (), 0.0)]
    if closed:
        at, t, left = here, 0.0, list(closed)
        while left:  # nearest first, as the floor opens them (bench/floor.py)
            d = min(left, key=lambda d: (drive(at, deposit_waypoint(d)), d))
            t += drive(at, deposit_waypoint(d)) + PULL_S
            at = deposit_waypoint(d)
            left.remove(d)
        if math.isfinite(t):
            options.append(_Option(belief, jobs, drive, at, tuple(closed), t))
    whole = options[-1]  # with the drawers open (where any is closed), every job can be done
    everything = whole.t0 + whole.route_cost(whole.fill(whole.doable(), math.inf))
    if everything <= left_s:
        return None
    best = None
    for o in options:
        route = o.best_route(left_s - o.t0)
        points = sum(o.jobs[j].points for j in route)
        if o.drawers and route:  # the bonus counts once an object is in (tidyplan.trace.score)
            points += DRAWERS_POINTS
        seconds = o.t0 + o.route_cost(route)
        if best is None or (points, -seconds) > (best[0], -best[1]):
            best = (points, seconds, o, route)
    points, seconds, o, route = best
    chosen = tuple(o.jobs[j].item for j in route)
    put_off = tuple(sorted(j.item for j in jobs if j.item not in chosen))
    drawers = o.drawers if route else ()
    return Deadline(left_s, everything, chosen, drawers, put_off, seconds, points)


class _Option:
    """Jobs from ``start`` after ``t0`` seconds (the drawers ``drawers`` opened by then)."""

    def __init__(self, belief: Belief, jobs: list[Job], drive, start: str, drawers, t0: float) -> None:
        self.drive, self.start, self.drawers, self.t0 = drive, start, drawers, t0
        still_closed = belief.closed - set(drawers)
        self.jobs: list[Job] = []
        self.fixed: list[float] = []  # a job's seconds from its grasp waypoint to its deposit's
        self.end: list[str] = []  # where a job leaves the robot
        for job in jobs:
            deposits = [
                deposit_waypoint(d.name)
                for d in belief.scenario.deposits
                if d.category == job.category and d.name not in still_closed
            ]
            start_wp = job.start if job.start is not None else start
            best = min(deposits, key=lambda w: (drive(start_wp, w), w), default=None)
            if best is None or not math.isfinite(drive(start_wp, best)):
                continue
            self.jobs.append(job)
            self.fixed.append((TAKE_S if job.start is not None else 0.0) + drive(start_wp, best) + PUT_S)
            self.end.append(best)
        # the item in the hand goes first: nothing else can be taken before it is put away
        self.held = next((j for j, job in enumerate(self.jobs) if job.start is None), None)

    def doable(self) -> list[int]:
        return [] if self.held is None else [self.held]

    def _from(self, j: int) -> str:
        job = self.jobs[j]
        return job.start if job.start is not None else self.start

    def route_cost(self, route: list[int]) -> float:
        t, at = 0.0, self.start
        for j in route:
            t += self.drive(at, self._from(j)) + self.fixed[j]
            at = self.end[j]
        return t

    def fill(self, route: list[int], budget: float) -> list[int]:
        """Ratio insertion: the job and the place adding the most points per second, while the
        route fits in ``budget``."""
        route = list(route)
        cost = self.route_cost(route)
        left = [j for j in range(len(self.jobs)) if j not in route]
        while left:
            best = None
            first = 1 if self.held is not None and route[:1] == [self.held] else 0
            for j in left:
                for p in range(first, len(route) + 1):
                    a = self.start if p == 0 else self.end[route[p - 1]]
                    added = self.drive(a, self._from(j)) + self.fixed[j]
                    if p < len(route):
                        b = self._from(route[p])
                        added += self.drive(self.end[j], b) - self.drive(a, b)
                    if not math.isfinite(added) or cost + added > budget:
                        continue
                    ratio = self.jobs[j].points / max(added, 1e-6)
                    key = (ratio, -added, -j, -p)
                    if best is None or key > best[0]:
                        best = (key, j, p, added)
            if best is None:
                break
            _, j, p, added = best
            route.insert(p, j)
            cost += added
            left.remove(j)
        return route

    def best_route(self, budget: float) -> list[int]:
        if budget <= 0:
            return []
        route = self.fill(self.doable(), budget)
        shorter = improve(route, self.route_cost, fixed_first=self.held is not None)
        return self.fill(shorter, budget)


def improve(order: list[int], cost, fixed_first: bool = False) -> list[int]:
    """2-opt (reverse a stretch) and or-opt (move one job elsewhere) until neither helps;
    ``fixed_first``: the first job stays first (the item in the hand)."""
    best, c = list(order), cost(order)
    lo = 1 if fixed_first else 0
    better = True
    while better:
        better = False
        n = len(best)
        for i in range(lo, n - 1):
            for k in range(i + 1, n):
                cand = best[:i] + best[i : k + 1][::-1] + best[k + 1 :]
                cc = cost(cand)
                if cc < c - 1e-9:
                    best, c, better = cand, cc, True
        for i in range(lo, n):
            for k in range(lo, n):
                if i == k:
                    continue
                cand = best[:i] + best[i + 1 :]
                cand.insert(k, best[i])
                cc = cost(cand)
                if cc < c - 1e-9:
                    best, c, better = cand, cc, True
    return best
