"""What the symbolic and the pybullet world share: fault rates and the referee's view of the
hidden truth (``WorldReferee``), on the contract every world implements (``tidyplan.worlds.contract``:
``Skills``, what the behaviour units call; ``Referee``, the truth and the verdict).

The behaviour units (``tidyplan.exec.units``) reach a world only through its skills; a world
keeps the truth the robot must not see, draws every fault from one seeded generator in a fixed
order, and answers the referee's questions (what is untidied, where an item really is). Worlds
are made by name (``tidyplan.worlds.registry``): a new one is one class and one entry there.
"""

from __future__ import annotations

import math

import numpy as np

from sim.scenario.model import Scenario
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.grasp import GRASP_BEST, GRASP_MAX, GRASP_MIN
from tidyplan.belief.percepts import Detection, Frame
from tidyplan.worlds.contract import Odometer, Outcome, Referee, Skills, TrueItem, World
from tidyplan.worlds.rates import Rates

__all__ = ["Odometer", "Outcome", "Rates", "Referee", "Skills", "TrueItem", "World", "WorldReferee"]

Point = tuple[float, float]
LOOK_INTO_S = 2.0  # s: the head tilts to the deposit and the detector runs (as a close look)
# m/s: a drawer pulled or pushed by the hand on its handle, the base backing off or closing in
# with the arm held (our figure: a little under the base's careful 0.11 m/s, a drawer steadily)
PULL_SPEED = 0.1
JAM_SHARE = (0.3, 0.7)  # of its travel: where a drawer that jams sticks
TAKE_TOLERANCE = 0.15  # m: the gripper closes on an item this close to where it was located
# m driven between the frames the camera keeps on the way (it runs at 30 Hz; a frame each half
# metre is enough at 0.22 m/s: consecutive 58 deg frames overlap from 0.5 m out)
FRAME_EVERY = 0.5
# The head's pan (rad from the base's heading; 1.0 rad/s both ways, ../shared/HSR.md) and a sweep's
# two tilts a stop (7 deg above to 60 deg below the horizon: the floor from 0.6 m out and table tops)
PAN_LEFT, PAN_RIGHT, HEAD_SPEED = 1.75, -3.84, 1.0
TILTS = (-0.65, -0.15)


def sweep_pans(yaw: float, stops, pan_now: float = 0.0) -> list[float]:
    """The head's pans for a sweep of the ``stops`` (headings in the room's frame) from a base
    heading ``yaw``, in the order the head visits them: from the end nearer where it pans now to
    the other, so it never swings back. A heading the head cannot pan to (behind, on the left)
    is looked at from the nearer end of its range, whose frame still reaches it."""
    pans = set()
    for h in stops:
        pan = (h - yaw + math.pi) % (2 * math.pi) - math.pi  # in (-pi, pi]
        if pan > PAN_LEFT:  # behind on the left: the long way round, or the nearer end
            right = pan - 2 * math.pi
            pan = (
                right
                if right >= PAN_RIGHT
                else min((PAN_LEFT, PAN_RIGHT), key=lambda e: min(abs(e - pan), math.tau - abs(e - pan)))
            )
        pans.add(round(pan, 4))
    order = sorted(pans, reverse=True)  # left to right
    if order and abs(order[-1] - pan_now) < abs(order[0] - pan_now):
        order.reverse()
    return order


def sweep_seconds(pans: list[float], pan_now: float = 0.0, tilt_now: float = -0.35) -> float:
    """What a sweep of ``pans`` takes, every joint at its speed: to the first stop, both tilts at
    each, across to the next, and back to the driving tilt (the pybullet world's head, moved)."""
    if not pans:
        return 0.0
    seconds = max(abs(pans[0] - pan_now), abs(TILTS[0] - tilt_now)) / HEAD_SPEED
    seconds += abs(pans[-1] - pans[0]) / HEAD_SPEED + len(pans) * abs(TILTS[1] - TILTS[0]) / HEAD_SPEED
    last = TILTS[len(pans) % 2]  # the tilt the last stop ends on: tilts alternate
    return seconds + abs(last - tilt_now) / HEAD_SPEED


