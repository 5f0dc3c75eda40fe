"""A fast symbolic world with a hidden true state: the loop's test bench and scenario planner.

What is hidden from the robot: where every item really is (some start where no waypoint sees
them, or behind furniture), which paths are really open (an unseen floor item can block one),
and whether an action works this time. The robot learns of the world only through action
outcomes and looks. Geometry is the scenario's: paths on the occupancy grid with the true floor
items as obstacles, line of sight against furniture and items (``sim.visibility``).

Randomness comes from one seeded generator, drawn in a fixed order, so a seed fixes the run.

The robot acts through skills the behaviour units call (``tidyplan.exec.units``): ``look``,
``locate`` (close range), ``holds`` (the gripper's sensor), ``follow`` (a path, with a state
monitor polled after every segment), ``grasp``, ``place``, ``put_down``, and for a deposit that
is a drawer ``drawer_opening``, ``pull_handle``, ``push_drawer``. Faults by rate: grasps that
close on nothing, placements that fail, false negatives and positives, items that fall while
carried (``grasp_drop``), transient obstacles (``path_blocked``), handles that slip out of the
hand (``handle_slip``) and drawers that jam part-way (``drawer_jam``).

Durations on the simulated clock (docs/trace.md): driving at the scenario's robot speed (the
HSR's 0.8 km/h = 0.22 m/s by default); a careful pose adjustment at half that; the frames on
the way and a glance no time of their own; the rest calibrated against the pybullet world,
whose motions take what the HSR's joint speeds give them: each is the mean of that motion in
pybullet over 18 Task 1 rooms (`python bench/clock.py PYBULLET_SWEEP SYMBOLIC_SWEEP`, which
prints both worlds side by side; since the base turns on the way to what it works on): a head
sweep 11 s, a close-range locate 6 s (tilting the head, raising the torso where the place is too
close, recognising), a grasp 4 s, a placement 9.8 s, a drop 10.5 s (an earlier sweep's); reading
how far a drawer is out 1 s; a pull or a push 9.3 s of arm motions plus the drawer's way at
0.1 m/s.
"""

from __future__ import annotations

import math

import numpy as np

from sim.grid import Box
from sim.scenario.model import ORIENTATION, DrawerLayout, Scenario, drawer_layout, out_boxes
from sim.visibility import Box3, in_frame, visible
from tidyplan.belief.geometry import RoomMap, free_spots
from tidyplan.belief.grasp import GRASP_MAX
from tidyplan.belief.percepts import Detection, Frame
from tidyplan.worlds.base import (
    FRAME_EVERY,
    PULL_SPEED,
    TAKE_TOLERANCE,
    Odometer,
    Outcome,
    Rates,
    TrueItem,
    WorldReferee,
    sweep_pans,
    sweep_seconds,
)
from tidyplan.worlds.contract import placed_edits

Point = tuple[float, float]

# s: the pybullet world's means of each motion (bench/clock.py over 18 Task 1 rooms, see above)
LOOK_S, LOCATE_S, TAKE_S, DELIVER_S, DROP_S = 11.0, 1.0, 3.7, 10.1, 10.5
CLOSE_RANGE = 1.2  # m: what a close-range look (head down, hand camera) sees around the robot
OPENING_S, HANDLE_S = 1.0, 9.3  # s: a look at a drawer's front; reach its handle, grip, let go, stow


