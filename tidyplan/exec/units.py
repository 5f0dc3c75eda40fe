"""Behaviour units of the tidy domain (``put_down`` in ``tidyplan.exec.put_down``, the drawer's in
``tidyplan.exec.drawer_units``), against an injected world (symbolic now, pybullet later).

Each unit reads and writes the belief as it goes, because only this layer knows what a grasp
means physically; the world is reached only through its skills:

    look() -> detections                 head camera sweep
    locate(near, radius, category)       close-range look (head down, hand camera) -> detection
    holds() -> bool                      the gripper's sensor
    pose() -> (x, y)                     odometry
    follow(path, monitor, careful=)      drive a path; monitor.poll() may stop it
    grasp(point), place(deposit, approach), put_down(point) -> outcome

Paths and poses are planned on the robot's own map (the static map plus the items the belief
holds), not on the truth: an obstacle nobody has seen is found by driving into it.
"""

from __future__ import annotations

import math

from tidyplan.belief.grasp import ADJUST_MAX, GRASP_BEST, GRASP_MAX, GRASP_MIN
from tidyplan.belief.mapfacts import deposit_waypoint
from tidyplan.belief.percepts import SWEEP_STOPS
from tidyplan.belief.ring import straight
from tidyplan.exec.catalogue import (
    ADJUST_BASE,
    ADJUST_POSE,
    APPROACH_DEPOSIT,
    APPROACH_HANDLE,
    GRASP,
    LOOK,
    NAVIGATE,
    PLACE,
)
from tidyplan.exec.context import AT_POSE, Context, Point
from tidyplan.exec.put_down import PutDown
from tidyplan.monitor.unit import Failure, FailureClass, StateMonitor, Unit

A, B, C = FailureClass.A, FailureClass.B, FailureClass.C

FIND_RADIUS = 0.25  # m around the believed place a close look searches for the target
FALL_SPREAD = 0.6  # m from where the hand let go that a dropped item is searched for
ADJUST_PATH_MAX = 1.5  # m: the longest careful base adjustment around an item
BUMP_RADIUS = 0.6  # m around the robot a close look searches after the base was stopped
BUMP_AHEAD = 0.4  # m ahead, along the way it was going, where that close look is aimed
MIN_FINDS = 0.05  # items a sweep is expected to find, at least, for that to be why it is taken
# s one stop adds to a sweep (pan 51 deg across, the second tilt, at 1 rad/s): a stop is swept
# where it is expected to find its share of MIN_FINDS in a whole sweep's 11 s, per second
STOP_S = 1.4
STOP_FINDS = MIN_FINDS / 11.0 * STOP_S
HIDES = 0.25  # m: an item this tall hides what lies behind it (case III's 0.45 m boxes hide a tool)


