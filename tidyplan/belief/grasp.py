"""Where the robot stands to grasp each item: Yan et al.'s grasp waypoints, chosen on the map.

A pose the navigation grid reaches now wins, nearest to the arm's comfortable reach; else one it
reaches once floor items in the way are cleared (P3's blocked case); else one a short pose
adjustment reaches from a navigable cell (P2's case). ``GraspPoses`` makes the choice for every
item of a floor and keeps, across floors, what each item's choice depends on (the floor items
near it, the poses taken near it, the ring cells the robot reaches, the room beyond): a new
floor chooses again only near what changed. ``tidyplan.belief.geometry.RoomMap`` owns one.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Protocol

import numpy as np

from sim.grid import Box, OccupancyGrid
from tidyplan.belief.mapfacts import MapFacts, Placed, Point, grasp_waypoint

# m from the item: the arm's comfortable reach; the minimum keeps the pose outside the item's own
# inflation (0.27 m + half its 8 cm), so an item never blocks the pose it is grasped from
GRASP_MIN, GRASP_BEST, GRASP_MAX = 0.35, 0.45, 0.65
ADJUST_MAX = 0.60  # m: the longest pose adjustment, a short careful omnidirectional move


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
        self._bare_cells: tuple[list[Point], np.ndarray] | None = None  # for _ring
        self._rings: dict[Point, list[Point]] = {}  # _ring's answers, by item position
        self._pairs: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}  # _pair's answers
        self._crossings: dict[tuple, _Blockers] = {}  # _crossing's answers, by item and floor near it
        self._poses: dict[tuple, MapFacts | object] = {}  # one item's grasp facts, by what they depend on
        self._windows: dict[Point, np.ndarray] = {}  # _beyond_reach's cells around an item (flat)
        self._ring_arrays: dict[Point, np.ndarray] = {}  # _ring's cells as an (n, 2) array
        self._ruled: dict[tuple[Point, Point], np.ndarray] = {}  # _ruled_out's answers
        self._ring_indexes: dict[Point, dict[Point, int]] = {}  # _ring_index's
        self._ring_flat: dict[Point, np.ndarray] = {}  # _ring_cells'
        self._orders: dict[Point, np.ndarray] = {}  # _order's

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
        reachable = _Reach(nav, origin)
        chosen = MapFacts()
        # the floor's boxes as arrays: which are near an item, for every item at once (a loop
        # over every pair was a seventh of a turn at 96 objects)
        boxes = np.array([(b.cx, b.cy, b.sx / 2, b.sy / 2) for b in floor], dtype=float).reshape(-1, 4)
        taken = _Taken()
        # the boxes as plain tuples, for the keys below (C's hashing, not a dataclass's)
        box_keys = [box_key(b) for b in floor]
        for p in sorted(items, key=lambda p: p.name):
            bad, previous = (avoid or {}).get(p.name, []), (sticky or {}).get(p.name)
            # the floor items that can cross the reach from a ring cell, stand on one, or
            # take one from the bare footprint: within the reach and the base's radius
            within = _near_boxes(boxes, p.xy, GRASP_MAX + self.room.bare_radius + 0.03)
            blockers = self._crossing(p, [floor[i] for i in within], tuple(box_keys[i] for i in within), bare)
            # The pose depends on the item, the floor items its ring waits for, the poses taken
            # near it, the pose kept and those avoided, which of its ring's cells the robot
            # reaches, and (for one not reached now) the room around it: kept by those, so a new
            # floor chooses again only where what changed matters to the choice (choosing for
            # every item of the room, each new floor, was a third of a 96-object turn; for
            # every item near a change, four in five chose as before)
            # the poses within 0.1 m of a ring cell: the only ones that rule one out
            near_poses = taken.near(p.xy, GRASP_MAX + 0.1 + 1e-6)
            others = tuple(sorted(q for q in near_poses if self._rules_out(p.xy, q)))
            reach = nav.reaches_cells(self._ring_cells(p.xy), origin).tobytes()
            key_p = (p.name, p.xy, blockers.key, out, previous, tuple(bad), others, reach)
            one = self._poses.get(key_p)
            if one is _LATER:  # not reached now: what the tiers beyond look at, too
                key_p = (*key_p, *self._beyond_reach(p, nav, static, boxes, floor))
                one = self._poses.get(key_p)
            if one is None:
                one = MapFacts()
                tier = self._add_grasp(one, p, blockers, nav, static, bare, reachable, previous, bad, taken)
                if len(self._poses) > 16_384:
                    self._poses.clear()
                if tier != 1 and len(key_p) == 8:
                    self._poses[key_p] = _LATER
                    key_p = (*key_p, *self._beyond_reach(p, nav, static, boxes, floor))
                self._poses[key_p] = one
                # the belief keeps the pose chosen (its sticky one) and asks again: a pose kept
                # is chosen again where its tier finds it, so the answer is the same
                pose = one.points.get(grasp_waypoint(p.name))
                if pose is not None and pose != previous:
                    if tier != 1:
                        self._poses[(*key_p[:4], pose, *key_p[5:8])] = _LATER
                    self._poses[(*key_p[:4], pose, *key_p[5:])] = one
            chosen.add_poses(one)
            for q in one.points.values():
                taken.add(q)
        return chosen

    def _add_grasp(
        self,
        facts: MapFacts,
        p: Placed,
        blockers: _Blockers,
        nav: OccupancyGrid,
        static: OccupancyGrid,
        bare: OccupancyGrid,
        reachable: _Reach,
        previous: Point | None,
        avoid: list[Point],
        taken: _Taken,
    ) -> int:
        """Choose where the robot stands to grasp ``p``: a pose the navigation grid reaches now,
        else one it reaches once floor items are cleared (blocked), else one a pose adjustment
        reaches from a navigable cell (tight). Nearest to the comfortable reach wins each tier
        (then fewest items waited for, then the cell). ``taken``: the grasp and adjustment
        poses chosen so far; ``blockers``: what each ring cell waits for (``_crossing``).
        Returns the tier: 1 now, 2 blocked, 3 tight, 0 none (unreachable).
        The ring is worked on as arrays over its cells (by index), a tier's choice one argmin
        over the cells' ranks (a list per cell was most of a choice at 96 objects)."""
        ring, xy = self._ring(p.xy), self._ring_array(p.xy)
        # poses taken by other waypoints (only those within reach of a ring cell can be within
        # 0.1 m of one), and those from which the robot failed to find p before
        kept = _apart(xy, list(avoid), 0.15)
        for q in taken.near(p.xy, GRASP_MAX + 0.1 + 1e-6):
            kept[self._ruled_out(p.xy, q)] = False
        waits = blockers.count
        candidates = kept & (waits == 0)
        # a cell's rank: the items it waits for, then its place in the ring's order
        rank = waits * len(ring) + self._order(p.xy)
        name = grasp_waypoint(p.name)
        before = self._ring_index(p.xy).get(previous) if previous is not None else None
        now = candidates & reachable.mask(xy)
        if now.any():
            k = before if before is not None and now[before] else _best(now, rank)
            facts.points[name], facts.kind[name] = ring[k], "grasp"
            facts.grasp[p.name] = name
            return 1
        # reached once other floor items are cleared; never a pose only ``p`` itself shuts off:
        # its paths would be blocked by the item to be taken from there (no plan could start)
        own = self.room.grid([p.box(), *self._out]) if p.on_floor else static
        start = self._origin if own.free(*self._origin) else self.room.entrance
        later = kept & own.reaches(xy, start)
        if later.any():
            k = before if before is not None and later[before] else _best(later, rank)
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

    def _crossing(self, p: Placed, floor: list[Box], floor_key: tuple, bare: OccupancyGrid) -> _Blockers:
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
        others_floor = [b for b in floor if b.name != p.name and b.clearance(*p.xy) <= GRASP_MAX + 0.5]
        # (``floor``: the floor items numpy found near p, in order; the exact test is this one)
        # What crosses the ring depends on p and each floor item near it, one pair at a time:
        # remembered per pair, so a floor with one item more or less costs that item's pairs
        # only (per whole neighbourhood, every neighbour of a taken item computed its ring again)
        ring = self._ring(p.xy)
        free = bare.free_at(self._ring_array(p.xy))
        hit = _Blockers(len(ring))
        for b in others_floor:
            cross_at, under_at = self._pair(p, b, ring)
            hit.add(b.name, cross_at, under_at[~free[under_at]])
        if len(self._crossings) > 4096:  # a mission's items, where they were seen, their floors
            self._crossings.clear()
        self._crossings[key] = hit
        return hit

    def _beyond_reach(self, p: Placed, nav, static, boxes: np.ndarray, floor: list[Box]) -> tuple:
        """What a grasp pose not reached now depends on beyond ``_poses``' first key: the part
        of the room with only ``p`` on the floor that the robot is in (blocked poses), the floor
        items and the cells the robot reaches within a pose adjustment of the ring (tight ones)."""
        own = self.room.grid([p.box(), *self._out]) if p.on_floor else static
        room = own.component(*(self._origin if own.free(*self._origin) else self.room.entrance))
        r = GRASP_MAX + ADJUST_MAX + 0.1
        wider = tuple(box_key(floor[i]) for i in _near_boxes(boxes, p.xy, r + self.room.bare_radius + 0.1))
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
        return room, wider, nav.reaches_cells(window, self._origin).tobytes()

    def _ring_cells(self, at: Point) -> np.ndarray:
        """The ring's cells as flat indices of the room's grids (all share bounds and cells)."""
        hit = self._ring_flat.get(at)
        if hit is None:
            if len(self._ring_flat) > 4096:
                self._ring_flat.clear()
            static = self.room.grid(())
            cells = [static.cell(*c) for c in self._ring(at)]
            hit = self._ring_flat[at] = np.array([i * static.shape[1] + j for i, j in cells], dtype=np.int64)
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
        """The cells of ``at``'s ring (indices) within 0.1 m of pose ``q`` (``_apart``'s verdict),
        kept: both are cell centres, met again on every floor."""
        key = (at, q)
        hit = self._ruled.get(key)
        if hit is None:
            if len(self._ruled) > 65_536:
                self._ruled.clear()
            hit = self._ruled[key] = np.nonzero(~_apart(self._ring_array(at), [q], 0.1))[0]
        return hit

    def _order(self, at: Point) -> np.ndarray:
        """Each ring cell's place when the ring is sorted nearest to the arm's comfortable reach
        first, then by cell (math.dist's distances, so ties fall as they always did)."""
        hit = self._orders.get(at)
        if hit is None:
            if len(self._orders) > 4096:
                self._orders.clear()
            ring = self._ring(at)
            by = sorted(range(len(ring)), key=lambda k: (abs(math.dist(ring[k], at) - GRASP_BEST), ring[k]))
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
        cell order: one array test, not a loop over the room's ten thousand cells per item."""
        if at in self._rings:
            return self._rings[at]
        if self._bare_cells is None:
            cells = self.room.grid((), bare=True).free_cells()
            self._bare_cells = (cells, np.array(cells, dtype=float).reshape(-1, 2))
        cells, xy = self._bare_cells
        d = np.hypot(xy[:, 0] - at[0], xy[:, 1] - at[1])
        # the same float test as math.dist, so a cell on the ring's edge stays in or out as before
        near = np.nonzero((d >= GRASP_MIN - 1e-9) & (d <= GRASP_MAX + 1e-9))[0]
        if len(self._rings) > 4096:  # a mission's items and where they were seen
            self._rings.clear()
        self._rings[at] = [c for c in (cells[k] for k in near) if GRASP_MIN <= math.dist(c, at) <= GRASP_MAX]
        return self._rings[at]

    def _pair(self, p: Placed, b: Box, ring: list[Point]) -> tuple[np.ndarray, np.ndarray]:
        """The cells of ``p``'s ring (their indices) from which the arm's reach to ``p`` passes
        over floor item ``b``, and those ``b`` stands on (within the bare footprint's radius):
        indices, not a flag per cell, since most of a ring's ~380 cells touch no given item."""
        key = (p.xy, b)
        hit = self._pairs.get(key)
        if hit is None:
            xy = self._ring_array(p.xy)
            # _crosses' own first test, for the whole ring at once: segments apart from b's
            # footprint along x or y cannot cross it
            hx, hy = b.sx / 2, b.sy / 2
            apart = (
                (np.maximum(xy[:, 0], p.x) < b.cx - hx)
                | (np.minimum(xy[:, 0], p.x) > b.cx + hx)
                | (np.maximum(xy[:, 1], p.y) < b.cy - hy)
                | (np.minimum(xy[:, 1], p.y) > b.cy + hy)
            )
            cross = np.array(_crossing_cells(ring, np.nonzero(~apart)[0], p.xy, b), dtype=np.int64)
            # the cells b stands on: numpy decides the clear cases, Box.clearance those within
            # 1e-9 m of the radius (its verdict is the rule, as in the grids' masks)
            d = np.hypot(
                np.maximum(np.abs(xy[:, 0] - b.cx) - b.sx / 2, 0.0),
                np.maximum(np.abs(xy[:, 1] - b.cy) - b.sy / 2, 0.0),
            )
            r = self.room.bare_radius
            under = np.array(
                [k for k in np.nonzero(d < r + 1e-9)[0] if d[k] < r - 1e-9 or b.clearance(*ring[k]) < r],
                dtype=np.int64,
            )
            if len(self._pairs) > 65_536:  # pairs of items near each other, over a mission
                self._pairs.clear()
            hit = self._pairs[key] = (cross, under)
        return hit