class SymbolicWorld(WorldReferee):
    @classmethod
    def for_mission(cls, scenario: Scenario, room: RoomMap, settings) -> SymbolicWorld:
        """The world for a mission's ``settings`` (``tidyplan.loop.mission.Settings``)."""
        return cls(scenario, room, seed=settings.seed, rates=settings.rates)

    def __init__(
        self,
        scenario: Scenario,
        room: RoomMap,
        seed: int = 0,
        rates: Rates = Rates(),  # noqa: B008 - frozen, never mutated
    ) -> None:
        super().__init__(scenario, room, seed, rates)
        self.robot: Point = room.entrance
        self.heading = 0.0  # rad: which way the head looks (the way it drives, or at its work)
        self.odometer = Odometer(track=[self.robot])
        self._furniture = [Box3.from_furniture(f) for f in scenario.furniture]
        layouts = {d.name: drawer_layout(scenario.furniture, d) for d in scenario.deposits}
        self.drawers: dict[str, DrawerLayout] = {n: x for n, x in layouts.items() if x is not None}
        self.opened = {n: x.start for n, x in self.drawers.items()}  # m each drawer is out
        self.jammed: dict[str, float] = {}  # where a jammed drawer is stuck
        self._kept: _Scene | None = None  # the items in place as the camera sees them (_scene)

    # ------------------------------------------------------------------ sensing
    def look(self, stops: tuple[float, ...] | None = None) -> list[Detection]:
        """Items in range and line of sight (of a sweep of ``stops``, headings in the room's
        frame: in one of their frames' width), each missed at the false-negative rate; a phantom
        at the false-positive rate (a random category, somewhere in view on the floor). A whole
        sweep takes LOOK_S, the pybullet world's mean; one of some stops what the head's motions
        take (``sweep_seconds``: the base here has no heading of its own, the head looks the
        way the robot last drove or worked)."""
        s = self.scenario.sensing
        if stops is None:
            self._spend(LOOK_S)
        else:
            self._spend(sweep_seconds(sweep_pans(self.heading, stops)))
        cam = (self.robot[0], self.robot[1], s.camera_height)
        half = math.radians(s.fov_h_deg) / 2
        out = []
        scene = self._scene()
        across = scene.across()  # each item occludes the others
        for it, z in zip(scene.ordered, scene.zs, strict=True):
            occ = across.between(cam, it)
            miss = self.rng.random() < self.fn  # drawn for every item in turn: seed fixes the run
            bearing = math.atan2(it.y - self.robot[1], it.x - self.robot[0])
            framed = stops is None or any(
                abs((bearing - h + math.pi) % math.tau - math.pi) <= half for h in stops
            )
            if (
                framed
                and visible(cam, (it.x, it.y, z), occ, range_min=s.range_min, range_max=s.range_max)
                and not miss
            ):
                out.append(it.seen(it.x, it.y))
        return out + self._phantom(stops)

    def _frame(self) -> Frame:
        """Items in the frame's field, range and line of sight; each missed at the false-negative
        rate (drawn from the frames' own stream, for every item in turn)."""
        s = self.scenario.sensing
        cam = (self.robot[0], self.robot[1], s.camera_height)
        out = []
        scene = self._scene()
        misses = [self.frame_rng.random() < self.fn for _ in scene.ordered]  # every item's, in turn
        # the field for every item at once (a call per item was most of a frame at 96 items)
        framed = in_frame(self.robot, self.heading, scene.xy, scene.z, s)
        for it, z, miss, seen in zip(scene.ordered, scene.zs, misses, framed, strict=True):
            if miss or not seen:
                continue
            occ = scene.across().between(cam, it)
            if visible(cam, (it.x, it.y, z), occ, range_min=s.range_min, range_max=s.range_max):
                out.append(it.seen(it.x, it.y))
        return Frame(self.robot, self.heading, out)

    def _face(self, at: Point) -> None:
        if math.dist(at, self.robot) > 1e-6:
            self.heading = math.atan2(at[1] - self.robot[1], at[0] - self.robot[0])

    def locate(self, near: Point, radius: float, category: str | None = None) -> Detection | None:
        """Close-range look (head tilted down, the hand camera): the placed item nearest ``near``
        within ``radius`` of it and within close range of the robot; missed at the false-negative
        rate. This is how a unit's check finds its target, also one the head camera's minimum
        range cannot see (at the robot's feet, where a dropped item lands)."""
        self._spend(LOCATE_S)
        self._face(near)
        found = [
            o
            for o in self._placed()
            if math.dist((o.x, o.y), near) <= radius
            and math.dist((o.x, o.y), self.robot) <= CLOSE_RANGE
            and (category is None or o.label == category)
        ]
        if self.rng.random() < self.fn or not found:
            return None
        o = min(found, key=lambda o: (math.dist((o.x, o.y), near), o.name))
        return o.seen(o.x, o.y)

    def holds(self) -> bool:
        """The gripper's sensor (finger angle, wrist force): is something in the hand?"""
        return self.holding is not None

    def pose(self) -> Point:
        return self.robot

    # ------------------------------------------------------------------ actions
    def follow(
        self, path: list[Point], monitor=None, *, careful: bool = False, face: Point | None = None
    ) -> Outcome:
        """Drive along ``path`` (its first point is where the robot is) at the robot's speed
        (``careful``: half of it, a pose adjustment). Stops before the first point the true
        footprint does not fit (an obstacle nobody has seen, or a transient one the
        ``path_blocked`` fault puts there): ``path_blocked``. ``monitor.poll()`` runs after every
        segment and stops the motion at once when it returns False (``interrupted``). An item in
        the hand falls on the way at the ``grasp_drop`` rate. The base has no heading here
        (``face`` is the pybullet world's): a take's and a put's means include their turns."""
        speed = self.scenario.robot.speed / (2 if careful else 1)
        n = len(path)
        block_at, drop_at = self._faults_on_path(n)
        bare = self._scene().bare(self.room, out_boxes(self.drawers, self.opened))
        metres = seconds = 0.0
        framed = 0.0  # m driven since the last frame kept
        for k in range(1, n):
            if k == block_at or not _segment_free(bare, path[k - 1], path[k]):
                return self._stopped("path_blocked", metres, seconds)
            d = math.dist(path[k - 1], path[k])
            metres, seconds = metres + d, seconds + d / speed
            self._face(path[k])
            self._arrive(path[k], d, d / speed)
            framed += d
            if framed >= FRAME_EVERY and k < n - 1:  # the last is the glance's own
                self._frames.append(self._frame())
                framed = 0.0
            if k == drop_at:
                self._fall()
            if monitor is not None and not monitor.poll():
                return self._stopped("interrupted", metres, seconds)
        return Outcome(True, None, seconds, metres)

    def grasp(self, target: Point) -> Outcome:
        """Close the gripper on the item at ``target`` (where a check located it); ``grasp_fail``
        at 1 - the take rate leaves the item where it was."""
        if self.holding is not None:
            return self._fail("hand_full", 1.0)
        self._face(target)
        near = [
            o
            for o in self._placed()
            if math.dist((o.x, o.y), target) <= TAKE_TOLERANCE
            and math.dist((o.x, o.y), self.robot) <= GRASP_MAX + 0.1
        ]
        if not near:
            return self._fail("not_found", TAKE_S / 2)
        if self.rng.random() >= self.rates.take:
            return self._fail("grasp_fail", TAKE_S)
        item = min(near, key=lambda o: (math.dist((o.x, o.y), target), o.name))
        item.state, self.holding = "held", item.name
        return self._spend(TAKE_S)

    def place(self, deposit: str, approach: Point) -> Outcome:
        """Put the held item into ``deposit`` from its approach pose; ``place_fail`` at
        1 - the deliver rate keeps it in the hand."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if math.dist(self.robot, approach) > 0.1:
            return self._fail("not_at_deposit", 1.0)
        item = self.items[self.holding]
        d = next(d for d in self.scenario.deposits if d.name == deposit)
        self._face((d.x, d.y))
        drawer = self.drawers.get(deposit)
        if drawer is not None and not drawer.takes(self.opened[deposit], (item.sx, item.sy)):
            return self._fail("deposit_closed", OPENING_S)  # the hand never goes out: it stays in it
        if self.rng.random() >= self.rates.deliver:
            return self._fail("place_fail", DELIVER_S)
        k = sum(o.state == "tidied" and o.deposit == deposit for o in self.items.values())
        # side by side in the tray, on a 5 x 5 lattice 4 cm apart: a look into the deposit tells
        # them apart (25 places: a deposit of the 96-object room receives 24); in a drawer, in
        # rows across its part out of the carcass, 2 cm apart along the slide
        if drawer is None:
            # a container's lattice shrunk to its inside (container B's is 8.5 cm across)
            step = 0.04 if d.container is None else min(0.04, (min(d.container[:2]) - 0.01) / 5)
            item.x, item.y = round(d.x + step * (k % 5 - 2), 3), round(d.y + step * (k // 5 % 5 - 2), 3)
        else:
            x0, x1, y0, y1 = drawer.exposed(self.opened[deposit])
            across, along = 0.04 * (k % 5 - 2), 0.02 * (k // 5 % 3 - 1)
            dx, dy = (along, across) if drawer.k == 0 else (across, along)
            item.x, item.y = round((x0 + x1) / 2 + dx, 3), round((y0 + y1) / 2 + dy, 3)
        item.state, item.deposit, self.holding = "tidied", deposit, None
        # no poses here: an orientation item stands in its box as the robot puts it, down end first
        item.stands = True if d.category == ORIENTATION and item.orientation is not None else None
        return self._spend(DELIVER_S)

    def put_down(self, spot: Point) -> Outcome:
        """Put the held item on the floor at ``spot`` (next to the robot); ``place_fail`` at
        1 - the drop rate, or when something the robot has not seen is lying there."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        self._face(spot)
        if self.rng.random() >= self.rates.drop or any(
            math.dist(spot, (o.x, o.y)) < 0.2 for o in self._placed()
        ):
            return self._fail("place_fail", DROP_S)
        item = self.items[self.holding]
        item.x, item.y, item.on, item.state, self.holding = spot[0], spot[1], "floor", "placed", None
        out = self._spend(DROP_S)
        return Outcome(True, None, out.seconds, 0.0, spot)

    # ------------------------------------------------------------------ drawers
    def drawer_opening(self, deposit: str) -> float:
        """How far the deposit's drawer is out (m; 0.0 closed): a look at its front."""
        self._spend(OPENING_S)
        return round(self.opened[deposit], 3)

    def pull_handle(self, deposit: str) -> Outcome:
        """Grip the drawer's handle from the approach and pull it out by its travel, with the hand
        empty; the handle slips part-way at the ``handle_slip`` rate (``handle_slip``: it stays
        where it got), the drawer sticks at 30-70 % of its travel at the ``drawer_jam`` rate
        (``drawer_jammed``: it goes no farther until pushed back closed)."""
        layout, opening = self.drawers[deposit], self.opened[deposit]
        stop, failure, jammed = self._pull_faults(self.jammed.get(deposit), opening, layout.spec.travel)
        refused = self._refused(deposit)
        if refused is not None:
            return refused
        if jammed is not None:
            self.jammed[deposit] = jammed
        self._slide(deposit, stop)
        seconds = (HANDLE_S if stop > opening or failure else OPENING_S) + (stop - opening) / PULL_SPEED
        return self._fail(failure, seconds) if failure else self._spend(seconds)

    def push_drawer(self, deposit: str) -> Outcome:
        """Push the drawer back closed from the approach, with the hand empty: it is free again."""
        refused = self._refused(deposit)
        if refused is not None:
            return refused
        opening = self.opened[deposit]
        self.jammed.pop(deposit, None)
        self._slide(deposit, 0.0)
        return self._spend((HANDLE_S if opening > 0 else OPENING_S) + opening / PULL_SPEED)

    def _slide(self, deposit: str, to: float) -> None:
        """The drawer to ``to`` m out, the items in it along with it."""
        layout = self.drawers[deposit]
        step = to - self.opened[deposit]
        for o in self.items.values():
            if o.state == "tidied" and o.deposit == deposit:
                if layout.k == 0:
                    o.x = round(o.x + layout.sign * step, 3)
                else:
                    o.y = round(o.y + layout.sign * step, 3)
        self.opened[deposit] = to

    # ------------------------------------------------------------------ helpers
    def _scene(self) -> _Scene:
        """The items in place, as looks and motions use them, kept while none of them changes
        (``placed_edits``): at 96 items, listing, sorting and boxing them anew for every frame
        on the way was a sixth of the frames' time."""
        edits = placed_edits()
        if self._kept is None or self._kept.edits != edits:
            self._kept = _Scene(self, edits)
        return self._kept

    def _base_z(self, o: TrueItem) -> float:
        return 0.0 if o.on == "floor" else self.scenario.furniture_named(o.on).height

    def _box3(self, o: TrueItem) -> Box3:
        return Box3.from_item(o, self._base_z(o))

    @staticmethod
    def _box(o: TrueItem) -> Box:
        return Box(o.x, o.y, o.sx, o.sy, o.name)

    def _fall(self) -> None:
        """The held item slips out and lands on free floor near the robot (grasp_drop)."""
        item = self.items[self.holding]
        spots = free_spots(self.scenario, self.robot, [(o.x, o.y) for o in self._placed()], (0.32, 0.45))
        k = int(self.rng.integers(0, len(spots))) if spots else None
        x, y = spots[k] if k is not None else self.robot
        item.x, item.y, item.on, item.state, self.holding = x, y, "floor", "placed", None

    def _stopped(self, failure: str, metres: float, seconds: float) -> Outcome:
        return Outcome(False, failure, seconds, metres)

    def _arrive(self, to: Point, metres: float, seconds: float) -> Outcome:
        self.robot = to
        self.odometer.sim_time_s += seconds
        self.odometer.distance_m += metres
        self.odometer.track.append(to)
        if self.holding is not None:
            held = self.items[self.holding]
            held.x, held.y = to
        return Outcome(True, None, seconds, metres)