class Navigate(Unit):
    """move, move_back, possible_ego_pose_adjustment: plan a path on the robot's map, follow it.
    Carrying, the state monitor watches the hand: an item that slips out stops the robot at once
    (class C), and the pick-up is inserted before the drive goes on."""

    name, phase = NAVIGATE, "approach"

    def __init__(self, ctx: Context, goal: Point, waypoint: str, careful: bool = False) -> None:
        self.ctx, self.goal, self.waypoint, self.careful = ctx, goal, waypoint, careful
        if careful:
            self.name = ADJUST_POSE
        self.path: list[Point] = []
        self.tries = 0
        self.carrying: str | None = None
        self.touched: Point | None = None  # where the base's bumper touched what stopped it

    def check(self):
        self.tries += 1
        if self.tries > 1 and self.touched is not None:
            # the bumper touched it: it lies at the base's edge, nearer than the head camera sees
            # the floor, where a sweep finds nothing. Found by a close look, it is on the map and
            # the retry's path goes round it (wrs-task1-s000: four sweeps saw nothing, 31 s)
            self._close_look()
        elif self.tries > 1:  # what stopped it is ahead: the stops around the way it was going
            heading = _way_ahead(self.ctx.world.pose(), self.path or [self.goal])
            self.ctx.look(why="a drive stopped: what is in the way now?", stops=_stops_around(heading))
        return None

    def plan(self):
        pose = self.ctx.world.pose()
        if math.dist(pose, self.goal) < AT_POSE:
            self.path = [pose]
            return None
        room = self.ctx.belief.room
        if self.careful:
            bare = room.grid(self.ctx.floor(), bare=True)
            if math.dist(pose, self.goal) > ADJUST_MAX + 0.05 or not bare.free(*self.goal):
                return Failure(A, "no_path", "no careful pose adjustment reaches the pose")
            self.path = [pose, self.goal]
            return None
        nav = room.grid(self.ctx.floor())
        start, prefix = pose, [pose]
        if not nav.free(*pose):  # in a tight pose: back out to the nearest navigable cell first
            start = nav.nearest_free_within(pose, ADJUST_MAX + 0.05)
            if start is None:
                return Failure(A, "no_path", "boxed in")
            prefix = [pose, start]
        inner = nav.path(start, self.goal)
        if inner is None:
            return Failure(A, "no_path", "no path on the map")
        if len(inner) > 1 and start == pose and straight(nav, pose, inner[1]):
            # not back to the centre of the cell it stands in first: that step may lead into what
            # it stopped short of, an object it cannot see so close (wrs-task1-s005: a bowl that
            # fell beside the base, 3.5 cm towards it, pinned the robot at container B)
            inner = inner[1:]
        self.path = _dedupe(prefix + inner + [self.goal])
        return None

    def do(self, monitor: StateMonitor):
        failure = _drive(self.ctx, self, self.path, monitor, self.careful, self._facing())
        if failure is None:
            self.ctx.belief.at(self.goal, self.waypoint)
        return failure

    def insert_for(self, failure: Failure) -> list[Unit]:
        return _pick_up_if_dropped(self.ctx, self, failure)

    def _facing(self) -> Point | None:
        """What the robot turns to on the way, as a navigation goal's pose has it: at an item's
        grasp pose the item, at a deposit's approach the deposit (the close look and the hand
        then start facing it: no turn of their own); elsewhere nothing."""
        belief = self.ctx.belief
        for d in belief.scenario.deposits:
            if deposit_waypoint(d.name) == self.waypoint:
                return d.x, d.y
        facts = belief.poses()
        for item, w in facts.grasp.items():
            if w == self.waypoint and item in belief.items:
                return belief.items[item].x, belief.items[item].y
        return None

    def learn(self, failure: Failure) -> None:
        """A way the base could not go is blocked for the planner, from where the action started
        and from where the robot stopped; what stopped it may lie too close for the head camera,
        so a close look searches around the robot."""
        if failure.what not in ("path_blocked", "no_path"):
            return
        belief = self.ctx.belief
        belief.blocked_moves |= {(self.ctx.start or belief.robot, self.goal), (belief.robot, self.goal)}
        if failure.what == "path_blocked":
            self._close_look()

    def _close_look(self) -> None:
        """A close look where the base touched what stopped it (the bumper's side), else where it
        was going: it lies there, too near for a sweep (the head sees the floor from about 0.7 m
        out); the close look steps back for it. Ahead alone missed a low box 40 degrees aside,
        out of the camera's field (wrs-task1-s004: 750 s pinned). What it finds is on the map."""
        belief = self.ctx.belief
        found = self.ctx.world.locate(self._ahead(belief.robot, self.touched), BUMP_RADIUS)
        new = belief.bumped(found) if found is not None else None
        if new is not None:
            self.ctx.new.append(new)

    def _ahead(self, here: Point, touched: Point | None = None) -> Point:
        """The point BUMP_AHEAD m from ``here`` towards where the base ``touched`` something, or
        else along the path the base was following (``here`` itself where neither gives a
        direction)."""
        i = min(range(len(self.path)), key=lambda k: math.dist(self.path[k], here), default=0)
        to = touched if touched is not None and math.dist(touched, here) > 0.04 else None
        to = to or next((q for q in self.path[i:] if math.dist(q, here) > 0.04), None)
        if to is None:
            return here
        d = math.dist(to, here)
        return (here[0] + (to[0] - here[0]) / d * BUMP_AHEAD, here[1] + (to[1] - here[1]) / d * BUMP_AHEAD)


