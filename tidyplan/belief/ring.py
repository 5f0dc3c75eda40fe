"""The cells around an item a grasp may be made from (its ring), worked on as arrays: what each
cell waits for (``Blockers``), whether the robot reaches it (``Reach``), the poses taken near
it (``Taken``), the floor items near an item, cells apart from poses, a straight short move,
and a reach crossing a footprint (sampled every 2 cm, for many cells at once).
``tidyplan.belief.grasp.GraspPoses`` chooses with them.
"""

from __future__ import annotations

import math

import numpy as np

from sim.grid import Box, OccupancyGrid
from tidyplan.belief.mapfacts import Point


class Blockers:
    """The floor items a grasp from each cell of a ring waits for: their count per cell (an
    array, read for every cell) and their names (asked for the chosen cell only: building a
    list per cell was a fifth of choosing a pose)."""

    def __init__(self, cells: int, by: list[tuple[str, np.ndarray, np.ndarray]], free: np.ndarray) -> None:
        """``by``: each floor item near, the cells its reach crosses and those it stands on (it
        is waited for there only where the bare footprint does not fit: not ``free``)."""
        self._by = [(n, c, u[~free[u]]) for n, c, u in by]
        self._by = [(n, c, u) for n, c, u in self._by if len(c) or len(u)]
        waits = [a for _, c, u in self._by for a in (c, u)]
        self.count = (
            np.bincount(np.concatenate(waits), minlength=cells) if waits else np.zeros(cells, np.int64)
        )
        self._key: tuple | None = None  # key's, once asked

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


class Reach:
    """Which cells the robot reaches from ``origin`` (``free_cells(reachable_from=origin)``'s),
    asked for a ring's at once: their components, not the component's list."""

    def __init__(self, nav: OccupancyGrid, origin: Point) -> None:
        self._nav, self._origin, self._label = nav, origin, nav.component(*origin)

    def cells(self, flat: np.ndarray) -> bytes:
        """Which of the cells (flat indices) the robot reaches, as a key."""
        return self._nav.reaches_cells(flat, self._origin).tobytes()

    def mask(self, points: np.ndarray) -> np.ndarray:
        """Whether the robot reaches each of ``points`` ((n, 2)), at once."""
        if self._label == 0:
            return np.zeros(len(points), dtype=bool)
        return self._nav.reaches(points, self._origin)


class Taken:
    """The grasp and adjustment poses chosen so far in one ``facts``, by 1 m square: which lie
    near an item is a look at the squares around it, not at every pose of the room."""

    def __init__(self) -> None:
        self._squares: dict[tuple[int, int], list[Point]] = {}

    def add(self, q: Point) -> None:
        self._squares.setdefault((math.floor(q[0]), math.floor(q[1])), []).append(q)

    def __bool__(self) -> bool:
        return bool(self._squares)

    def near(self, at: Point, r: float) -> list[Point]:
        """The poses within ``r`` of ``at`` (and maybe a few more: the squares' corners)."""
        out = []
        for i in range(math.floor(at[0] - r), math.floor(at[0] + r) + 1):
            for j in range(math.floor(at[1] - r), math.floor(at[1] + r) + 1):
                out += self._squares.get((i, j), ())
        return out


class Watched(Taken):
    """Poses, as ``Taken`` keeps them, and which of some points (the items, ``at``: (n, 2)) have
    one of them in the squares ``near(point, r)`` looks at: marked as each pose comes, for every
    point at once (``hit``), so a point with none needs no look (a look per item, on every new
    floor, was nearly a fifth of a grasp choice at 96 objects under a line profiler)."""

    def __init__(self, at: np.ndarray, r: float) -> None:
        super().__init__()
        # the squares near() looks at, as it works them out (the same float sums)
        self._lo, self._hi = np.floor(at - r).astype(np.int64), np.floor(at + r).astype(np.int64)
        self.hit = np.zeros(len(at), dtype=bool)

    def add(self, q: Point) -> None:
        super().add(q)
        i, j = math.floor(q[0]), math.floor(q[1])
        lo, hi = self._lo, self._hi
        self.hit |= (lo[:, 0] <= i) & (i <= hi[:, 0]) & (lo[:, 1] <= j) & (j <= hi[:, 1])