_LATER = object()  # in GraspPoses._poses: not reached now, the wider key decides


class _Blockers:
    """The floor items a grasp from each cell of a ring waits for: their count per cell (an
    array, read for every cell) and their names (asked for the chosen cell only: building a
    list per cell was a fifth of choosing a pose)."""

    def __init__(self, cells: int) -> None:
        self.count = np.zeros(cells, dtype=np.int64)
        self._by: list[tuple[str, np.ndarray, np.ndarray]] = []  # (item, cells crossed, stood on)
        self._key: tuple | None = None  # key's, once asked (no add after)

    def add(self, name: str, crosses: np.ndarray, under: np.ndarray) -> None:
        """Floor item ``name`` crosses the reach from ``crosses`` and stands on ``under``."""
        if len(crosses) or len(under):
            self.count[crosses] += 1
            self.count[under] += 1
            self._by.append((name, crosses, under))

    @property
    def key(self) -> tuple:
        """What the cells wait for, as a key: the same key, the same counts and names."""
        if self._key is None:
            self._key = tuple((n, c.tobytes(), u.tobytes()) for n, c, u in self._by)
        return self._key

    def names(self, k: int) -> tuple[str, ...]:
        """The items cell ``k`` waits for: those crossing its reach, then those standing on it,
        each in the floor's order."""
        return tuple(n for n, c, _ in self._by if k in c) + tuple(n for n, _, u in self._by if k in u)