class WorldReferee:
    """What every world shares: the hidden truth (``items``), the seeded generator every fault
    is drawn from, the referee's view of the truth, and the clock's bookkeeping. Subclasses set
    ``robot`` and ``odometer``."""

    robot: Point
    odometer: Odometer

    def __init__(self, scenario: Scenario, room: RoomMap, seed: int, rates: Rates) -> None:
        self.scenario = scenario
        self.room = room
        self.rng = np.random.default_rng(seed)
        s = scenario.sensing
        self.fn = s.false_negative if rates.false_negative is None else rates.false_negative
        self.fp = s.false_positive if rates.false_positive is None else rates.false_positive
        self.rates = rates
        self.items = {
            i.name: TrueItem(
                i.name, i.category, i.x, i.y, i.on, i.sx, i.sy, i.sz, label=i.label, orientation=i.orientation
            )
            for i in scenario.items
        }
        self.holding: str | None = None
        self._frames: list[Frame] = []  # taken on the way since the last glance
        # a frame's misses from a stream of their own: how many frames a path holds never shifts
        # the faults the world draws
        self.frame_rng = np.random.default_rng([seed, 1])

    def glance(self) -> list[Frame]:
        """The frames the camera took on the way since the last glance, and one from where the
        robot stands now, as the head looks: no time of their own (the camera runs while the
        robot drives and works). A frame reports no phantoms: the detector keeps a detection
        only when consecutive frames agree, and a false one does not persist."""
        frames, self._frames = self._frames + [self._frame()], []
        return frames

    def _frame(self) -> Frame:
        """What the camera shows now, as the head looks (each world's own)."""
        raise NotImplementedError

    def untidied(self) -> list[str]:
        """Items not in a deposit of their category (an unknown object's: the deposits for
        unknown objects; an orientation item's: those for orientation items too, as the rulebook
        counts it)."""
        deposits = {d.name: d for d in self.scenario.deposits}
        return sorted(
            o.name
            for o in self.items.values()
            if o.state != "tidied" or o.deposit not in deposits or not deposits[o.deposit].takes(o)
        )

    def standing(self) -> list[str]:
        """Orientation items standing the right way in a deposit for orientation items."""
        return sorted(n for n, o in self.items.items() if o.state == "tidied" and o.stands)

    def where(self, name: str) -> tuple[str, Point]:
        o = self.items[name]
        return o.state if o.state != "tidied" else f"tidied:{o.deposit}", (o.x, o.y)

    def escaped(self) -> list[str]:
        """Items whose true place is outside the room's bounds: a fault of the simulation (an
        object pushed through a wall), for the trace to report, never a lost object. A held item
        is where the hand carries it (kinematically, into a wall too), not loose: never escaped.
        The symbolic world puts items only inside the room: [] there."""
        x0, x1, y0, y1 = self.scenario.bounds
        return sorted(
            n
            for n, o in self.items.items()
            if o.state != "held" and not (x0 <= o.x <= x1 and y0 <= o.y <= y1)
        )

    def look_into(self, deposit: str) -> list[Detection]:
        """A close look into a deposit from where the robot stands at it (head tilted down): the
        items resting in it, each missed at the false-negative rate."""
        out = []
        for o in sorted(self.items.values(), key=lambda o: o.name):
            if o.state == "tidied" and o.deposit == deposit and self.rng.random() >= self.fn:
                out.append(self._seen(o))
        self.odometer.sim_time_s += LOOK_INTO_S
        return out

    def _seen(self, o: TrueItem) -> Detection:
        """What the detector reports of ``o`` where it is (the pybullet world turns its axis too)."""
        return o.seen(o.x, o.y)

    def close(self) -> None:
        """Release what the world holds (a physics server); nothing here."""

    def grasp_distances(self, height: float) -> tuple[float, float, float]:
        """(nearest, best, farthest) the base's centre may stand from an object of ``height``
        to take it: the arm's comfortable reach."""
        return GRASP_MIN, GRASP_BEST, GRASP_MAX

    def _faults_on_path(self, n: int) -> tuple[int | None, int | None]:
        """For a motion along ``n`` path points: the segment a transient obstacle stops it at
        (``path_blocked``) and the one the held item slips out on (``grasp_drop``), or None.
        Both numbers are drawn every time, so a seed fixes the run whatever happens."""
        blocked_u, drop_u = self.rng.random(), self.rng.random()
        block_at = int(self.rng.integers(1, n)) if n > 1 and blocked_u < self.rates.path_blocked else None
        carrying = n > 1 and self.holding is not None
        drop_at = int(self.rng.integers(1, n)) if carrying and drop_u < self.rates.grasp_drop else None
        return block_at, drop_at

    def _pull_faults(
        self, jammed: float | None, opening: float, travel: float
    ) -> tuple[float, str | None, float | None]:
        """For a pull of a drawer ``opening`` m out (stuck at ``jammed``, or None): where it stops,
        why (``handle_slip``, ``drawer_jammed``, None when it comes fully out) and where it is
        stuck then. A jam (``drawer_jam``) sticks it at 30-70 % of its travel (where it is, if
        farther out); a slip (``handle_slip``) lets go at a drawn point of the way it can go.
        Four numbers are drawn every time, so a seed fixes the run whatever happens."""
        slip_u, jam_u, slip_at, jam_at = (float(u) for u in self.rng.random(4))
        if opening >= travel - 1e-3:
            return opening, None, jammed  # out already: nothing to pull
        if jammed is None and jam_u < self.rates.drawer_jam:
            lo, hi = JAM_SHARE
            jammed = max(opening, travel * (lo + (hi - lo) * jam_at))
        end = travel if jammed is None else jammed
        if slip_u < self.rates.handle_slip and end - opening > 1e-3:
            return opening + slip_at * (end - opening), "handle_slip", jammed
        return end, None if jammed is None else "drawer_jammed", jammed

    def _phantom(self, stops: tuple[float, ...] | None = None) -> list[Detection]:
        """At the false-positive rate, a detection of nothing: a random category somewhere in
        view on the floor (of a sweep of ``stops``, in one of their frames; none when that place
        is outside the room)."""
        if self.rng.random() >= self.fp:
            return []
        s = self.scenario.sensing
        angle = self.rng.uniform(0, 2 * math.pi)
        if stops:  # the same draw, in a stop's frame: which stop, and where across its width
            share = angle / (2 * math.pi) * len(stops)
            angle = stops[min(int(share), len(stops) - 1)] + (share % 1.0 - 0.5) * math.radians(s.fov_h_deg)
        dist = self.rng.uniform(s.range_min, min(s.range_max, 2.0))
        x, y = self.robot[0] + dist * math.cos(angle), self.robot[1] + dist * math.sin(angle)
        cats = sorted({i.label for i in self.items.values()})  # what a detection could say
        cat = cats[int(self.rng.integers(0, len(cats)))]
        x0, x1, y0, y1 = self.scenario.bounds
        return [Detection(cat, round(x, 3), round(y, 3), "floor")] if x0 < x < x1 and y0 < y < y1 else []

    def _placed(self) -> list[TrueItem]:
        return [o for o in self.items.values() if o.state == "placed"]

    def _refused(self, deposit: str) -> Outcome | None:
        """Why the hand cannot go to the drawer's handle: full, or not at the deposit's approach."""
        if self.holding is not None:
            return self._fail("hand_full", 1.0)
        approach = next(d.approach for d in self.scenario.deposits if d.name == deposit)
        if math.dist(self.robot, approach) > 0.1:
            return self._fail("not_at_deposit", 1.0)
        return None

    def _spend(self, seconds: float) -> Outcome:
        self.odometer.sim_time_s += seconds
        return Outcome(True, None, seconds)

    def _fail(self, failure: str, seconds: float) -> Outcome:
        self.odometer.sim_time_s += seconds
        return Outcome(False, failure, seconds)