class AdjustBase(Unit):
    """Locate the item close up and bring the base within the arm's reach of it: no motion when
    it already is; another pose around the item when asked to approach differently."""

    name, phase = ADJUST_BASE, "approach"

    def __init__(self, ctx: Context, item: str) -> None:
        self.ctx, self.item = ctx, item
        self.target: Point | None = None
        self.reach = (GRASP_MIN, GRASP_BEST, GRASP_MAX)  # from the base to the item's centre
        self.path: list[Point] | None = None
        self.tried: list[Point] = []
        self.another = False

    def check(self):
        self.ctx.located.pop(self.item, None)
        failure = _locate(self.ctx, self.item, self)
        if failure is None:
            self.ctx.located[self.item] = (self.ctx.world.pose(), self.target, self.reach)
        return failure

    def plan(self):
        pose = self.ctx.world.pose()
        d = math.dist(pose, self.target)
        near, best, far = self.reach
        within = near - 0.05 <= d <= far
        if within and not self.another:
            self.path = None
            return None
        bare = self.ctx.belief.room.grid(self.ctx.floor(without=self.item), bare=True)
        tx, ty = self.target
        ring = [
            (round(tx + best * math.cos(a), 3), round(ty + best * math.sin(a), 3))
            for a in (2 * math.pi * k / 16 for k in range(16))
        ]
        ring = [p for p in ring if bare.free(*p) and all(math.dist(p, q) > 0.1 for q in self.tried + [pose])]
        lengths = bare.lengths_from(pose, ring) if bare.free(*pose) else [None] * len(ring)
        options = sorted(
            (n, p) for n, p in zip(lengths, ring, strict=True) if n is not None and n <= ADJUST_PATH_MAX
        )
        if not options and within:
            # asked for another pose (the grasp failed from this one) where there is none: the
            # grasp is tried again from here, which reaches the item (a failed grasp at an item's
            # one tight pose asked four times and gave the action up: 15 of 54 faulty missions)
            self.path = None
            return None
        if not options:
            return Failure(A, "no_base_pose", f"no pose within reach of {self.item}")
        goal = options[0][1]
        self.path = _dedupe([pose] + (bare.path(pose, goal) or []) + [goal])
        return None

    def do(self, monitor: StateMonitor):
        self.another = False
        if self.path is None:
            return None
        world = self.ctx.world
        self.tried.append(world.pose())
        out = world.follow(self.path, monitor, careful=True, face=self.target)
        self.ctx.belief.robot = world.pose()
        return None if out.ok else Failure(A, out.failure or "path_blocked")

    def again_differently(self) -> None:
        self.another = True

    def learn(self, failure: Failure) -> None:
        if failure.what == "not_found":
            self.ctx.belief.not_found(self.item)  # lost, unless the last look from here showed it
        elif failure.what == "no_base_pose":
            self.ctx.belief.unreached(self.item)


