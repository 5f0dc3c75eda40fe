"""The room as the planner sees it: waypoints, paths k(x, y), reachability h(x, y), obstructions.

Yan et al. plan over "the length of a feasible path" between robot, object and deposit (Eq. 2-4)
on an occupancy grid that the robot "maintains dynamically according to the position of the
objects detected". This module turns a scenario's static map plus a list of placed items (where
the belief, or the hidden truth, has them) into the facts of ``domains/tidy.pddl``:

- a waypoint for the entrance, each viewpoint, each deposit (where the robot stands to deliver)
  and each item (where it stands to grasp it);
- ``path``/``distance`` for every pair joined on the grid with the floor items as obstacles;
- ``blocked``/``blocks`` for pairs joined only once some floor item is taken away (P3's case);
- ``pose-adjustment`` into a grasp or delivery pose that the navigation grid, inflated by a
  safety margin, cannot reach but the bare footprint fits (P2's "additional motions ... to
  obtain a feasible and collision-free grasping pose").

Two grids: navigation plans with the footprint plus a margin (as a costmap's inflation does);
the bare footprint decides where a careful pose adjustment may still go.
"""

from __future__ import annotations

import math
import operator
from collections import OrderedDict
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from sim.grid import Box, OccupancyGrid
from sim.joins import joins_without, pair_cells
from sim.scenario.model import Scenario
from tidyplan.belief.grasp import ADJUST_MAX, GraspPoses
from tidyplan.belief.mapfacts import ENTRANCE, MapFacts, Placed, Point, deposit_waypoint
from tidyplan.belief.ring import box_key

PATHS_KEPT = 8  # sets of fixed waypoints whose pairs a floor keeps (a few components, sticky poses)
FLOORS_KEPT = 4  # floors whose grasp poses and blockers are kept (a failed grasp's replan sees the last)
BLOCKERS_KEPT = 8  # sets of floor items whose blocked pairs' answers are kept (_Floor.blockers, joined)
CHANGED_MOST = 8  # floor items come or gone from a kept grid's: past it, a grid is made anew


@dataclass(slots=True)
class _Floor:
    """What one floor (the placed items, the open drawers) gives that the robot's pose does not
    change: the grasp poses chosen from each component the robot can stand in, each blocked
    pair's blockers, the fixed waypoints' pairs. After a move, the facts cost the robot's own
    waypoint. A new floor puts them together again from what the RoomMap keeps across floors
    (each item's grasp facts in its ``GraspPoses``, each box's window without it, each static
    path's items), so it works out anew only what lies near the change."""

    grasp: dict[tuple, MapFacts] = field(default_factory=dict)
    blockers: dict[tuple[Point, Point], tuple[str, ...]] = field(default_factory=dict)
    # the single floor items whose removal joins a kind of pair (its ends' components)
    joined: dict[tuple, tuple[str, ...]] = field(default_factory=dict)
    paths: dict[tuple, MapFacts] = field(default_factory=dict)  # _add_paths' fixed pairs
    focused: dict[tuple, MapFacts] = field(default_factory=dict)  # those among some waypoints
    # the floor items' boxes and the grids with them: (floor, navigation, static, bare)
    grids: tuple | None = None


