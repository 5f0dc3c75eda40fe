"""The belief state: what the robot knows of the room, and what it does not know yet.

Goebelbecker et al. plan on a state where some facts are known and others are not yet known,
and bridge the gap with assumptions over virtual objects. For the tidy-up room that is:

- known items: seen, with a category and a believed place (floor, furniture top, the gripper,
  or a deposit once delivered);
- unseen items: what the scenario's ``[prior]`` tells the robot (12 = 4 x 3 in the O-FSM
  cases), so every missing one is a virtual object of a known category; told nothing, the robot
  assumes one more item of each deposit's category while some of the room is still unseen
  (docs/scenario.md). The true items are never read: the belief is built from the scenario
  without them (``Scenario.without_items``);
- where an unseen item may be: the placement points nobody has seen yet, and the viewpoints to
  see them from, are the exploration's (``tidyplan.belief.exploration``), which the belief owns
  and tells what each look showed;
- what the robot did: waypoints reached (Algorithm 1 needs them), looks taken, moves that
  found their way blocked.

The belief knows the static map (the paper's prerequisite: a pre-built occupancy map and the
deposits' poses) and computes line of sight against furniture only: it cannot know what
unseen items hide.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np

from sim.grid import Box
from sim.scenario.model import DrawerLayout, Scenario, drawer_layout, out_boxes
from sim.visibility import GLANCE_TILT_DEG, Box3, BoxTable, in_frame, visible
from tidyplan.belief import revisit
from tidyplan.belief.exploration import LOST_RADIUS, Exploration
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.known import Items, Known, Update, edits
from tidyplan.belief.mapfacts import ENTRANCE, MapFacts, Placed
from tidyplan.belief.percepts import MISS_EDGE_DEG, MISS_WIDTH, SWEEP_STOPS, Detection, Frame, in_stops

Point = tuple[float, float]

MISS_RANGE = 2.5  # m: a miss counts only this close; far detections are the unreliable ones
SAME_ITEM = 0.20  # m: a detection this close to a believed item of its category is that item
FORGET_AFTER = 3  # looks in a row that should have seen an item and did not: it is not there
# (at a false-negative rate of 0.2, three misses in a row of a real item happen 1 time in 125)
# m: a confirmed item seen this far from where it was believed has been moved there (and the grasp
# pose kept for its old place is chosen again)
MOVED = 0.03


class Belief:
    """Mutable by design: the loop owns one and updates it after every action; the facts handed
    to the planner are computed from it, never stored in it."""

    def __init__(self, scenario: Scenario, room: RoomMap) -> None:
        self.scenario = scenario.without_items()  # the robot is never told the true items
        self.room = room
        self.prior = scenario.prior_counts()  # None: told nothing, explore the whole room
        told = self.prior if self.prior is not None else {d.category for d in scenario.deposits}
        self.categories = sorted(told)
        self.items: dict[str, Known] = Items()
        self.robot: Point = room.entrance
        self.robot_wp = ENTRANCE  # the waypoint the robot last reached: its name for the planner
        self.holding: str | None = None
        self.reached: set[str] = {ENTRANCE}
        # Atoms of the domain's predicates no sensor reports (must-move-back, a user's own): the
        # scenario's facts to start with, then kept by the effects of the actions executed
        self.memory: set[tuple[str, ...]] = set(scenario.facts)
        # drawers not open, as the robot was told and then saw (the pull unit's check)
        self.closed: set[str] = {
            d.name for d in scenario.deposits if d.drawer is not None and d.drawer.closed
        }
        # how far each drawer is out, as told and then seen (m): the part out of its carcass is
        # furniture for the base (wrs-task1-s002: paths the map gave ran into the open top drawer)
        layouts = ((d.name, drawer_layout(scenario.furniture, d)) for d in scenario.deposits if d.drawer)
        self.drawers: dict[str, DrawerLayout] = {n: x for n, x in layouts if x is not None}
        self.drawer_out: dict[str, float] = {n: x.start for n, x in self.drawers.items()}
        # items the error layer gave up (monitor.loop): written without their category, so no
        # plan delivers them again; a plan may still move one aside
        self.undeliverable: set[str] = set()
        self.sticky: dict[str, Point] = {}
        self.blocked_moves: set[tuple[Point, Point]] = set()
        # (item place, robot pose): a close look from that pose did not find the item there
        self.failed_poses: list[tuple[Point, Point]] = []
        self._serial: Counter[str] = Counter()
        self.looks = 0  # sweeps and frames taken into the belief so far
        self.arrived: tuple[int, Point] = (0, self.robot)  # (looks, where) when a drive last ended
        self.forgotten: dict[str, Known] = {}  # seen again near where it was: same name
        self._occluders = [Box3.from_furniture(f) for f in scenario.furniture]
        # the last answers of facts (whole, among some waypoints) and poses, by what they depend on
        self._facts: tuple[tuple, MapFacts] | None = None
        self._focused: tuple[tuple, MapFacts] | None = None
        self._poses: tuple[tuple, MapFacts] | None = None
        self._untidied: tuple[tuple, list[Known], list[Placed]] = ((), [], [])  # untidied()'s
        self._placed_arrays: tuple = ((),)  # _in_place()'s, with untidied()'s key
        self._boxes: tuple = ((),)  # item_boxes()'s, with untidied()'s key
        # the space seen and the viewpoints to look from; it adds the map's viewpoints now
        self.exploration = Exploration(self.scenario, room, self._occluders)

    # ------------------------------------------------------------------ what is (not) known
    def virtual(self) -> list[tuple[str, str]]:
        """(name, category) of each item the room may still hold that nobody has seen: the
        virtual objects of the next problem, named by category and number. With a prior, those it
        names beyond the items seen; without one, one of each category while some of the room is
        unseen (``explorable``)."""
        if self.prior is None:
            return [(f"unseen-{cat}-1", cat) for cat in self.categories] if self.explorable() else []
        have = Counter(k.category for k in self.items.values())
        out = []
        for cat in self.categories:
            out += [(f"unseen-{cat}-{n + 1}", cat) for n in range(max(0, self.prior[cat] - have[cat]))]
        return out

    def explorable(self) -> bool:
        """Whether some viewpoint nobody has looked from would reveal unseen space."""
        return bool(self.exploration.p_item_near(self.poses()))

    def untidied(self) -> list[Known]:
        """The items not put away, by name; kept while no item changes (asked many times a turn)."""
        key = (edits(), self.items.edits) if isinstance(self.items, Items) else None  # (a dict: not kept)
        if key is None or self._untidied[0] != key:
            kept = sorted((k for k in self.items.values() if k.state != "tidied"), key=lambda k: k.name)
            self._untidied = (key, kept, [k.placed() for k in kept if k.state == "placed"])
        return list(self._untidied[1])

    def placed(self) -> list[Placed]:
        """Where the items not put away and not in the hand are: ``Known.placed`` of each."""
        self.untidied()
        return list(self._untidied[2])

    def facts(self, among: frozenset[str] | None = None) -> MapFacts:
        """The map's facts for the belief as it is; the monitor asks several times a step, so the
        last answer is kept while nothing it depends on changes (callers must not edit it).
        ``among``: the pairs of those waypoints only (and the robot's with them; every waypoint
        is there, ``RoomMap.facts``): what the monitor checks a plan against."""
        key = self._facts_key()
        kept = self._facts if among is None else self._focused
        if kept is not None and kept[0] == (key, among):
            return kept[1]
        facts = self.room.facts(*self._room_args(), among=among)
        self._stick(facts)
        if self.blocked_moves:
            # a move found this way blocked: the grid is wrong here (looked up by the few blocked
            # moves' points, not by every pair of waypoints)
            at: dict[Point, list[str]] = {}
            for name, q in facts.points.items():
                at.setdefault(q, []).append(name)
            for qa, qb in self.blocked_moves:
                for a in at.get(qa, ()):
                    for b in at.get(qb, ()):
                        facts.path.pop((a, b), None)
                        facts.adjust.pop((a, b), None)
                        facts.dropped.add((a, b))
        if among is None:
            self._facts = ((self._facts_key(), among), facts)
        else:
            self._focused = ((self._facts_key(), among), facts)
        return facts

    def poses(self) -> MapFacts:
        """``facts`` without any pair: the waypoints, each item's grasp pose and its adjustment,
        what the monitor asks of the map after every action (where an item is grasped from)."""
        key = self._facts_key()
        if self._poses is not None and self._poses[0] == key:
            return self._poses[1]
        poses = self.room.poses(*self._room_args())
        self._stick(poses)
        self._poses = (self._facts_key(), poses)
        return poses

    def _room_args(self) -> tuple:
        avoid = {
            k.name: [pose for place, pose in self.failed_poses if math.dist(place, (k.x, k.y)) <= SAME_ITEM]
            for k in self.untidied()
        }
        return self.placed(), (self.robot_wp, self.robot), self.sticky, avoid, self.drawers_out()

    def _stick(self, facts: MapFacts) -> None:
        """Keep the grasp poses just chosen for the next answers (a plan's waypoints survive)."""
        for item, wp in facts.grasp.items():
            self.sticky[item] = facts.points[wp]

    def _forget_facts(self) -> None:
        self._facts = self._focused = self._poses = None

    def _facts_key(self) -> tuple:
        return (
            tuple(self.placed()),
            self.robot_wp,
            self.robot,
            frozenset(self.blocked_moves),
            tuple(sorted(self.sticky.items())),
            tuple(self.failed_poses),
            tuple(sorted(self.drawer_out.items())),
        )

    def drawers_out(self) -> list[Box]:
        """The open drawers' boxes out of their carcasses, as last seen: furniture for the base."""
        return out_boxes(self.drawers, self.drawer_out)

    # ------------------------------------------------------------------ updates
    def drawer_seen(self, deposit: str, opening: float, is_open: bool) -> None:
        """A look at a drawer's front: it is out by ``opening`` m; open enough to use, or not."""
        self.drawer_out[deposit] = opening
        if is_open:
            self.closed.discard(deposit)
        else:
            self.closed.add(deposit)

    def at(self, point: Point, waypoint: str) -> None:
        self.robot, self.robot_wp = point, waypoint
        self.arrived = (self.looks, point)
        self.reached.add(waypoint)

    def observe(
        self,
        detections: list[Detection],
        waypoint: str | None,
        frame: Frame | None = None,
        stops: tuple[float, ...] | None = None,
    ) -> Update:
        """A sweep from where the robot stands (of the pan ``stops`` given, headings in the room's
        frame; all around by default), or one ``frame`` taken on the way (``detections`` are then
        the frame's): add, confirm and forget items; mark the space it showed seen. A frame, and
        a sweep of some stops, show and count misses in their own field only."""
        update = Update()
        self.looks += 1
        at = self.robot if frame is None else frame.at
        wedge = frame is not None and frame.heading is not None
        self.exploration.looked(at, frame, stops)
        if waypoint is not None:
            self.exploration.looked_from.add(waypoint)
        matched: set[str] = set()
        for d in detections:
            k = self._match(d, matched)
            if k is not None:
                k.misses = 0
                # a fallen item found, or one knocked aside: now its place is known
                if k.spread or math.dist((k.x, k.y), (d.x, d.y)) > MOVED:
                    self.relocate(k.name, d.x, d.y)
                k.sx, k.sy, k.sz = d.sx, d.sy, d.sz  # and its extent as it lies now (relocate)
                k.oriented = d.down is not None  # what the detector says of it now (relocate)
                matched.add(k.name)
                update.confirmed.append(k.name)
                k.saw(at, self.looks)
                continue
            under = self._under(d)
            if under is not None:
                update.overlapping.append(under.name)
                continue
            name = self._add(d)
            self.items[name].saw(at, self.looks)
            matched.add(name)
            update.new.append(name)
        boxes = None  # the believed items as occluders, built once for this look's misses
        placed, index, xy, z = self._in_place()
        shown = np.ones(len(placed), dtype=bool)  # those in place this look did not match
        for name in matched:
            if name in index:
                shown[index[name]] = False
        # the frame's field and the stops first, for all of them at once: they are cheap, the
        # line of sight is not
        if len(placed) and (wedge or stops is not None):
            if wedge:
                shown &= self._in_frame(at, frame.heading, xy, z, miss=True, tilt=frame.tilt_deg)
            if stops is not None:
                shown &= in_stops(at, stops, xy, self.scenario.sensing.fov_h_deg, MISS_WIDTH)
        for n in np.flatnonzero(shown).tolist():
            k = placed[n]
            if boxes is None:
                boxes = self.item_boxes()
            if not self.should_see(k, at, boxes):
                continue
            k.misses += 1
            if k.misses >= FORGET_AFTER:
                self.forget(k.name)
                update.forgotten.append(k.name)
                boxes = None  # a forgotten item hides nothing from the next
        return update

    def _in_place(self) -> tuple[list[Known], dict[str, int], np.ndarray, np.ndarray]:
        """The untidied items believed in place, in name order, their index by name, their
        (x, y) and the heights a look aims at: kept with ``untidied`` (every frame's misses
        ask for them)."""
        self.untidied()
        key = self._untidied[0]
        if key is None or self._placed_arrays[0] != key:
            placed = [k for k in self._untidied[1] if k.state == "placed"]
            xy = np.array([[k.x, k.y] for k in placed], dtype=float).reshape(-1, 2)
            z = np.array([self._z(k) for k in placed], dtype=float)
            arrays = (key, placed, {k.name: n for n, k in enumerate(placed)}, xy, z)
            if key is None:
                return arrays[1:]
            self._placed_arrays = arrays
        return self._placed_arrays[1:]

    def _add(self, d: Detection) -> str:
        name = self._revive(d)
        if name is None:
            self._serial[d.category] += 1
            name = f"{d.category}-{self._serial[d.category]}"
        oriented = d.down is not None
        self.items[name] = Known(name, d.category, d.x, d.y, d.on, d.sx, d.sy, d.sz, oriented=oriented)
        return name

    def bumped(self, d: Detection) -> str | None:
        """What a close look around the robot found after its base ran into something (the head
        camera cannot see so near): the believed item of that category nearest it, within
        LOST_RADIUS, was knocked there; else it is an item never seen. Returns a new item's name."""
        near = [
            k
            for k in self.items.values()
            if k.state == "placed"
            and k.category == d.category
            and math.dist((k.x, k.y), (d.x, d.y)) <= LOST_RADIUS
        ]
        if near:
            k = min(near, key=lambda k: (math.dist((k.x, k.y), (d.x, d.y)), k.name))
            self.relocate(k.name, d.x, d.y, oriented=d.down is not None)
            k.on, k.sx, k.sy, k.sz = d.on, d.sx, d.sy, d.sz
            return None
        return self._add(d)

    def forget(self, name: str) -> None:
        """An item believed in a place that is not there (a false detection, or it moved)."""
        k = self.items.pop(name, None)
        if k is not None:
            self.forgotten[name] = k
        self.sticky.pop(name, None)

    def lost(self, name: str) -> None:
        """An item not where the belief had it, after a close look: forgotten, and the space
        around that place unseen again, so exploration looks for it there (it may have rolled).
        An item seen there again is grasped from another pose: the look from this one failed."""
        k = self.items.get(name)
        if k is not None:
            self.unreached(name)
            self.exploration.unsee((k.x, k.y), max(LOST_RADIUS, k.spread + 0.4))
        self.forget(name)

    def not_found(self, name: str) -> None:
        """A close look from where the robot stands did not find the item. Where a look since
        the robot arrived here showed it (a frame the drive took on its way) and the robot has not
        moved since, it is there and this pose does not show it to the close look (a table's
        edge, another item in between): it is grasped from another pose. Else it is not where the
        belief had it: lost. (wrs-task1-s001: a tool on the tall table, shown by the frames on the
        way, missed by the close looks from two poses; lost each time, found again from two
        viewpoints, 80 s a round.)"""
        k = self.items.get(name)
        looks, where = self.arrived
        if (
            k is not None
            and k.state == "placed"
            and k.seen_look > looks
            and math.dist(where, self.robot) <= 0.05
        ):
            self.unreached(name)
        else:
            self.lost(name)

    def unreached(self, name: str) -> None:
        """The item could not be taken from where the robot stands (a look did not find it, the
        arm did not reach it, no base pose near this one did): the map grasps it from another
        pose. The map's reach is a distance, the arm's is not (wrs-task1-s106: a spoon on the
        floor between two tables, 0.64 m out, tried from the same pose until given up)."""
        k = self.items.get(name)
        if k is not None and k.state == "placed":
            self.failed_poses.append(((k.x, k.y), self.robot))

    def in_deposit(self, deposit: str) -> list[Known]:
        """The items believed tidied into ``deposit``."""
        return [k for k in self.items.values() if k.state == "tidied" and k.deposit == deposit]

    def inspect_deposit(self, deposit: str, detections: list[Detection]) -> tuple[list[str], list[str]]:
        """What close looks into a deposit showed (``detections``, distinct items): each believed
        item of the deposit is confirmed by one shown of its category; those left over are not
        there (knocked out, or never placed right) and are lost, to be found and tidied again.
        Returns (confirmed, lost)."""
        shown = Counter(d.category for d in detections)
        confirmed, gone = [], []
        for k in sorted(self.in_deposit(deposit), key=lambda k: k.name):
            if shown[k.category] > 0:
                shown[k.category] -= 1
                confirmed.append(k.name)
            else:
                gone.append(k.name)
        for name in gone:
            self.lost(name)
        return confirmed, gone

    def taken(self, name: str) -> None:
        k = self.items[name]
        k.state, self.holding = "held", name
        if k.on == "floor":
            self.exploration.scene_changed = True
            self.blocked_moves.clear()  # the floor changed: old blockages may be gone
        self.sticky.pop(name, None)

    def put(self, name: str, x: float, y: float, on: str = "floor", aside: bool = False) -> None:
        """The item in the hand put down at (x, y); ``aside``: out of the way (``put_down``)."""
        k = self.items[name]
        k.state, k.x, k.y, k.on, k.misses, k.spread, k.aside = "placed", x, y, on, 0, 0.0, aside
        self.holding = None

    def fell(self, name: str, near: Point, spread: float) -> None:
        """The item in the hand slipped out near ``near``: on the floor within ``spread`` of it,
        place not seen yet (the pick-up's check looks for it there)."""
        self.put(name, *near)
        self.items[name].spread = spread
        self.exploration.scene_changed = True
        self.exploration.unsee(near, spread + 0.4)  # a look for it covers where it may have rolled

    def relocate(
        self,
        name: str,
        x: float,
        y: float,
        size: tuple[float, float, float] | None = None,
        oriented: bool | None = None,
    ) -> None:
        """A look found the item at (x, y), ``size`` (sx, sy, sz) as it lies now: a tall box that
        toppled covers more floor (kept upright in the belief, the map let the base drive into it,
        and a put-down ring fit for it upright shut the robot in). ``oriented``: whether the
        detector reported a down end this time; the object a close look finds of the category
        may be another than the one first seen there (a box beside a marker: the box was taken,
        believed a marker, and stood on its end in container B, out of which it toppled)."""
        k = self.items[name]
        if oriented is not None:
            k.oriented = oriented
        if math.dist((k.x, k.y), (x, y)) > MOVED:
            self.sticky.pop(name, None)  # the grasp pose chosen for the old place may not fit
        k.x, k.y, k.spread, k.misses = x, y, 0.0, 0
        if size is not None:
            k.sx, k.sy, k.sz = size
        # another believed item whose footprint holds the place is this object, seen earlier under
        # another name (two solid objects cannot lie there): kept, each blocked the other's grasp
        # poses for good (wrs-task1-s009: kitchen-2 and kitchen-7 at one place, no plan for either)
        for other in [o for o in self.items.values() if o.name != name and o.state == "placed"]:
            if other.on == k.on and abs(x - other.x) < other.sx / 2 and abs(y - other.y) < other.sy / 2:
                del self.items[other.name]
                self.sticky.pop(other.name, None)

    def delivered(self, name: str, deposit: str) -> None:
        k = self.items[name]
        k.state, k.deposit = "tidied", deposit
        self.holding = None

    # ------------------------------------------------------------------ geometry
    def _match(self, d: Detection, taken: set[str]) -> Known | None:
        best = None
        for k in self.items.values():
            if k.state != "placed" or k.category != d.category or k.name in taken:
                continue
            dist = math.dist((k.x, k.y), (d.x, d.y))
            if dist <= max(SAME_ITEM, k.spread) and (best is None or dist < best[0]):
                best = (dist, k)
        return None if best is None else best[1]

    def _under(self, d: Detection) -> Known | None:
        """A believed item on the same support whose footprint holds the detection's centre: two
        solid objects cannot lie there, so this is that item seen as another category (or twice)
        and adds nothing. Were the belief the wrong one, its misses forget it in time."""
        for k in self.items.values():
            inside = abs(d.x - k.x) < k.sx / 2 and abs(d.y - k.y) < k.sy / 2
            if inside and k.state == "placed" and k.on == d.on:
                return k
        return None

    def _revive(self, d: Detection) -> str | None:
        """The name of a forgotten item of this category that lay where d is, if any."""
        for name, k in sorted(self.forgotten.items()):
            if k.category == d.category and math.dist((k.x, k.y), (d.x, d.y)) <= SAME_ITEM:
                del self.forgotten[name]
                return name
        return None

    def should_see(self, k: Known, at: Point | None = None, boxes: list | None = None) -> bool:
        """Would a look from ``at`` (default: where the robot is) see k if it were there?
        ``boxes``: ``item_boxes()``, for a caller asking of many items in one state."""
        at = self.robot if at is None else at
        s = self.scenario.sensing
        z = self._z(k)
        across = math.dist(at, (k.x, k.y))
        if across > MISS_RANGE:
            return False
        # Under the sweep's lowest frame (the floor right beside the base) a miss is no evidence:
        # an item the robot dropped beside itself was forgotten there, and driven into.
        if math.degrees(math.atan2(s.camera_height - z, across)) > s.look_down_deg:
            return False
        # Furniture, and the items it knows of, may hide k: a miss behind them is no evidence.
        if boxes is None:
            boxes = self.item_boxes()
        eye, target = self.exploration.camera(at), (k.x, k.y, z)
        # the furniture and items whose boxes may meet the line of sight (a table's: at once)
        fixed, near = (
            boxes.near_segment(eye, target) if isinstance(boxes, BoxTable) else (self._occluders, boxes)
        )
        occ = [b for b in fixed if b.name != k.on] + [b for o, b in near if o is not k]
        return visible(eye, target, occ, range_min=s.range_min, range_max=s.range_max)

    def _z(self, k: Known) -> float:
        """The height a look aims at: 5 cm above what k lies on."""
        return 0.05 if k.on == "floor" else self.scenario.furniture_named(k.on).height + 0.05

    def _xyz(self, k: Known) -> tuple[np.ndarray, np.ndarray]:
        return np.array([[k.x, k.y]]), np.array([self._z(k)])

    def _in_frame(
        self,
        at: Point,
        heading: float,
        xy: np.ndarray,
        z: np.ndarray,
        miss: bool = False,
        tilt: float = GLANCE_TILT_DEG,
    ) -> np.ndarray:
        """``sim.visibility.in_frame``; ``miss``: only the part where a miss counts."""
        width, edge = (MISS_WIDTH, MISS_EDGE_DEG) if miss else (1.0, 0.0)
        return in_frame(at, heading, xy, z, self.scenario.sensing, width, edge, tilt)

    def item_boxes(self) -> BoxTable:
        """The untidied items believed in place, with their boxes: what may hide another (kept
        with ``untidied``'s key, as ``_in_place``: callers must not edit it)."""
        self.untidied()
        key = self._untidied[0]
        if key is None or self._boxes[0] != key:
            items = ((o, self._box3(o)) for o in self._untidied[1] if o.state == "placed")
            table = BoxTable(items, fixed=self._occluders)
            if key is None:
                return table
            self._boxes = (key, table)
        return self._boxes[1]

    def _box3(self, k: Known) -> Box3:
        return Box3.from_item(k, 0.0 if k.on == "floor" else self.scenario.furniture_named(k.on).height)

    # ------------------------------------------------------------------ exploration
    # What of the room has been seen and where to look is the exploration's (exploration.py);
    # what it means for the items nobody has found is the belief's.

    def look_finds(self, at: Point) -> float:
        """How many of the items nobody has found (the virtual objects) a sweep from ``at`` is
        expected to find: spread uniformly over the placement points nobody has seen (as
        ``p_item_near``), the share of them in view, each seen at the detector's hit rate. Asked
        after every action, for the trace's ``why``: without a prior it counts one per category
        while some space is unseen (as ``virtual``) without ``virtual``'s map facts, which the
        action has made stale."""
        missing = self._missing()
        if missing == 0:
            return 0.0
        return missing * self.exploration.unseen_share(at) * (1.0 - self.scenario.sensing.false_negative)

    def _missing(self) -> int:
        """How many items nobody has found: the prior's count less those known, or one per
        category without a prior (as ``virtual``)."""
        if self.prior is None:
            return len(self.categories)
        have = Counter(k.category for k in self.items.values())
        return sum(max(0, self.prior[c] - have[c]) for c in self.categories)

    def stop_finds(self, at: Point) -> list[tuple[float, float]]:
        """For each of a sweep's stops (SWEEP_STOPS): its heading and the items nobody has found
        that its frames are expected to find (``look_finds``, of the part of the view nearer that
        stop's heading than any other's, so that the stops' finds add up to the sweep's)."""
        missing = self._missing()
        if missing == 0:
            return [(h, 0.0) for h in SWEEP_STOPS]
        hit = 1.0 - self.scenario.sensing.false_negative
        return [(h, missing * share * hit) for h, share in self.exploration.stop_shares(at)]

    def explore_again(self) -> list[str] | None:
        """A new round of exploration (``Exploration.new_round``), when the prior names items
        nobody has found and the whole room has been seen, with a viewpoint at each forgotten
        item's place. Returns the viewpoints added, None when the rounds are used up."""
        added = self.exploration.new_round()
        if added is None:
            return None
        self._forget_facts()  # the map has new viewpoints
        looks = revisit.viewpoints_at_forgotten(self)
        if looks:
            self._forget_facts()
        return added + looks