class Grasp(Unit):
    """Locate the item relative to the hand, plan the grasp, close the gripper, and verify with
    the gripper's sensor (class B when it closed on nothing: the item is almost unchanged)."""

    name, phase, earlier = GRASP, "manipulation", ADJUST_BASE

    def __init__(self, ctx: Context, item: str) -> None:
        self.ctx, self.item = ctx, item
        self.target: Point | None = None
        self.reach = (GRASP_MIN, GRASP_BEST, GRASP_MAX)

    def check(self):
        if self.ctx.world.holds():
            return Failure(A, "hand_full")
        # the base still stands where the adjustment's close look found the item: that look is
        # this one (6.6 s a take in pybullet); a retry after a failed grasp looks again
        pose, target, reach = self.ctx.located.pop(self.item, (None, None, None))
        if pose is not None and math.dist(pose, self.ctx.world.pose()) < 1e-3:
            self.target, self.reach = target, reach
            return None
        return _locate(self.ctx, self.item, self)

    def plan(self):
        d = math.dist(self.ctx.world.pose(), self.target)
        near, _, far = self.reach
        if not near - 0.1 <= d <= far + 0.05:
            return Failure(A, "out_of_reach", f"{self.item} is {d:.2f} m from the base")
        return None

    def do(self, monitor: StateMonitor):
        out = self.ctx.world.grasp(self.target)
        if not out.ok:
            return Failure(B, out.failure or "grasp_fail")
        if not self.ctx.world.holds():
            return Failure(B, "grasp_fail", "the gripper's sensor finds the hand empty")
        self.ctx.belief.taken(self.item)
        return None

    def learn(self, failure: Failure) -> None:
        if failure.what == "not_found":
            self.ctx.belief.not_found(self.item)  # lost, unless the last look from here showed it
        elif failure.what == "out_of_reach":
            self.ctx.belief.unreached(self.item)  # the arm did not reach it from this pose


class AlignAtDeposit(Unit):
    """Stand at the deposit's approach pose with the item in hand: a short careful move if the
    base is off it. ``hand_empty``: to pull a drawer's handle there, the hand free instead."""

    name, phase = APPROACH_DEPOSIT, "approach"

    def __init__(self, ctx: Context, approach: Point, waypoint: str, hand_empty: bool = False) -> None:
        self.ctx, self.approach, self.waypoint = ctx, approach, waypoint
        self.path: list[Point] = []
        self.carrying: str | None = None
        self.touched: Point | None = None
        self.hand_empty = hand_empty
        if hand_empty:
            self.name = APPROACH_HANDLE

    def check(self):
        if self.hand_empty:
            return Failure(A, "hand_full") if self.ctx.world.holds() else None
        return None if self.ctx.world.holds() else Failure(A, "hand_empty")

    def plan(self):
        pose = self.ctx.world.pose()
        if math.dist(pose, self.approach) <= AT_POSE:
            self.path = [pose]
        elif math.dist(pose, self.approach) <= ADJUST_MAX:
            self.path = [pose, self.approach]
        else:
            return Failure(A, "out_of_reach", "the deposit is too far for a pose adjustment")
        return None

    def do(self, monitor: StateMonitor):
        if len(self.path) < 2:
            return None
        failure = _drive(self.ctx, self, self.path, monitor, careful=True)
        if failure is None:
            self.ctx.belief.at(self.approach, self.waypoint)
        return failure

    def insert_for(self, failure: Failure) -> list[Unit]:
        return _pick_up_if_dropped(self.ctx, self, failure)


class Place(Unit):
    """Put the held item into the deposit and verify the hand let go (class B when it did not);
    an item that left the hand but not into the deposit is class C, picked up again first."""

    name, phase, earlier = PLACE, "manipulation", APPROACH_DEPOSIT

    def __init__(self, ctx: Context, item: str, deposit: str, approach: Point) -> None:
        self.ctx, self.item, self.deposit, self.approach = ctx, item, deposit, approach

    def check(self):
        return None if self.ctx.world.holds() else Failure(A, "hand_empty")

    def plan(self):
        if math.dist(self.ctx.world.pose(), self.approach) > 0.1:
            return Failure(A, "out_of_reach", f"not at {self.deposit}'s approach pose")
        return None

    def do(self, monitor: StateMonitor):
        world, belief = self.ctx.world, self.ctx.belief
        out = world.place(self.deposit, self.approach)
        if out.failure == "place_missed" and not world.holds():
            # let go, but it did not stay in the deposit (it tipped over the rim): the condition
            # changed significantly, so pick it up again near the deposit, then place again
            d = next(d for d in belief.scenario.deposits if d.name == self.deposit)
            belief.fell(self.item, (d.x, d.y), FALL_SPREAD)
            return Failure(C, "place_missed", f"{self.item} is not in {self.deposit}")
        if out.failure == "out_of_reach" and world.holds():
            # the arm cannot bring it upright over the deposit as it is held: the condition of
            # the hand must change, so put it down here and take it again (another grasp)
            return Failure(C, "out_of_reach", f"{self.item} cannot be put into {self.deposit} as held")
        if not out.ok or world.holds():
            return Failure(B, out.failure or "place_fail")
        belief.delivered(self.item, self.deposit)
        return None

    def insert_for(self, failure: Failure) -> list[Unit]:
        if failure.what == "place_missed":
            return pick_up(self.ctx, self.item)
        if failure.what == "out_of_reach":
            return [PutDown(self.ctx, self.item), *pick_up(self.ctx, self.item)]
        return []