class RoomMap:
    """The static map of a scenario and the facts it gives for any placement of items.

    Grids are cached by their set of floor obstacles: a replan after a failed grasp sees the
    same floor and costs nothing here.
    """

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.nav_radius = scenario.robot.radius + scenario.robot.nav_margin
        self.bare_radius = scenario.robot.radius
        self._origin: Point = (0.0, 0.0)  # where reachability is counted from, set by facts()
        self._out: tuple[Box, ...] = ()  # the open drawers' boxes, set by facts()
        # least recently used last out: the static map (asked every turn) keeps its paths
        self._grids: OrderedDict[tuple[float, frozenset[tuple]], OccupancyGrid] = OrderedDict()  # box_keys
        self._floors: OrderedDict[tuple, _Floor] = OrderedDict()  # the last few floors' work
        self._blocker_sets: OrderedDict[tuple, tuple] = OrderedDict()  # _Floor's blockers, joined
        self._last_floor: tuple | None = None  # (items, open drawers, _Floor) last asked (_floor_of)
        self._lines: dict[tuple, np.ndarray] = {}  # static paths' cells, for _near_paths
        self._discs: dict[tuple, np.ndarray] = {}  # the cells near an item, for _near_paths
        self._without: dict[tuple, tuple | None] = {}  # sim.joins' window parts, across floors
        self._near: dict[tuple, tuple] = {}  # a static path's floor items: (those asked, those near)
        static = self.grid(())
        self.entrance = static.nearest_free(*scenario.entrance)
        self.fixed: dict[str, Point] = {ENTRANCE: self.entrance}
        self.fixed_kind: dict[str, str] = {ENTRANCE: "entrance"}
        for v in scenario.viewpoints:
            self.fixed[v.name] = static.nearest_free(v.x, v.y, reachable_from=self.entrance)
            self.fixed_kind[v.name] = "viewpoint"
        for d in scenario.deposits:
            name = deposit_waypoint(d.name)
            if d.approach is not None:
                self.fixed[name] = d.approach
            else:  # in front of the deposit where the navigation grid reaches
                self.fixed[name] = static.nearest_free(d.x, d.y, reachable_from=self.entrance)
            self.fixed_kind[name] = "deposit"
        self.grasps = GraspPoses(self)  # each item's grasp pose, and what it depends on

    def add_viewpoint(self, name: str, point: Point) -> None:
        """A viewpoint beyond the scenario's (generated from the map by the belief)."""
        self.fixed[name], self.fixed_kind[name] = point, "viewpoint"

    # ------------------------------------------------------------------ grids
    def grid(self, floor: Iterable[Box], *, bare: bool = False) -> OccupancyGrid:
        """The occupancy grid with the furniture and these floor boxes, navigation or bare radius."""
        radius = self.bare_radius if bare else self.nav_radius
        # the boxes as plain tuples: C's hashing and comparing, not a dataclass's (several grids
        # a turn, each a key over every floor item)
        key = (radius, frozenset(map(box_key, floor)))
        if key in self._grids:
            self._grids.move_to_end(key)
        else:
            while len(self._grids) > 64:  # a mission sees a few dozen floors; keep memory bounded
                self._grids.popitem(last=False)
            boxes = tuple(f.box() for f in self.scenario.furniture) + tuple(Box(*k) for k in sorted(key[1]))
            # a floor a few items from one kept (the latest such): its grid from that one's,
            # changed there only (a look may show a few floor items at once: at 96 objects a
            # grid made anew took about 3 ms, one changed by an item 0.35 ms)
            near = next(
                (
                    (g, k[1])
                    for k, g in reversed(self._grids.items())
                    if k[0] == radius and len(k[1] ^ key[1]) <= CHANGED_MOST
                ),
                None,
            )
            if near is not None:
                grid, floor = near
                gone, new = sorted(floor - key[1]), sorted(key[1] - floor)
                self._grids[key] = grid.changed(boxes, [Box(*k) for k in gone], [Box(*k) for k in new])
            else:
                self._grids[key] = OccupancyGrid(self.scenario.bounds, boxes, radius=radius)
        return self._grids[key]

    # ------------------------------------------------------------------ facts
    def facts(
        self,
        items: Sequence[Placed],
        robot: tuple[str, Point] | None = None,
        sticky: dict[str, Point] | None = None,
        avoid: dict[str, list[Point]] | None = None,
        out: Sequence[Box] = (),
        among: frozenset[str] | None = None,
    ) -> MapFacts:
        """Waypoints and path facts with ``items`` where they are; ``robot`` = (name, point) adds
        the robot's pose under that name (the waypoint it last reached, which may be gone from the
        map: the grasp pose of the item now in its hand) when no waypoint is there already.
        ``sticky`` holds grasp poses chosen before: kept while still usable, so a plan's waypoints
        survive a replan. ``out``: the open drawers' boxes out of their carcasses, furniture for
        the base as long as they are out (never an item to take away). ``among``: the pairs of
        those waypoints only (and the robot's with them; the entrance always: a tight deposit is
        one the entrance does not reach), each as the whole map has it; every waypoint is there."""
        facts = self.poses(items, robot, sticky, avoid, out)
        floor_memo = self._floor_of(items)
        _floor, nav, static, _bare = floor_memo.grids
        self._add_paths(facts, items, nav, static, floor_memo, among)
        return facts

    def poses(
        self,
        items: Sequence[Placed],
        robot: tuple[str, Point] | None = None,
        sticky: dict[str, Point] | None = None,
        avoid: dict[str, list[Point]] | None = None,
        out: Sequence[Box] = (),
    ) -> MapFacts:
        """``facts`` without the pairs: the waypoints (the robot's too) and each item's grasp pose,
        with its adjustment or the items its reach waits for."""
        self._out = tuple(out)
        floor_memo = self._floor_of(items)
        if floor_memo.grids is None:
            floor = [p.box() for p in items if p.on_floor]
            base_floor = floor + list(out)
            floor_memo.grids = (
                floor,
                self.grid(base_floor),
                self.grid(out),
                self.grid(base_floor, bare=True),
            )
        floor, nav, static, bare = floor_memo.grids
        facts = MapFacts(points=dict(self.fixed), kind=dict(self.fixed_kind))
        # Reachable from where the robot is, not from the entrance: an item that fell by the door
        # shuts the entrance's cell, not the room (case III with faults had no grasp pose left),
        # and one dropped beside the robot in a corner shuts the robot in: the grasp pose that
        # frees it must be one it reaches from there (case III with faults, seed 1).
        self._origin = self.entrance
        if robot is not None:
            q = robot[1]
            self._origin = q if nav.free(*q) else nav.nearest_free(*q)
        component = nav.component(*self._origin)
        key = (
            component,
            None if component else self._origin,  # no component: nothing reachable, from here
            tuple((p.name, (sticky or {}).get(p.name)) for p in items),
            tuple((p.name, tuple((avoid or {}).get(p.name, ()))) for p in items),
        )
        chosen = floor_memo.grasp.get(key)
        if chosen is None:
            # the grasp poses depend on the robot only through the cells it reaches (its
            # component); each item's is kept by what it depends on (``GraspPoses``)
            chosen = self.grasps.choose(
                items, floor, nav, static, bare, sticky or {}, avoid or {}, self._out, self._origin
            )
            floor_memo.grasp[key] = chosen
            # The belief keeps the poses just chosen (its sticky ones) and asks again: with them
            # kept, each item's choice is the same (a pose kept is taken where still usable, and
            # it is usable: it was just chosen), so the answer is stored for that question too
            kept = dict(sticky or {})
            kept.update((item, chosen.points[wp]) for item, wp in chosen.grasp.items())
            floor_memo.grasp[(*key[:2], tuple((p.name, kept.get(p.name)) for p in items), key[3])] = chosen
        facts.add_poses(chosen)
        if robot is not None and robot[0] not in facts.points:
            # under its own name even beside another waypoint: the plan being executed says it
            facts.points[robot[0]], facts.kind[robot[0]] = robot[1], "robot"
        elif robot is not None and not any(math.dist(robot[1], q) < 0.03 for q in facts.points.values()):
            facts.points["wp-robot"], facts.kind["wp-robot"] = robot[1], "robot"
        return facts

    def _floor_of(self, items: Sequence[Placed]) -> _Floor:
        """``_floor`` of these items and the open drawers (``self._out``): the last one asked
        at once where the items are the very same records (the belief's, kept while an item
        is unchanged), without hashing every item (several times a turn, at 96 objects)."""
        last = self._last_floor
        if (
            last is not None
            and last[1] == self._out
            and len(last[0]) == len(items)
            and all(map(operator.is_, last[0], items))
        ):
            return last[2]
        key = (tuple(items), self._out)
        memo = self._floor(key)
        self._last_floor = (key[0], self._out, memo)
        return memo

    def _floor(self, key: tuple) -> _Floor:
        """The remembered work for this floor (new if it was not among the last few). Each
        key is hashed as few times as may be: a tuple of a room's items hashes every item."""
        memo = self._floors.get(key)
        if memo is not None:
            self._floors.move_to_end(key)
            return memo
        memo = self._floors[key] = _Floor()
        while len(self._floors) > FLOORS_KEPT:
            self._floors.popitem(last=False)
        # A pair's blockers depend on the floor items and the open drawers alone: a floor that
        # differs from one before only off the floor (an item taken from a table, a quarter of
        # the new floors at 96 objects) finds them again not at all
        by = (tuple(p for p in key[0] if p.on_floor), key[1])
        found = self._blocker_sets.pop(by, None) or ({}, {})
        memo.blockers, memo.joined = self._blocker_sets[by] = found  # the newest last
        while len(self._blocker_sets) > BLOCKERS_KEPT:
            self._blocker_sets.popitem(last=False)
        return memo

    def _add_paths(
        self, facts: MapFacts, items: Sequence[Placed], nav, static, floor_memo: _Floor, among=None
    ) -> None:
        """The path, blocked, blocks and adjustment facts of every pair of ``facts.points`` (of
        ``among``, and the robot's, where given). The pairs of the fixed waypoints (all but the
        robot's own) depend on the floor, their points and the part of the room the robot is
        in, not on where in it the robot stands: they are worked out once per floor and kept
        (``_Floor.paths``); after a move, only the robot's pairs are new (a turn's cost then
        grows with the waypoints, not with their pairs)."""
        names = sorted(facts.points)
        if among is not None:
            names = [n for n in names if n in among or n == ENTRANCE or facts.kind[n] == "robot"]
        robots = [n for n in names if facts.kind[n] == "robot"]
        fixed = [n for n in names if facts.kind[n] != "robot"]
        component = nav.component(*self._origin)
        key = (
            component,
            None if component else self._origin,
            tuple((n, facts.points[n], facts.kind[n]) for n in fixed),
            tuple(facts.reach_blockers.items()),
        )
        kept = floor_memo.paths if among is None else floor_memo.focused
        part = kept.get(key)
        if part is None:
            part = MapFacts(
                points={n: facts.points[n] for n in fixed}, kind={n: facts.kind[n] for n in fixed}
            )
            part.reach_blockers = dict(facts.reach_blockers)
            self._fixed_paths(part, items, nav, static, floor_memo)
            if len(kept) >= PATHS_KEPT:
                kept.clear()
            kept[key] = part
        bases = [n for n in part.points if n not in facts.points]  # the deposits' adjustment poses
        for n in bases:
            facts.points[n], facts.kind[n] = part.points[n], part.kind[n]
        # the robot's pairs (and the grasp poses' adjustments, chosen before) apart from the
        # floor's: a reader of what changed after a move reads these only (``MapFacts.own``)
        own = MapFacts(points=facts.points, kind=facts.kind, reach_blockers=facts.reach_blockers)
        own.adjust = dict(facts.adjust)
        for r in robots:
            self._robot_paths(own, items, names, r, bases, nav, static, floor_memo)
        facts.add_pairs(part)
        facts.add_pairs(own)
        facts.shared, facts.own = part, own

    def _fixed_paths(self, facts: MapFacts, items, nav, static, floor_memo: _Floor) -> None:
        """``_add_paths`` for waypoints none of which is the robot's."""
        names = sorted(facts.points)
        pts = [facts.points[n] for n in names]
        now = nav.length_matrix(pts)
        later = static.length_matrix(pts)
        np.fill_diagonal(now, np.nan)
        np.fill_diagonal(later, np.nan)
        drivable = ~np.isnan(now)
        for i, j in zip(*np.nonzero(drivable), strict=True):
            facts.path[(names[i], names[j])] = round(float(now[i, j]), 2)
        blocked_pairs = [
            (int(i), int(j)) for i, j in zip(*np.nonzero(~drivable & ~np.isnan(later)), strict=True)
        ]
        for i, j in blocked_pairs:
            facts.blocked[(names[i], names[j])] = round(float(later[i, j]), 2)
        # Tight deposit poses get an adjustment from their nearest navigable waypoint-free cell.
        if ENTRANCE in names:
            entrance = names.index(ENTRANCE)
            for i, n in enumerate(names):
                if facts.kind[n] == "deposit" and np.isnan(later[i, entrance]):
                    self._adjust_into(facts, n, nav)
        if blocked_pairs:
            self._blockers(facts, items, names, pts, blocked_pairs, floor_memo)
        self._reach_blocked(facts, names)

    def _robot_paths(self, facts: MapFacts, items, names, r: str, bases, nav, static, floor_memo) -> None:
        """The pairs of the robot's waypoint ``r`` with every waypoint in ``names`` and with the
        deposits' adjustment poses (``bases``), as ``_fixed_paths`` gives the others'. A robot
        left in a tight pose that is no waypoint any more (the item it was to grasp from there
        turned out not to exist) gets an adjustment too: it backs out the way it came."""
        q = facts.points[r]
        others = [n for n in names if n != r]
        pts = [facts.points[n] for n in others]
        now_there, now_back = nav.lengths_both_ways(q, pts)
        later_there, later_back = static.lengths_both_ways(q, pts)
        blocked_pairs = []
        index = {n: k for k, n in enumerate(names)}
        for n, there, back, later_t, later_b in zip(
            others, now_there, now_back, later_there, later_back, strict=True
        ):
            for (a, b), length, later in (((r, n), there, later_t), ((n, r), back, later_b)):
                if length is not None:
                    facts.path[(a, b)] = round(length, 2)
                elif later is not None:
                    facts.blocked[(a, b)] = round(later, 2)
                    blocked_pairs.append((index[a], index[b]))
        for base in bases:
            length = nav.path_length(q, facts.points[base])
            if length is not None:
                facts.path[(r, base)] = facts.path[(base, r)] = round(length, 2)
        if not nav.free(*q):
            self._adjust_into(facts, r, nav)
        if blocked_pairs:
            self._blockers(facts, items, names, [facts.points[n] for n in names], blocked_pairs, floor_memo)
        self._reach_blocked(facts, [r])

    @staticmethod
    def _reach_blocked(facts: MapFacts, names) -> None:
        """A grasp pose whose reach crosses a floor item is entered only once that item is gone:
        from each of ``names``."""
        for g, who in facts.reach_blockers.items():
            for a in names:
                if (a, g) in facts.path:
                    facts.blocked[(a, g)] = facts.path.pop((a, g))
                if (a, g) in facts.blocked:
                    facts.blocks.update((item, a, g) for item in who)

    def _adjust_into(self, facts: MapFacts, name: str, nav: OccupancyGrid) -> None:
        target = facts.points[name]
        base = nav.nearest_free_within(target, ADJUST_MAX, self._origin)
        if base is None:
            return
        bname = name + "-base"
        facts.points[bname], facts.kind[bname] = base, "adjust"
        d = round(math.dist(base, target), 2)
        facts.adjust[(bname, name)] = facts.adjust[(name, bname)] = d
        others = [o for o in facts.points if o != bname and facts.kind[o] != "adjust"]
        # one search, from the base (the graph is undirected: the length there is the length back)
        lengths = nav.lengths_from(base, [facts.points[o] for o in others])
        for other, length in zip(others, lengths, strict=True):
            if length is not None:
                facts.path[(other, bname)] = facts.path[(bname, other)] = round(length, 2)

    def _blockers(self, facts, items, names, pts, pairs, floor_memo: _Floor) -> None:
        """Which floor item, taken away alone, frees each blocked pair; failing any single one,
        every floor item near the pair's path on the static map (all of them must go). Each
        pair's answer depends on its two points and the floor only: remembered per floor."""
        known = floor_memo.blockers
        todo = list(dict.fromkeys((pts[i], pts[j]) for i, j in pairs if (pts[i], pts[j]) not in known))
        if todo:
            self._find_blockers(items, todo, floor_memo)
        for i, j in pairs:
            for item in known[(pts[i], pts[j])]:
                facts.blocks.add((item, names[i], names[j]))

    def _find_blockers(self, items, pairs: list[tuple[Point, Point]], floor_memo: _Floor) -> None:
        floor = [p for p in items if p.on_floor]
        nav = floor_memo.grids[1]  # the floor's navigation grid, kept with it (poses made it)
        # Whether taking one item away joins a pair depends on the components its two ends are
        # in, where an end stands in one (an end no cell of the grid holds: on that end): pairs
        # of the same two components get one answer (a two-room floor: thousands of pairs, a
        # few dozen such kinds), on this floor and on the floors with the same floor items
        # (``_Floor.joined``: a new plan's waypoints, the robot's after a move, ask of the same
        # kinds again)
        kinds: dict[Point, tuple] = {}
        for q in {q for pair in pairs for q in pair}:
            label = nav.component(*q)
            kinds[q] = ("component", label) if label else ("point", q)
        who_of = floor_memo.joined
        kind_of = [(kinds[a], kinds[b]) for a, b in pairs]
        first: dict[tuple, int] = {}  # a kind of pair not met before -> its first pair, asked
        for n, kind in enumerate(kind_of):
            if kind not in who_of:
                first.setdefault(kind, n)
        if first:
            ask = sorted(first.values())
            cells = pair_cells(nav, [pairs[n] for n in ask])
            freed = np.zeros((len(floor), len(ask)), dtype=bool)  # item k, taken alone, frees pair n
            for k, p in enumerate(floor):
                freed[k] = joins_without(nav, p.box(), cells, self._without)
            for m, n in enumerate(ask):
                who_of[kind_of[n]] = tuple(floor[k].name for k in np.nonzero(freed[:, m])[0])
        for n, (a, b) in enumerate(pairs):
            floor_memo.blockers[(a, b)] = who_of[kind_of[n]]
        # failing any single item, every floor item near the pair's path on the static map:
        # an item's being near a path depends on the two alone (the static map's path does not
        # change with the floor), so what was found is kept for the items it was found for
        boxes = [(p.name, p.x, p.y, p.sx, p.sy) for p in floor]  # tuples: C's hashing, not Box's
        index = {b: k for k, b in enumerate(boxes)}
        now = frozenset(boxes)
        alone = [pairs[n] for n, kind in enumerate(kind_of) if not who_of[kind]]
        empty = (frozenset(), ())
        todo = [q for q in alone if not now <= self._near.get((self._out, *q), empty)[0]]
        if todo:
            if len(self._near) > 50_000:
                self._near.clear()
            # each item is near a path or not by itself: only the items a pair was not yet
            # asked about are looked at (before, a pair met with one such item was asked
            # about every floor item again)
            was = [self._near.get((self._out, *q), empty) for q in todo]
            new = sorted(set().union(*(now - checked for checked, _ in was)), key=index.__getitem__)
            rows = self._near_paths(self.grid(self._out), [floor[index[b]] for b in new], todo)
            unions: dict[int, frozenset] = {}  # one set asked per set asked before: shared
            for q, (checked, near), row in zip(todo, was, rows, strict=True):
                found = {new[k] for k in np.nonzero(row)[0] if new[k] not in checked}
                if id(checked) not in unions:
                    unions[id(checked)] = now if checked <= now else checked | now
                self._near[(self._out, *q)] = (unions[id(checked)], tuple(sorted(found.union(near))))
        # kept in name order: a floor in name order (the belief's) gives them as they are.
        # Not an item the robot put aside: it was left where the ways stayed open, and listed it
        # was taken again, the pair still blocked, and put aside again, over and over (one room
        # of 72 items: 22 times, no item delivered)
        aside = {p.name for p in floor if p.aside}
        ordered = all(a[0] < b[0] for a, b in zip(boxes, boxes[1:], strict=False))
        for q in alone:
            near = self._near[(self._out, *q)][1]
            if ordered:
                floor_memo.blockers[q] = tuple(b[0] for b in near if b in now and b[0] not in aside)
            else:
                found = sorted(index[b] for b in near if b in index and b[0] not in aside)
                floor_memo.blockers[q] = tuple(floor[k].name for k in found)

    def _near_paths(self, static: OccupancyGrid, floor: list[Placed], pairs) -> np.ndarray:
        """For each pair (a, b), which floor items stand within the navigation radius + 0.1 m
        of a cell centre on the static map's path a-b (none where there is no path), as a bool
        array (pair, item). A path is its cells; an item is the cells whose centres are that
        near it: one gather over every path's cells of a table of the items' cells, not a
        distance per item and cell of each path (at 96 objects a tenth of the mission's time)."""
        out = np.zeros((len(pairs), len(floor)), dtype=bool)
        if not pairs or not floor:
            return out
        r = self.nav_radius + 0.1
        # the items each cell is near, as bits: 96 items are 12 bytes a cell
        owner = np.zeros((static.shape[0] * static.shape[1], len(floor)), dtype=bool)
        for k, p in enumerate(floor):
            owner[self._disc(static, p.xy, r), k] = True
        bits = np.packbits(owner, axis=1)
        lines = [self._line(static, a, b) for a, b in pairs]
        todo = [n for n, line in enumerate(lines) if len(line)]
        for chunk in _chunks(todo, [len(lines[n]) for n in todo], 200_000):
            cat = np.concatenate([lines[n] for n in chunk])
            starts = np.cumsum([0] + [len(lines[n]) for n in chunk[:-1]])
            hit = np.bitwise_or.reduceat(bits[cat], starts, axis=0)
            out[chunk] = np.unpackbits(hit, axis=1, count=len(floor)).astype(bool)
        return out

    def _disc(self, static: OccupancyGrid, at: Point, r: float) -> np.ndarray:
        """The flat indices of the cells whose centres lie closer than r to ``at`` (the distance
        numpy's hypot gives from ``at`` to the centre, as a path's cells were tested before)."""
        key = (at, r)
        if key not in self._discs:
            if len(self._discs) > 4096:
                self._discs.clear()
            n_i, n_j = static.shape
            i0, j0 = static.cell(at[0] - r, at[1] - r)
            i1, j1 = static.cell(at[0] + r, at[1] + r)
            i0, j0, i1, j1 = max(i0, 0), max(j0, 0), min(i1 + 1, n_i), min(j1 + 1, n_j)
            x0, _x1, y0, _y1 = static.bounds
            xs = x0 + (np.arange(i0, i1) + 0.5) * static.cell_size
            ys = y0 + (np.arange(j0, j1) + 0.5) * static.cell_size
            ii, jj = np.nonzero(np.hypot(at[0] - xs[:, None], at[1] - ys[None, :]) < r)
            self._discs[key] = (ii + i0) * n_j + (jj + j0)
        return self._discs[key]

    def _line(self, static: OccupancyGrid, a: Point, b: Point) -> np.ndarray:
        """The static map's path a-b as its cells' flat indices (empty: none), remembered: the
        furniture and the open drawers change seldom, the floor items every few actions."""
        key = (self._out, a, b)
        if key not in self._lines:
            if len(self._lines) > 50_000:
                self._lines.clear()
            cells = static.path_cells(a, b)
            self._lines[key] = np.zeros(0, dtype=np.int64) if cells is None else cells.astype(np.int64)
        return self._lines[key]