def _segment_free(grid, a: Point, b: Point, step: float = 0.05) -> bool:
    """Every point from a (excluded: the robot is there) to b, ``step`` apart, fits the robot."""
    n = max(1, math.ceil(math.dist(a, b) / step))
    return all(grid.free(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) for k in range(1, n + 1))


class _Scene:
    """The items in place at one count of ``placed_edits``: in the world's order (``placed``)
    and in name order (``ordered``, with each one's middle height ``zs`` and the arrays a
    frame's field takes), the occluders (``across``, made when first asked) and the bare grid
    a motion checks its path on (``bare``, by the drawers out)."""

    def __init__(self, world: SymbolicWorld, edits: int) -> None:
        self.world, self.edits = world, edits
        self.placed = world._placed()
        self.ordered = sorted(self.placed, key=lambda t: t.name)
        self.zs = [world._base_z(it) + it.sz / 2 for it in self.ordered]
        self.xy = np.array([[it.x, it.y] for it in self.ordered], dtype=float).reshape(-1, 2)
        self.z = np.array(self.zs, dtype=float)
        self._across: _Across | None = None
        self._bare: dict[tuple, object] = {}

    def across(self) -> _Across:
        if self._across is None:
            world = self.world
            self._across = _Across(world._furniture, self.placed, [world._box3(o) for o in self.placed])
        return self._across

    def bare(self, room: RoomMap, out: list[Box]):
        """The bare grid with the floor items in place and the drawers' ``out`` boxes."""
        key = tuple(out)
        if key not in self._bare:
            floor = [self.world._box(o) for o in self.placed if o.on == "floor"]
            self._bare[key] = room.grid(floor + list(out), bare=True)
        return self._bare[key]