class Look(Unit):
    """observing, after every action: the frames the camera took on the way and one from where
    the robot stands (a glance: no time of its own), for the monitor (what moved, what nobody
    announced); then a head sweep only where one pays, and the trace says why (``why``): after
    a failure (what changed?), where an item tall enough to hide another (HIDES) was just taken
    away, at a viewpoint the plan came to look from, or where the sweep is expected to find
    MIN_FINDS items nobody has found yet. In pybullet a sweep is 11 s: one after every action took
    a Task 1 room 3567 s, where 1284 s of it were sweeps that only the monitor asked for."""

    name, phase = LOOK, "observe"

    def __init__(
        self,
        ctx: Context,
        waypoint: str | None,
        after_failure: bool = False,
        took: str | None = None,
        failed_at: str | None = None,
    ) -> None:
        self.ctx, self.waypoint, self.after_failure, self.took = ctx, waypoint, after_failure, took
        self.failed_at = failed_at  # the item a failed approach or grasp was at, if that failed

    def do(self, monitor: StateMonitor):
        self.ctx.glance(GLANCE_WHY)
        why = self.why()
        if why is not None:
            self.ctx.look(self.waypoint, *why)
        return None

    def why(self) -> tuple[str, tuple[float, ...] | None] | None:
        """Why a sweep pays here, and its stops (None: all around), or None where the glance is
        enough. After a failure what changed may be anywhere around (after one at an item, it is
        about that item: the stops expected to find something); what a tall item hid lies
        beyond where it stood; at a viewpoint the plan came to look from, all around where it may
        find anything; elsewhere the space nobody has seen is swept stop by stop, where a stop is
        expected to find STOP_FINDS items or more, when the prior says how many are missing (its
        rounds of exploration look again for what every look missed); without one, all around
        where MIN_FINDS are expected."""
        belief = self.ctx.belief
        here = self.ctx.world.pose()
        if self.after_failure and (self.failed_at is None or belief.prior is None):
            return "after a failure: what changed?", None
        if self.after_failure:
            # An approach or a grasp failed at an item: what changed is about that item. Lost,
            # the space around its place is unseen again, and the stops that expect to find
            # something there are swept, as exploration picks them; still believed (another pose
            # next), nothing new is expected and the glance is all. All around, 11 s in pybullet,
            # such a sweep found a new item after 1 of 13 failures in ten Task 1 rooms.
            return _stops_that_pay(belief, here, f"after a failure at {self.failed_at}")
        taken = belief.items.get(self.took or "")
        if taken is not None and taken.sz >= HIDES:
            stops = _stops_around(math.atan2(taken.y - here[1], taken.x - here[0]))
            return f"{taken.name} ({taken.sz:.2f} m tall) taken away: what it hid is in view", stops
        if belief.room.fixed_kind.get(self.waypoint or "") == "viewpoint":
            # all around: what the plan came here for, and a second chance at what the first
            # looks missed (the detector misses one in five: only the sweeps look again)
            finds = belief.look_finds(here)
            return (f"a viewpoint: {finds:.2f} items expected found", None) if finds > 0 else None
        if belief.prior is None:
            # nothing says how many are missing, so nothing sends the robot back for an item every
            # look so far missed: the sweeps all around are its second chance
            finds = belief.look_finds(here)
            return (
                (f"unseen space in view: {finds:.2f} items expected found", None)
                if finds >= MIN_FINDS
                else None
            )
        return _stops_that_pay(belief, here, "unseen space in view")