def free_spots(
    scenario: Scenario, around: Point, occupied: Sequence[Point], radii: tuple[float, float] = (0.45, 0.45)
) -> list[Point]:
    """Floor spots on rings ``radii`` around ``around``: inside the room, clear of furniture, and
    20 cm from every point of ``occupied``. Where an item can be put down (drop_object), or where
    one that slips out of the hand can land."""
    x0, x1, y0, y1 = scenario.bounds
    out = []
    for r in sorted(set(radii)):
        for k in range(16):
            a = 2 * math.pi * k / 16
            p = (round(around[0] + r * math.cos(a), 3), round(around[1] + r * math.sin(a), 3))
            if not (x0 + 0.1 < p[0] < x1 - 0.1 and y0 + 0.1 < p[1] < y1 - 0.1):
                continue
            if any(f.box().clearance(*p) < 0.05 for f in scenario.furniture):
                continue
            if any(math.dist(p, q) < 0.2 for q in occupied):
                continue
            out.append(p)
    return out


def _chunks(todo: list[int], sizes: list[int], most: int) -> Iterator[list[int]]:
    """``todo`` in consecutive runs whose ``sizes`` add up to ``most`` or less (one item at
    least a run): a gather of many paths' cells at once stays a few megabytes."""
    run: list[int] = []
    total = 0
    for n, size in zip(todo, sizes, strict=True):
        if run and total + size > most:
            yield run
            run, total = [], 0
        run.append(n)
        total += size
    if run:
        yield run