class _Reach:
    """The cell centres the robot reaches from ``origin`` (``free_cells(reachable_from=origin)``
    as a set), asked one at a time: a cell's component, not the component's list."""

    def __init__(self, nav: OccupancyGrid, origin: Point) -> None:
        self._nav, self._origin, self._label = nav, origin, nav.component(*origin)

    def __contains__(self, c: Point) -> bool:
        return self._label != 0 and self._nav.component(*c) == self._label

    def mask(self, points: np.ndarray) -> np.ndarray:
        """``__contains__`` for each of ``points`` ((n, 2)) at once."""
        if self._label == 0:
            return np.zeros(len(points), dtype=bool)
        return self._nav.reaches(points, self._origin)


class _Taken:
    """The grasp and adjustment poses chosen so far in one ``facts``, by 1 m square: which lie
    near an item is a look at the squares around it, not at every pose of the room."""

    def __init__(self) -> None:
        self._squares: dict[tuple[int, int], list[Point]] = {}

    def add(self, q: Point) -> None:
        self._squares.setdefault((math.floor(q[0]), math.floor(q[1])), []).append(q)

    def near(self, at: Point, r: float) -> list[Point]:
        """The poses within ``r`` of ``at`` (and maybe a few more: the squares' corners)."""
        out = []
        for i in range(math.floor(at[0] - r), math.floor(at[0] + r) + 1):
            for j in range(math.floor(at[1] - r), math.floor(at[1] + r) + 1):
                out += self._squares.get((i, j), ())
        return out