def _stops_that_pay(belief, here: Point, why: str) -> tuple[str, tuple[float, ...] | None] | None:
    """The sweep's stops from ``here`` each expected to find STOP_FINDS items or more nobody has
    found (None: all seven), and the look's reason (``why``: N items expected found, K of 7
    stops); None where no stop pays."""
    chosen = [(h, f) for h, f in belief.stop_finds(here) if f >= STOP_FINDS and f > 0]
    if not chosen:
        return None
    finds = sum(f for _, f in chosen)
    stops = None if len(chosen) == len(SWEEP_STOPS) else tuple(h for h, _ in chosen)
    return f"{why}: {finds:.2f} items expected found ({len(chosen)} of 7 stops)", stops


GLANCE_WHY = "frames on the way: for the monitor, what moved, what nobody announced"


def _drive(
    ctx: Context, unit, path: list[Point], monitor: StateMonitor, careful: bool, face: Point | None = None
) -> Failure | None:
    """Follow ``path`` (turning on the way to ``face`` it); carrying, the state monitor watches
    the hand and stops the robot the moment the item slips out (class C), and the belief puts
    the item near the robot at once."""
    world, belief = ctx.world, ctx.belief
    unit.carrying = belief.holding
    if unit.carrying is not None:
        monitor.watch("grasp_drop", C, world.holds)
    out = world.follow(path, monitor, careful=careful, face=face)
    belief.robot = world.pose()
    unit.touched = out.at if out.failure == "path_blocked" else None
    if out.ok:
        return None
    if monitor.fired is not None:
        if unit.carrying is not None and not world.holds():
            belief.fell(unit.carrying, world.pose(), FALL_SPREAD)  # accounted for at once
        return monitor.fired
    return Failure(A, out.failure or "path_blocked")


def _pick_up_if_dropped(ctx: Context, unit, failure: Failure) -> list[Unit]:
    if failure.what == "grasp_drop" and unit.carrying is not None:
        return pick_up(ctx, unit.carrying)
    return []


def pick_up(ctx: Context, item: str) -> list[Unit]:
    """The units inserted for a dropped item (class C): find it, stand within reach, grasp it."""
    return [AdjustBase(ctx, item), Grasp(ctx, item)]


def _locate(ctx: Context, item: str, unit) -> Failure | None:
    """A unit's check: find ``item`` close up near its believed place; record where it is."""
    k = ctx.belief.items.get(item)
    if k is None:
        return Failure(A, "not_found", f"{item} is not in the belief")
    seen = ctx.world.locate((k.x, k.y), max(FIND_RADIUS, k.spread), k.category)
    if seen is None:
        return Failure(A, "not_found", f"no {k.category} near ({k.x:.2f}, {k.y:.2f})")
    ctx.belief.relocate(item, seen.x, seen.y, (seen.sx, seen.sy, seen.sz), oriented=seen.down is not None)
    unit.target = (seen.x, seen.y)
    unit.reach = ctx.world.grasp_distances(seen.sz)
    return None


def _way_ahead(pose: Point, path: list[Point]) -> float:
    """The heading (room's frame) of the way ``path`` goes on from ``pose``: toward its first
    point half a metre or more beyond the point of it nearest the robot."""
    near = min(range(len(path)), key=lambda i: math.dist(path[i], pose))
    ahead = next((q for q in path[near:] if math.dist(q, pose) >= 0.5), path[-1])
    return math.atan2(ahead[1] - pose[1], ahead[0] - pose[0])


def _stops_around(heading: float) -> tuple[float, ...]:
    """The sweep's stop nearest ``heading`` and those either side of it: 154 deg across."""
    n = len(SWEEP_STOPS)
    i = round((heading % (2 * math.pi)) / (2 * math.pi / n)) % n
    return tuple(SWEEP_STOPS[(i + k) % n] for k in (-1, 0, 1))


def _dedupe(path: list[Point]) -> list[Point]:
    out: list[Point] = []
    for p in path:
        if not out or math.dist(out[-1], p) > 1e-6:
            out.append(p)
    return out
