"""Where the robot stands to grasp each item: Yan et al.'s grasp waypoints, chosen on the map.

A pose the navigation grid reaches now wins, nearest to the arm's comfortable reach; else one it
reaches once floor items in the way are cleared (P3's blocked case); else one a short pose
adjustment reaches from a navigable cell (P2's case). ``GraspPoses`` makes the choice for every
item of a floor and keeps, across floors, what each item's choice depends on (the floor items
its ring waits for, the poses taken near it, the ring cells the robot reaches, the room beyond),
and the last choice: an item near which nothing changed keeps its answer without a key, so a
new floor costs the items near what changed. The ring's arithmetic is ``tidyplan.belief.ring``'s;
``tidyplan.belief.geometry.RoomMap`` owns a ``GraspPoses``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from functools import cache
from typing import NamedTuple, Protocol

import numpy as np

from sim.grid import Box, OccupancyGrid
from tidyplan.belief.mapfacts import MapFacts, Placed, Point, grasp_waypoint
from tidyplan.belief.ring import (
    Blockers,
    Reach,
    Taken,
    Watched,
    apart,
    best,
    box_key,
    crossing_cells,
    near_boxes,
    straight,
)

# m from the item: the arm's comfortable reach; the minimum keeps the pose outside the item's own
# inflation (0.27 m + half its 8 cm), so an item never blocks the pose it is grasped from
GRASP_MIN, GRASP_BEST, GRASP_MAX = 0.35, 0.45, 0.65
ADJUST_MAX = 0.60  # m: the longest pose adjustment, a short careful omnidirectional move
TAKEN_NEAR = GRASP_MAX + 0.1 + 1e-6  # m: a pose farther from an item is 0.1 m from all its ring
AROUND = GRASP_MAX + ADJUST_MAX + 0.1  # m: the half side of the window a tight pose is sought in


class Map(Protocol):
    """What the choice needs of the map it is made on (``tidyplan.belief.geometry.RoomMap``)."""

    entrance: Point
    bare_radius: float

    def grid(self, floor: Iterable[Box], *, bare: bool = False) -> OccupancyGrid: ...


class GraspPoses:
    """Each item's grasp pose on a floor (``choose``), with what the choices depend on kept."""

    def __init__(self, room: Map) -> None:
        self.room = room
        self._out: tuple[Box, ...] = ()  # the open drawers' boxes, set by choose()
        self._origin: Point = room.entrance  # where the robot reaches from, set by choose()
        self._bare: OccupancyGrid | None = None  # the bare map without floor items, for _ring
        self._rings: dict[Point, list[Point]] = {}  # _ring's answers, by item position
        self._pairs: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}  # _pair's answers
        self._crossings: dict[tuple, Blockers] = {}  # _crossing's answers, by item and floor near it
        self._poses: dict[tuple, MapFacts | object] = {}  # one item's grasp facts, by what they depend on
        self._windows: dict[Point, np.ndarray] = {}  # _around's cells around an item (flat)
        self._ring_arrays: dict[Point, np.ndarray] = {}  # _ring's cells as an (n, 2) array
        self._ruled: dict[tuple[Point, Point], np.ndarray] = {}  # _ruled_out's answers
        self._ring_indexes: dict[Point, dict[Point, int]] = {}  # _ring_index's
        self._ring_flat: dict[Point, np.ndarray] = {}  # _ring_cells'
        self._orders: dict[Point, np.ndarray] = {}  # _order's
        self._last: _Last | None = None  # the last choice, what it was made on and its answers

    def choose(
        self,
        items,
        floor: list[Box],
        nav: OccupancyGrid,
        static: OccupancyGrid,
        bare: OccupancyGrid,
        sticky: dict[str, Point],
        avoid: dict[str, list[Point]],
        out: tuple[Box, ...],
        origin: Point,
    ) -> MapFacts:
        """Every item's grasp pose (and adjustment, or the items its reach waits for), items in
        name order: a pose chosen is taken for the items after it. ``sticky``: poses chosen
        before, kept where still usable; ``avoid``: poses to stay away from, by item."""
        self._out, self._origin = out, origin
        reachable = Reach(nav, origin)
        chosen = MapFacts()
        # the floor's boxes as arrays: which are near an item, for every item at once (a loop
        # over every pair was a seventh of a turn at 96 objects)
        boxes = np.array([(b.cx, b.cy, b.sx / 2, b.sy / 2) for b in floor], dtype=float).reshape(-1, 4)
        taken = Taken()
        # the boxes as plain tuples, for the keys below (C's hashing, not a dataclass's)
        box_keys = [box_key(b) for b in floor]
        items = sorted(items, key=lambda p: p.name)
        # An item whose floor near it, ring reach, kept and avoided poses, poses taken near it,
        # (if not reached now) part of the room and (if no pose reached) the room around its
        # ring are as at the last choice keeps its answer without a key: only the items near
        # what changed are looked at (a key for every item of the room, each new floor, was a
        # third of the choice at 96 objects).
        # "Near" is what the key reads: a floor item over the ring, a pose within 0.1 m of it.
        reach = nav.reaches_cells(np.arange(nav.shape[0] * nav.shape[1]), origin)
        last = self._last.answers if self._last is not None else {}

        @cache
        def held(i: int) -> int | None:  # asked of the items near a change only
            return self._held(last.get(items[i].name), items[i], (sticky or {}).get(items[i].name))

        stale = self._stale(items, set(box_keys), out, reach, nav, held)
        # the poses of the items whose answer changed, before and after
        moved = Watched(np.array([p.xy for p in items], dtype=float).reshape(-1, 2), TAKEN_NEAR)
        for name in last.keys() - {p.name for p in items}:
            for q in last[name].facts.points.values():
                moved.add(q)
        answers: dict[str, _Answer] = {}
        for i, p in enumerate(items):
            bad, previous = tuple((avoid or {}).get(p.name, ())), (sticky or {}).get(p.name)
            was = last.get(p.name)
            if (
                was is not None
                and not stale[i]
                and (was.item, was.avoided) == (p, bad)
                and (was.kept == previous or held(i) is not None)
                and not (moved.hit[i] and self._moved_near(p, was.level, held(i), moved, reach))
                and (was.level == 1 or self._room_of(p, static) == was.room)
            ):
                answer = was if was.kept == previous else was._replace(kept=previous)
            else:
                answer = self._keyed(
                    p, floor, box_keys, boxes, nav, static, bare, reachable, previous, bad, taken
                )
                if was is None or was.facts.points != answer.facts.points:
                    for q in (*(was.facts.points.values() if was else ()), *answer.facts.points.values()):
                        moved.add(q)
            answers[p.name] = answer
            chosen.add_poses(answer.facts)
            for q in answer.facts.points.values():
                taken.add(q)
        self._last = _Last(set(box_keys), out, reach, answers)
        return chosen

    def _keyed(
        self, p, floor, box_keys, boxes, nav, static, bare, reachable, previous, bad, taken
    ) -> _Answer:
        """``p``'s grasp facts by what they depend on (chosen anew only for a key not met before),
        and what beyond the ring they depend on (``_Answer.level``)."""
        # the floor items that can cross the reach from a ring cell, stand on one, or
        # take one from the bare footprint: within the reach and the base's radius
        within = near_boxes(boxes, p.xy, GRASP_MAX + self.room.bare_radius + 0.03)
        blockers = self._crossing(p, [floor[i] for i in within], tuple(box_keys[i] for i in within), bare)
        # The pose depends on the item, the floor items its ring waits for, the poses taken
        # near it, the pose kept and those avoided, which of its ring's cells the robot
        # reaches, and (for one not reached now) the room around it: kept by those, so a new
        # floor chooses again only where what changed matters to the choice (for every item
        # near a change, four in five chose as before)
        # the poses within 0.1 m of a ring cell: the only ones that rule one out
        near_poses = taken.near(p.xy, TAKEN_NEAR)
        others = tuple(sorted(q for q in near_poses if self._rules_out(p.xy, q)))
        reach = reachable.cells(self._ring_cells(p.xy))
        key = (p.name, p.xy, blockers.key, self._out, previous, tuple(bad), others, reach)
        one, room = self._poses.get(key), None
        if one is _LATER:  # not reached now: reached once others are cleared, from the robot?
            room = self._room_of(p, static)
            key = (*key, room)
            one = self._poses.get(key)
            if one is _LATER:  # not even then: the room around it, for a pose adjustment
                key = (*key, *self._around(p, nav, boxes, floor))
                one = self._poses.get(key)
        if one is None:
            one = MapFacts()
            tier = self._add_grasp(one, p, blockers, nav, static, bare, reachable, previous, bad, others)
            if len(self._poses) > 16_384:
                self._poses.clear()
            beyond = []  # what the key holds beyond its first part, by tier
            if tier != 1:
                room = self._room_of(p, static) if room is None else room
                beyond.append((room,))
            if tier in (0, 3):
                beyond.append(self._around(p, nav, boxes, floor))
            # the belief keeps the pose chosen (its sticky one) and asks again: a pose kept
            # is chosen again where its tier finds it, so the answer is the same
            pose = one.points.get(grasp_waypoint(p.name))
            firsts = [key[:8]] if pose is None or pose == previous else [key[:8], (*key[:4], pose, *key[5:8])]
            for k in firsts:
                for part in beyond:
                    self._poses[k] = _LATER
                    k = (*k, *part)
                self._poses[k] = one
            return _Answer(p, previous, tuple(bad), one, 1 + len(beyond), room)
        # found: its key's length says how far beyond the ring it looked
        return _Answer(p, previous, tuple(bad), one, 1 if len(key) == 8 else 2 if len(key) == 9 else 3, room)

    def _held(self, was: _Answer | None, p: Placed, previous: Point | None) -> int | None:
        """Where ``p``'s last answer was a pose reached now or once others are cleared (level 1
        or 2) and is the pose kept now: that pose's cell of the ring (else None). A kept pose
        still usable is the one chosen again (``_add_grasp``), so for such an answer only a
        change that can make it unusable, or (level 2) free a cell of the ring, matters."""
        if was is None or was.level not in (1, 2) or previous is None or was.item != p:
            return None
        if was.facts.points.get(grasp_waypoint(p.name)) != previous:
            return None
        return self._ring_index(p.xy).get(previous)

    def _moved_near(self, p: Placed, level: int, k: int | None, moved: Taken, reach: np.ndarray) -> bool:
        """Whether a pose that changed since the last choice may change ``p``'s: one within
        0.1 m of a cell of its ring; for a pose kept, of the kept pose's cell (a pose gone frees
        cells, and the kept one is taken while usable) or, for one reached once others are
        cleared, of a cell reached now (freed, it may be a pose reached now: ``_freed``)."""
        near = moved.near(p.xy, TAKEN_NEAR)
        if k is not None and level == 1:
            return any(k in self._ruled_out(p.xy, q) for q in near)
        if k is not None and level == 2:
            return any(self._freed(p, k, self._ruled_out(p.xy, q), reach) for q in near)
        return any(self._rules_out(p.xy, q) for q in near)

    def _freed(self, p: Placed, k: int, cells: np.ndarray, reach: np.ndarray) -> bool:
        """For a pose reached once others are cleared and kept (cell ``k`` of ``p``'s ring):
        whether a change at these ring cells may change the answer. The kept pose stays while
        the robot reaches it with only ``p`` on the floor, which no floor item or other pose
        changes; so only a change at its own cell (what it waits for, whether it is ruled out)
        matters, or at a cell the robot reaches now (no longer waiting or ruled out, it would
        be a pose reached now, which wins). A cell reached now that was not, ``_stale``'s reach
        test sees."""
        if not len(cells):
            return False
        return bool(k in cells or reach[self._ring_cells(p.xy)[cells]].any())

    def _stale(
        self,
        items: list[Placed],
        floor: set,
        out: tuple,
        reach: np.ndarray,
        nav: OccupancyGrid,
        held: Callable[[int], int | None],
    ):
        """For each item, whether something its pose (if reached now) depends on may have
        changed since the last choice: a floor item come or gone that crosses a reach from its
        ring or stands on a cell of it, a cell of its ring reached then and not now or the other
        way. For an answer that is the pose kept (``held``: its cell), less: a floor item come
        matters only over that cell (elsewhere it only takes cells away, and the kept pose is
        taken while usable); one gone, not for a pose reached now, and for one reached once
        others are cleared only over that cell or a cell reached now (``_freed``); a cell no
        longer reached, only that one; a cell reached now that was not, for a pose reached now
        not at all.
        (The item itself, its kept and avoided poses and the poses taken near it, ``choose``
        compares.)"""
        if self._last is None or self._last.out != out or self._last.reach.shape != reach.shape:
            return np.ones(len(items), dtype=bool)
        xy = np.array([p.xy for p in items], dtype=float).reshape(-1, 2)
        stale = np.zeros(len(items), dtype=bool)
        keys = sorted(floor ^ self._last.floor)
        changed = np.array([(b[0], b[1], b[2] / 2, b[3] / 2) for b in keys], dtype=float)
        if len(changed):  # near_boxes' test, for every item and changed box at once
            dx = np.maximum(np.abs(xy[:, None, 0] - changed[None, :, 0]) - changed[None, :, 2], 0.0)
            dy = np.maximum(np.abs(xy[:, None, 1] - changed[None, :, 1]) - changed[None, :, 3], 0.0)
            d = np.hypot(dx, dy)
            near = d <= GRASP_MAX + self.room.bare_radius + 0.03 + 1e-9
            # one that neither crosses a reach from the ring nor stands on a cell of it (where
            # the bare grid has it cover the cell: the same test) changes nothing of the choice
            for i, j in zip(*np.nonzero(near), strict=True):
                p = items[i]
                if not stale[i] and keys[j][4] != p.name:
                    cross, under = self._pair(p, keys[j])
                    k = held(i)
                    if k is None:
                        stale[i] = bool(len(cross) or len(under))
                    elif keys[j] in floor:  # come since: over the kept pose's cell?
                        stale[i] = bool(k in cross or k in under)
                    elif self._last.answers[p.name].level == 2:  # gone: the cells it freed
                        stale[i] = self._freed(p, k, np.union1d(cross, under), reach)
        # an answer that reached no pose (level 3) reads the room around its ring too
        # (``_around``): a floor item come or gone near it, or a cell of its window flipped
        wide = np.array([getattr(self._last.answers.get(p.name), "level", 0) == 3 for p in items], bool)
        if len(changed) and wide.any():
            stale |= wide & (d <= self._wider() + 1e-9).any(axis=1)
        flipped = (reach != self._last.reach).reshape(nav.shape)
        if flipped.any():  # the flipped cells in each ring's square (a cell to spare), summed
            sums = np.zeros((nav.shape[0] + 1, nav.shape[1] + 1), dtype=np.int64)
            sums[1:, 1:] = flipped.cumsum(axis=0).cumsum(axis=1)
            x0, _x1, y0, _y1 = nav.bounds

            def flips(r: float, lo: int, hi: int) -> np.ndarray:
                """Whether each item's square, its cells at -r less ``lo`` to +r plus ``hi``
                (exclusive), clipped to the grid, holds a flipped cell."""
                ij = [
                    np.clip(np.floor((xy[:, a] + s - o) / nav.cell_size).astype(int) + k, 0, nav.shape[a])
                    for a, o in ((0, x0), (1, y0))
                    for s, k in ((-r, -lo), (r, hi))
                ]
                i0, i1, j0, j1 = ij[0], np.maximum(ij[1], ij[0]), ij[2], np.maximum(ij[3], ij[2])
                return (sums[i1, j1] - sums[i0, j1] - sums[i1, j0] + sums[i0, j0]) > 0

            square = flips(GRASP_MAX, 1, 2)
            # of those with one in the square, those with one on the ring (what the key reads)
            flat = flipped.ravel()
            for i in np.nonzero(square & ~stale)[0].tolist():
                cells, k = self._ring_cells(items[i].xy), held(i)
                if k is None:
                    stale[i] = bool(flat[cells].any())
                elif self._last.answers[items[i].name].level == 1:  # the kept cell no longer reached
                    stale[i] = bool(flat[cells[k]])
                else:  # a cell reached now that was not
                    stale[i] = bool((flat[cells] & reach[cells]).any())
            stale |= wide & flips(AROUND, 0, 1)  # _around's window
        return stale

    def _add_grasp(
        self,
        facts: MapFacts,
        p: Placed,
        blockers: Blockers,
        nav: OccupancyGrid,
        static: OccupancyGrid,
        bare: OccupancyGrid,
        reachable: Reach,
        previous: Point | None,
        avoid: tuple[Point, ...],
        others: tuple[Point, ...],
    ) -> int:
        """Choose where the robot stands to grasp ``p``: a pose the navigation grid reaches now,
        else one it reaches once floor items are cleared (blocked), else one a pose adjustment
        reaches from a navigable cell (tight). Nearest to the comfortable reach wins each tier
        (then fewest items waited for, then the cell). ``others``: the grasp and adjustment
        poses chosen so far within 0.1 m of a ring cell; ``blockers``: what each ring cell
        waits for (``_crossing``).
        Returns the tier: 1 now, 2 blocked, 3 tight, 0 none (unreachable).
        The ring is worked on as arrays over its cells (by index), a tier's choice one argmin
        over the cells' ranks (a list per cell was most of a choice at 96 objects)."""
        ring, xy = self._ring(p.xy), self._ring_array(p.xy)
        # away from the poses taken by other waypoints and those from which the robot failed to
        # find p before
        kept = apart(xy, list(avoid), 0.15)
        for q in others:
            kept[self._ruled_out(p.xy, q)] = False
        waits = blockers.count
        candidates = kept & (waits == 0)
        # a cell's rank: the items it waits for, then its place in the ring's order
        rank = waits * len(ring) + self._order(p.xy)
        name = grasp_waypoint(p.name)
        before = self._ring_index(p.xy).get(previous) if previous is not None else None
        now = candidates & reachable.mask(xy)
        if now.any():
            k = before if before is not None and now[before] else best(now, rank)
            facts.points[name], facts.kind[name] = ring[k], "grasp"
            facts.grasp[p.name] = name
            return 1
        # reached once other floor items are cleared; never a pose only ``p`` itself shuts off:
        # its paths would be blocked by the item to be taken from there (no plan could start)
        own = self.room.grid([p.box(), *self._out]) if p.on_floor else static
        start = self._origin if own.free(*self._origin) else self.room.entrance
        later = kept & own.reaches(xy, start)
        if later.any():
            k = before if before is not None and later[before] else best(later, rank)
            facts.points[name], facts.kind[name] = ring[k], "grasp"
            facts.grasp[p.name] = name
            if waits[k]:
                facts.reach_blockers[name] = blockers.names(k)
            return 2
        # the best-ranked cell the bare footprint fits on that a pose adjustment reaches
        fits = np.nonzero(candidates & bare.free_at(xy))[0]
        for k in fits[np.argsort(rank[fits], kind="stable")].tolist():
            c = ring[k]
            # a pose adjustment is a short straight move: never through furniture or a wall
            # (the reachable cells near c, from the grid's window around it, not the room's)
            near = nav.free_cells_near(c, ADJUST_MAX, reachable_from=self._origin)
            base = [q for q in near if math.dist(q, c) <= ADJUST_MAX and straight(bare, q, c)]
            if base:
                base = min(base, key=lambda q: (math.dist(q, c), q))
                break
        else:
            facts.unreachable.append(p.name)
            return 0
        facts.points[name], facts.kind[name] = c, "grasp"
        facts.points[name + "-base"], facts.kind[name + "-base"] = base, "adjust"
        facts.grasp[p.name] = name
        d = round(math.dist(base, c), 2)
        facts.adjust[(name + "-base", name)] = facts.adjust[(name, name + "-base")] = d
        return 3

    def _crossing(self, p: Placed, floor: list[Box], floor_key: tuple, bare: OccupancyGrid) -> Blockers:
        """The floor items a grasp of ``p`` from each cell of its ring must wait for: those its
        reach to ``p`` passes over, and those standing on the cell where the bare footprint does
        not fit. It depends on ``p``, the floor items near it (``floor``) and the open drawers
        only, so it is kept by them (``floor_key``: ``floor``'s boxes as ``box_key``s): a new
        floor works out again only the rings near what changed (every ring of the room, each
        new floor, was a third of a 96-object turn)."""
        key = (p.name, p.xy, floor_key, self._out)
        hit = self._crossings.get(key)
        if hit is not None:
            return hit
        # GRASP_MIN keeps poses off the item's own footprint, so the grid with every floor item
        # serves. The arm reaches straight: a floor item in between makes a pose usable only
        # once that item is taken away, like an item lying across a path.
        # A pose where another floor item stands is usable once that item is taken away too: the
        # only poses of an item hemmed in by others (a table side lined with floor items).
        others_floor = [
            (b, k)
            for b, k in zip(floor, floor_key, strict=True)
            if b.name != p.name and b.clearance(*p.xy) <= GRASP_MAX + 0.5
        ]
        # (``floor``: the floor items numpy found near p, in order; the exact test is this one)
        # What crosses the ring depends on p and each floor item near it, one pair at a time:
        # remembered per pair, so a floor with one item more or less costs that item's pairs
        # only (per whole neighbourhood, every neighbour of a taken item computed its ring again)
        ring = self._ring(p.xy)
        free = bare.free_at(self._ring_array(p.xy))
        hit = Blockers(len(ring), [(b.name, *self._pair(p, k, b)) for b, k in others_floor], free)
        if len(self._crossings) > 4096:  # a mission's items, where they were seen, their floors
            self._crossings.clear()
        self._crossings[key] = hit
        return hit

    def _room_of(self, p: Placed, static: OccupancyGrid) -> int:
        """What a grasp pose not reached now depends on beyond ``_poses``' first key: the part of
        the room with only ``p`` on the floor (and the open drawers) the robot is in."""
        own = self.room.grid([p.box(), *self._out]) if p.on_floor else static
        return own.component(*(self._origin if own.free(*self._origin) else self.room.entrance))

    def _around(self, p: Placed, nav: OccupancyGrid, boxes: np.ndarray, floor: list[Box]) -> tuple:
        """What a grasp pose neither reached now nor once others are cleared depends on beyond
        that: the floor items and the cells the robot reaches within a pose adjustment of the
        ring (tight poses)."""
        r = AROUND
        wider = tuple(box_key(floor[i]) for i in near_boxes(boxes, p.xy, self._wider()))
        window = self._windows.get(p.xy)
        if window is None:
            if len(self._windows) > 4096:
                self._windows.clear()
            static_cells = self.room.grid(())
            i0, j0 = static_cells.cell(p.x - r, p.y - r)
            i1, j1 = static_cells.cell(p.x + r, p.y + r)
            # the square's cells inside the grid, as flat indices (those outside reach nothing)
            rows, cols = static_cells.shape
            ii = np.arange(max(i0, 0), min(i1, rows - 1) + 1)
            jj = np.arange(max(j0, 0), min(j1, cols - 1) + 1)
            window = self._windows[p.xy] = (ii[:, None] * cols + jj[None, :]).ravel()
        return wider, nav.reaches_cells(window, self._origin).tobytes()

    def _wider(self) -> float:
        """How near a floor item's footprint must come to an item for ``_around`` to read it:
        within a pose adjustment of the ring, and the base's radius beyond."""
        return AROUND + self.room.bare_radius + 0.1

    def _ring_cells(self, at: Point) -> np.ndarray:
        """The ring's cells as flat indices of the room's grids (all share bounds and cells)."""
        hit = self._ring_flat.get(at)
        if hit is None:
            self._rings.pop(at, None)
            self._ring(at)  # works them out with the ring
            hit = self._ring_flat[at]
        return hit

    def _ring_index(self, at: Point) -> dict[Point, int]:
        """Each ring cell's index in ``_ring(at)``."""
        hit = self._ring_indexes.get(at)
        if hit is None:
            if len(self._ring_indexes) > 4096:
                self._ring_indexes.clear()
            hit = self._ring_indexes[at] = {c: k for k, c in enumerate(self._ring(at))}
        return hit

    def _rules_out(self, at: Point, q: Point) -> bool:
        """Whether pose ``q`` lies within 0.1 m of a cell of ``at``'s ring."""
        return bool(len(self._ruled_out(at, q)))

    def _ruled_out(self, at: Point, q: Point) -> np.ndarray:
        """The cells of ``at``'s ring (indices) within 0.1 m of pose ``q`` (``apart``'s verdict),
        kept: both are cell centres, met again on every floor."""
        key = (at, q)
        hit = self._ruled.get(key)
        if hit is None and not GRASP_MIN - 0.1 - 1e-6 < math.dist(at, q) < TAKEN_NEAR:
            return _NONE  # no ring cell is within 0.1 m of a pose this far out or in
        if hit is None:
            if len(self._ruled) > 65_536:
                self._ruled.clear()
            hit = self._ruled[key] = np.nonzero(~apart(self._ring_array(at), [q], 0.1))[0]
        return hit

    def _order(self, at: Point) -> np.ndarray:
        """Each ring cell's place when the ring is sorted nearest to the arm's comfortable reach
        first, then by cell (math.dist's distances, so ties fall as they always did)."""
        hit = self._orders.get(at)
        if hit is None:
            if len(self._orders) > 4096:
                self._orders.clear()
            ring = self._ring(at)
            xy = self._ring_array(at)
            off = [abs(math.dist(c, at) - GRASP_BEST) for c in ring]
            by = np.lexsort((xy[:, 1], xy[:, 0], np.array(off, dtype=float)))  # off, then x, then y
            hit = self._orders[at] = np.empty(len(ring), dtype=np.int64)
            hit[by] = np.arange(len(ring))
        return hit

    def _ring_array(self, at: Point) -> np.ndarray:
        hit = self._ring_arrays.get(at)
        if hit is None:
            if len(self._ring_arrays) > 4096:
                self._ring_arrays.clear()
            hit = self._ring_arrays[at] = np.array(self._ring(at), dtype=float).reshape(-1, 2)
        return hit

    def _ring(self, at: Point) -> list[Point]:
        """The bare map's free cells within the arm's reach of ``at`` (GRASP_MIN to GRASP_MAX), in
        cell order: one array test over the cells of the square around ``at`` (over the room's
        every free cell, a new item's ring grew with the room)."""
        if at in self._rings:
            return self._rings[at]
        if self._bare is None:
            self._bare = self.room.grid((), bare=True)
        bare, r = self._bare, GRASP_MAX + self._bare.cell_size
        i0, j0 = bare.cell(at[0] - r, at[1] - r)
        i1, j1 = bare.cell(at[0] + r, at[1] + r)
        i0, j0 = max(i0, 0), max(j0, 0)
        ii, jj = np.nonzero(bare.mask[i0 : i1 + 1, j0 : j1 + 1])
        # the cells' centres as OccupancyGrid.xy gives them (the same sums), in cell order
        x0, _x1, y0, _y1 = bare.bounds
        xs, ys = x0 + (ii + i0 + 0.5) * bare.cell_size, y0 + (jj + j0 + 0.5) * bare.cell_size
        d = np.hypot(xs - at[0], ys - at[1])
        # the same float test as math.dist, so a cell on the ring's edge stays in or out as before
        near = np.nonzero((d >= GRASP_MIN - 1e-9) & (d <= GRASP_MAX + 1e-9))[0]
        if len(self._rings) > 4096:  # a mission's items and where they were seen
            self._rings.clear()
            self._ring_flat.clear()
        cells = zip(xs[near].tolist(), ys[near].tolist(), strict=True)
        kept = [k for k, c in enumerate(cells) if GRASP_MIN <= math.dist(c, at) <= GRASP_MAX]
        near = near[kept]
        self._rings[at] = list(zip(xs[near].tolist(), ys[near].tolist(), strict=True))
        # and as flat indices of the room's grids (all share bounds and cells)
        self._ring_flat[at] = (ii[near] + i0) * bare.shape[1] + (jj[near] + j0)
        return self._rings[at]

    def _pair(self, p: Placed, b_key: tuple, b: Box | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The cells of ``p``'s ring (their indices) from which the arm's reach to ``p`` passes
        over floor item ``b``, and those ``b`` stands on (within the bare footprint's radius):
        indices, not a flag per cell, since most of a ring's ~380 cells touch no given item.
        ``b_key``: ``box_key(b)``, the pair's key; ``b`` itself, where the caller has it, else
        made from the key on a miss only (most pairs a new floor asks about are kept)."""
        key = (p.xy, b_key)
        hit = self._pairs.get(key)
        if hit is None:
            b = Box(*b_key) if b is None else b
            ring, xy = self._ring(p.xy), self._ring_array(p.xy)
            # first, for the whole ring at once: a segment wholly beside the footprint along x
            # or y cannot cross it
            hx, hy = b.sx / 2, b.sy / 2
            beside = (
                (np.maximum(xy[:, 0], p.x) < b.cx - hx)
                | (np.minimum(xy[:, 0], p.x) > b.cx + hx)
                | (np.maximum(xy[:, 1], p.y) < b.cy - hy)
                | (np.minimum(xy[:, 1], p.y) > b.cy + hy)
            )
            cross = crossing_cells(xy, np.nonzero(~beside)[0], p.xy, b)
            # the cells b stands on: numpy decides the clear cases, Box.clearance those within
            # 1e-9 m of the radius (its verdict is the rule, as in the grids' masks)
            d = np.hypot(
                np.maximum(np.abs(xy[:, 0] - b.cx) - b.sx / 2, 0.0),
                np.maximum(np.abs(xy[:, 1] - b.cy) - b.sy / 2, 0.0),
            )
            r = self.room.bare_radius
            under = np.nonzero(d < r + 1e-9)[0]
            border = under[d[under] >= r - 1e-9]
            if len(border):
                under = np.setdiff1d(under, [k for k in border.tolist() if b.clearance(*ring[k]) >= r])
            if len(self._pairs) > 65_536:  # pairs of items near each other, over a mission
                self._pairs.clear()
            hit = self._pairs[key] = (cross, under)
        return hit


_NONE = np.zeros(0, dtype=np.int64)  # _ruled_out's answer for a pose far from every ring cell
_LATER = object()  # in GraspPoses._poses: not reached now, the wider key decides


class _Answer(NamedTuple):
    """One item's grasp facts in a choice, and what they were chosen from beyond the floor."""

    item: Placed
    kept: Point | None  # the pose kept from before (sticky)
    avoided: tuple[Point, ...]
    facts: MapFacts
    # reached now (1: the answer depends on the ring's reach alone), once other floor items are
    # cleared (2: and on ``room``, the robot's part of the room with only the item on the floor),
    # or by a pose adjustment or not at all (3: and on the room around the ring)
    level: int
    room: int | None


class _Last(NamedTuple):
    """A choice: the floor it was made on (``box_key``s), the open drawers, the cells the robot
    reached (flat), and each item's answer."""

    floor: set
    out: tuple
    reach: np.ndarray
    answers: dict[str, _Answer]