def _best(cells: np.ndarray, rank: np.ndarray) -> int:
    """The index of the best-ranked (lowest) of the ``cells`` marked True (some are)."""
    return int(np.argmin(np.where(cells, rank, np.iinfo(np.int64).max)))


def _near_boxes(boxes: np.ndarray, xy: Point, within: float) -> np.ndarray:
    """Indices, in order, of the boxes (cx, cy, half sx, half sy) that may lie within ``within``
    of ``xy``: a superset of ``Box.clearance``'s verdict (1e-9 m to spare), which decides."""
    if not len(boxes):
        return np.zeros(0, dtype=int)
    dx = np.maximum(np.abs(xy[0] - boxes[:, 0]) - boxes[:, 2], 0.0)
    dy = np.maximum(np.abs(xy[1] - boxes[:, 1]) - boxes[:, 3], 0.0)
    return np.nonzero(np.hypot(dx, dy) <= within + 1e-9)[0]


def _apart(cells, points: list[Point], gap: float, axis: int = 1) -> np.ndarray:
    """Which of ``cells`` are at least ``gap`` from every one of ``points`` (``axis`` 0: which of
    ``points`` are at least ``gap`` from every cell): math.dist's verdict (numpy decides the
    clear cases, math.dist those within 1e-9 m of the gap, as in _ring)."""
    if not len(cells) or not len(points):
        return np.ones(len(cells) if axis == 1 else len(points), dtype=bool)
    c, q = np.asarray(cells, dtype=float), np.asarray(points, dtype=float)
    d = np.hypot(c[:, None, 0] - q[None, :, 0], c[:, None, 1] - q[None, :, 1])
    keep = (d >= gap + 1e-9).all(axis=axis)
    for k in np.nonzero(~keep & (d >= gap - 1e-9).all(axis=axis))[0]:
        if axis == 1:
            keep[k] = all(math.dist(tuple(c[k]), tuple(x)) >= gap for x in q)
        else:
            keep[k] = all(math.dist(tuple(x), tuple(q[k])) >= gap for x in c)
    return keep