class _Across:
    """A look's occluders (the furniture, then every placed item's box) as arrays: those whose
    footprint overlaps the rectangle a line of sight spans, found for all at once. A box
    outside it cannot meet the segment (the slab test's verdict on x or y): in a room of a
    hundred items, testing each box for each item seen was most of a look."""

    def __init__(self, furniture: list[Box3], placed: list, boxes: list[Box3]) -> None:
        self.boxes = list(furniture) + list(boxes)
        self.names = [b.name for b in furniture] + [None] * len(boxes)  # furniture: what it holds up
        self.items = [None] * len(furniture) + list(placed)
        self.xy = np.array([(b.x0, b.x1, b.y0, b.y1) for b in self.boxes], dtype=float).reshape(-1, 4)

    def between(self, cam, it) -> list[Box3]:
        """The boxes that may hide ``it`` from ``cam``: across its line of sight, neither it
        nor the furniture it stands on."""
        x0, x1 = min(cam[0], it.x), max(cam[0], it.x)
        y0, y1 = min(cam[1], it.y), max(cam[1], it.y)
        b = self.xy
        hit = (b[:, 0] <= x1) & (b[:, 1] >= x0) & (b[:, 2] <= y1) & (b[:, 3] >= y0)
        return [
            self.boxes[k]
            for k in np.nonzero(hit)[0]
            if self.items[k] is not it and (self.names[k] is None or self.names[k] != it.on)
        ]