def best(cells: np.ndarray, rank: np.ndarray) -> int:
    """The index of the best-ranked (lowest) of the ``cells`` marked True (some are)."""
    return int(np.argmin(np.where(cells, rank, np.iinfo(np.int64).max)))


def near_boxes(boxes: np.ndarray, xy: Point, within: float) -> np.ndarray:
    """Indices, in order, of the boxes (cx, cy, half sx, half sy) that may lie within ``within``
    of ``xy``: a superset of ``Box.clearance``'s verdict (1e-9 m to spare), which decides."""
    if not len(boxes):
        return np.zeros(0, dtype=int)
    dx = np.maximum(np.abs(xy[0] - boxes[:, 0]) - boxes[:, 2], 0.0)
    dy = np.maximum(np.abs(xy[1] - boxes[:, 1]) - boxes[:, 3], 0.0)
    return np.nonzero(np.hypot(dx, dy) <= within + 1e-9)[0]


def apart(cells, points: list[Point], gap: float) -> np.ndarray:
    """Which of ``cells`` are at least ``gap`` from every one of ``points``: math.dist's verdict
    (numpy decides the clear cases, math.dist those within 1e-9 m of the gap, as in _ring)."""
    if not len(cells) or not len(points):
        return np.ones(len(cells), dtype=bool)
    c, q = np.asarray(cells, dtype=float), np.asarray(points, dtype=float)
    d = np.hypot(c[:, None, 0] - q[None, :, 0], c[:, None, 1] - q[None, :, 1])
    keep = (d >= gap + 1e-9).all(axis=1)
    for k in np.nonzero(~keep & (d >= gap - 1e-9).all(axis=1))[0]:
        keep[k] = all(math.dist(tuple(c[k]), tuple(x)) >= gap for x in q)
    return keep


def straight(grid: OccupancyGrid, a: Point, b: Point, step: float = 0.05) -> bool:
    """Whether the straight segment a-b runs over free cells only (sampled every ``step``)."""
    n = max(1, math.ceil(math.dist(a, b) / step))
    return all(grid.free(a[0] + (b[0] - a[0]) * k / n, a[1] + (b[1] - a[1]) * k / n) for k in range(n + 1))


def crossing_cells(ring: np.ndarray, cells: np.ndarray, at: Point, box: Box) -> np.ndarray:
    """Of ``cells`` (indices into ``ring``, an (n, 2) array of cell centres), those whose segment
    to ``at`` passes over the box, sampled every 2 cm (``max(2, int(length / 0.02))`` steps,
    the samples ``a + (at - a) * k / n`` for k = 0..n), all of them at once (the same sums a
    sample at a time makes, so the same points; a sample is on the footprint when neither of its
    distances along x and y from the box's sides is positive, which is
    ``Box.clearance(...) == 0``)."""
    cells = np.asarray(cells, dtype=np.int64)
    if not len(cells):
        return cells
    a = ring[cells]
    # steps per segment from math.dist's length (numpy's where no whole
    # number of 2 cm steps lies within 1e-9 of it, math.dist's where one may)
    steps = np.hypot(a[:, 0] - at[0], a[:, 1] - at[1]) / 0.02
    n = np.floor(steps).astype(np.int64)
    for k in np.nonzero(np.abs(steps - np.round(steps)) < 1e-9)[0].tolist():
        n[k] = int(math.dist(tuple(a[k]), at) / 0.02)
    n = np.maximum(n, 2)
    counts = n + 1
    starts = np.concatenate(([0], np.cumsum(counts)[:-1]))
    j = (np.arange(int(counts.sum())) - np.repeat(starts, counts)).astype(float)
    ax, ay, nn = np.repeat(a[:, 0], counts), np.repeat(a[:, 1], counts), np.repeat(n, counts).astype(float)
    x = ax + (at[0] - ax) * j / nn
    y = ay + (at[1] - ay) * j / nn
    on = (np.abs(x - box.cx) - box.sx / 2 <= 0.0) & (np.abs(y - box.cy) - box.sy / 2 <= 0.0)
    return cells[np.logical_or.reduceat(on, starts)]


def box_key(b: Box) -> tuple:
    """A box as a plain tuple, its fields in order (``Box(*box_key(b)) == b``): for sorting, and
    for keys (C's hashing, not a dataclass's)."""
    return (b.cx, b.cy, b.sx, b.sy, b.name)