def straight(grid: OccupancyGrid, a: Point, b: Point, step: float = 0.05) -> bool:
    """Whether the straight segment a-b runs over free cells only (sampled every ``step``)."""
    n = max(1, math.ceil(math.dist(a, b) / step))
    return all(grid.free(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) for k in range(n + 1))


def _crossing_cells(ring: list[Point], cells: np.ndarray, at: Point, box: Box) -> tuple[int, ...]:
    """Of ``cells`` (indices into ``ring``), those whose segment to ``at`` passes over the box:
    ``_crosses``' samples for all of them at once (the same sums in the same order, so the
    same points; a sample is on the footprint when neither of its distances along x and y
    from the box's sides is positive, which is ``Box.clearance(...) == 0``)."""
    if not len(cells):
        return ()
    a = np.array([ring[k] for k in cells], dtype=float)
    n = np.array([max(2, int(math.dist(ring[k], at) / 0.02)) for k in cells], dtype=np.int64)
    counts = n + 1
    starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
    j = (np.arange(int(counts.sum())) - np.repeat(starts, counts)).astype(float)
    ax, ay, nn = np.repeat(a[:, 0], counts), np.repeat(a[:, 1], counts), np.repeat(n, counts).astype(float)
    x = ax + (at[0] - ax) * j / nn
    y = ay + (at[1] - ay) * j / nn
    on = (np.abs(x - box.cx) - box.sx / 2 <= 0.0) & (np.abs(y - box.cy) - box.sy / 2 <= 0.0)
    hit = np.logical_or.reduceat(on, starts)
    return tuple(int(k) for k, h in zip(cells, hit, strict=True) if h)


def _crosses(a: Point, b: Point, box: Box) -> bool:
    """Whether segment a-b passes over the box's footprint (sampled every 2 cm)."""
    hx, hy = box.sx / 2, box.sy / 2
    if (
        max(a[0], b[0]) < box.cx - hx
        or min(a[0], b[0]) > box.cx + hx
        or max(a[1], b[1]) < box.cy - hy
        or min(a[1], b[1]) > box.cy + hy
    ):
        return False  # apart: no sample can fall on it (most boxes near an item, most segments)
    n = max(2, int(math.dist(a, b) / 0.02))
    return any(
        box.clearance(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) == 0.0 for k in range(n + 1)
    )


def box_key(b: Box) -> tuple:
    """A box as a plain tuple: for sorting, and for keys (C's hashing, not a dataclass's)."""
    return (b.cx, b.cy, b.sx, b.sy, b.name)
