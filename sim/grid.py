"""Occupancy grid and shortest paths on it: the room as the robot's base can drive through it.

Why a grid: move costs the planner sees must be path lengths around furniture, not straight
lines (docs/architecture.md), and navigation later needs the same paths. The grid
knows rooms only as bounds and boxes; which room, which furniture, is the caller's business.

Invariants, relied on by callers that compare runs byte for byte (bench/tidygen.py):
- a cell (i, j) is free when its centre is at least the inflation radius from every wall and
  every obstacle box: the robot is a disc, so inflating the obstacles lets paths treat it as a
  point;
- the graph is 8-connected over free cells, a straight step weighs one cell, a diagonal
  sqrt(2) cells; it is built in one fixed order, so Dijkstra's ties fall the same way each run
  (which of two equally short paths is taken is the search's choice, the same every time);
- every choice among equals (nearest cell) breaks ties by cell index, so results are a
  function of the inputs alone.

Imports: sim.box (the footprints it inflates), sim.carried (the lengths a changed grid keeps).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Iterable, Sequence

import numpy as np
from scipy.ndimage import label as _label_components
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from sim.box import Box
from sim.carried import Known, carried

CELL = 0.05  # m: 5 cm resolves the ~0.2 m gaps between WRS items and keeps the graph small
# The robot as a disc: half the HSR's footprint of about 0.43 m across (docs/sources.md; a
# quoted figure, not confirmed), so a cell is free when the whole base fits around its centre.
ROBOT_RADIUS = 0.22
# Sources whose trees and lengths a grid keeps, the longest unasked forgotten first: a mission
# asks from its waypoints again and again and from the robot's pose once a step. In the 96-object
# two-room mission one source was asked again after 96 others and none after 128; in a 30-object
# Task 1 room none after 64. Up to 512 were kept, then all dropped: a long mission's memory grew
# towards that (bench/soak.py).
SOURCES_KEPT = 128

Point = tuple[float, float]
Cell = tuple[int, int]


class OccupancyGrid:
    """Free space of a rectangular room with box obstacles inflated by the robot's radius.

    The grid does not change once built: ``with_obstacles`` returns a new one. A static map is
    shared (its path lengths are the planner's move costs) while objects seen on the floor come
    and go; a copy per observation cannot leave a picked-up object in the shared map, and
    rebuilding costs tens of milliseconds at 5 cm in a WRS-sized room.

    Points are mapped to the cell that contains them; path lengths and paths run between cell
    centres. A point outside the room or in a cell that is not free is unreachable.
    """

    def __init__(
        self,
        bounds: tuple[float, float, float, float],
        obstacles: Iterable[Box] = (),
        *,
        cell: float = CELL,
        radius: float = ROBOT_RADIUS,
        mask: np.ndarray | None = None,
    ) -> None:
        """``bounds`` is (x0, x1, y0, y1), the room's walls, which are inflated like the boxes.
        ``mask``: the free cells, worked out already (``changed``); else from the obstacles."""
        self.bounds = bounds
        self.obstacles = tuple(obstacles)
        self.cell_size = cell
        self.radius = radius
        x0, x1, y0, y1 = bounds
        self.shape = (round((x1 - x0) / cell), round((y1 - y0) / cell))
        self.mask = self._free_mask() if mask is None else mask
        # one Dijkstra per source cell, remembered: lengths and the cell before each on its path
        self._trees: dict[Cell, np.ndarray] = {}  # by source cell: each free cell's predecessor
        self._lengths: dict[Cell, np.ndarray] = {}  # a source cell's lengths to every free cell
        self._index: np.ndarray | None = None
        self._ij: np.ndarray | None = None  # the free cells in _node order (_free_ij)
        self._csr: csr_matrix | None = None
        self._label: np.ndarray | None = None  # every cell's component (_labels)
        self._reach: dict[int, list[Point]] = {}  # free_cells(reachable_from), by component
        self._local: dict[tuple, tuple | None] = {}  # sim.joins' window parts, when no memo is given
        self._spans: tuple[np.ndarray, list[Box]] | None = None  # _obstacle_spans
        # the lengths length_matrix gave between cells (NaN: unreachable), for a grid changed
        # from this one; and the grid this one was changed from, with the cells freed and shut
        self._known: Known | None = None
        self._before: tuple[weakref.ref, np.ndarray, np.ndarray] | None = None

    # ------------------------------------------------------------------ cells and points
    def xy(self, i: int, j: int) -> Point:
        """Centre of cell (i, j) in room coordinates."""
        x0, _x1, y0, _y1 = self.bounds
        return x0 + (i + 0.5) * self.cell_size, y0 + (j + 0.5) * self.cell_size

    def cell(self, x: float, y: float) -> Cell:
        """The cell containing (x, y); may lie outside the grid when the point is outside the room."""
        x0, _x1, y0, _y1 = self.bounds
        return math.floor((x - x0) / self.cell_size), math.floor((y - y0) / self.cell_size)

    def free(self, x: float, y: float) -> bool:
        """Whether the robot's centre may stand in the cell of (x, y)."""
        return self._free_cell(self.cell(x, y))

    def component(self, x: float, y: float) -> int:
        """The connected component of free cells the point's cell is in (0: not free): two
        points with the same number reach each other, and each reaches the same cells."""
        c = self.cell(x, y)
        return int(self._labels[c]) if self._free_cell(c) else 0

    def free_cells(self, reachable_from: Point | None = None) -> list[Point]:
        """Centres of the free cells, in cell order; only those connected to ``reachable_from``
        when it is given (none if that point is not free): where the robot can actually go.
        A component's cells are remembered (the map's facts ask every turn of the same floor)."""
        if reachable_from is None:
            return [self.xy(int(i), int(j)) for i, j in zip(*np.nonzero(self.mask), strict=True)]
        start = self.cell(*reachable_from)
        if not self._free_cell(start):
            return []
        label = int(self._labels[start])
        if label not in self._reach:
            self._reach[label] = [self.xy(*c) for c in self._component_of(start)]
        return list(self._reach[label])

    def reaches_cells(self, flat: np.ndarray, reachable_from: Point) -> np.ndarray:
        """``reaches`` for cells given by flat index (i * columns + j), all in the grid."""
        start = self.cell(*reachable_from)
        if not self._free_cell(start):
            return np.zeros(len(flat), dtype=bool)
        return self._labels.ravel()[flat] == self._labels[start]

    def free_at(self, points: np.ndarray) -> np.ndarray:
        """``free`` for each of ``points`` ((n, 2)), at once."""
        i, j, inside = self._cells_of(points)
        out = np.zeros(len(points), dtype=bool)
        out[inside] = self.mask[i[inside], j[inside]]
        return out

    def _cells_of(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``cell`` of each of ``points`` ((n, 2)) as arrays (i, j), and which lie in the grid."""
        x0, _x1, y0, _y1 = self.bounds
        i = np.floor((points[:, 0] - x0) / self.cell_size).astype(np.int64)
        j = np.floor((points[:, 1] - y0) / self.cell_size).astype(np.int64)
        return i, j, (i >= 0) & (i < self.shape[0]) & (j >= 0) & (j < self.shape[1])

    def reaches(self, points: np.ndarray, reachable_from: Point) -> np.ndarray:
        """For each of ``points`` ((n, 2)): is its cell free and connected to ``reachable_from``'s
        (none where that is not free)? ``connected`` for many points at once."""
        start = self.cell(*reachable_from)
        if not self._free_cell(start) or not len(points):
            return np.zeros(len(points), dtype=bool)
        i, j, inside = self._cells_of(points)
        out = np.zeros(len(points), dtype=bool)
        out[inside] = self._labels[i[inside], j[inside]] == self._labels[start]
        return out

    def free_cells_near(self, at: Point, r: float, reachable_from: Point | None = None) -> list[Point]:
        """Centres of the free cells (connected to ``reachable_from`` where it is given) whose
        cell lies in the square of half-side ``r`` around ``at`` (a superset of those within
        ``r``; the caller measures), in cell order: ``free_cells`` near one point without
        listing every free cell."""
        free = self._free_of(reachable_from)
        if free is None:
            return []
        i0, j0 = self.cell(at[0] - r, at[1] - r)
        i1, j1 = self.cell(at[0] + r, at[1] + r)
        i0, j0 = max(i0, 0), max(j0, 0)
        i1, j1 = min(i1 + 1, self.shape[0]), min(j1 + 1, self.shape[1])
        if i0 >= i1 or j0 >= j1:
            return []
        ii, jj = np.nonzero(free[i0:i1, j0:j1])
        return [self.xy(int(i) + i0, int(j) + j0) for i, j in zip(ii, jj, strict=True)]

    def nearest_free_within(self, at: Point, r: float, reachable_from: Point | None = None) -> Point | None:
        """``nearest_free`` among the free cells within ``r`` of ``at`` (None where there is none),
        from the square around it only: where a tight pose backs out to, or adjusts from."""
        cells = [c for c in self.free_cells_near(at, r, reachable_from) if math.dist(c, at) <= r]
        return min(cells, key=lambda c: (math.dist(c, at), c)) if cells else None

    def nearest_free(self, x: float, y: float, reachable_from: Point | None = None) -> Point:
        """The centre of the free cell closest to (x, y), e.g. to snap a goal out of an obstacle;
        among ``free_cells(reachable_from)``. Raises ValueError when there is none. The cells
        within a hair of the least distance are found at once, and of those the one the exact
        distance and then the cell pick (a Python ``min`` over every free cell, several
        milliseconds each time the robot stood where no cell is free)."""
        free = self._free_of(reachable_from)
        ii, jj = np.nonzero(free) if free is not None else ((), ())
        if not len(ii):
            raise ValueError(f"no free cell{'' if reachable_from is None else ' reachable'} in the grid")
        x0, _x1, y0, _y1 = self.bounds
        d2 = (x0 + (ii + 0.5) * self.cell_size - x) ** 2 + (y0 + (jj + 0.5) * self.cell_size - y) ** 2
        near = np.flatnonzero(d2 <= d2.min() * (1 + 1e-9) + 1e-12)
        cells = [(int(ii[k]), int(jj[k])) for k in near]
        return self.xy(*min(cells, key=lambda c: (math.dist(self.xy(*c), (x, y)), c)))

    # ------------------------------------------------------------------ paths
    def path_length(self, a: Point, b: Point) -> float | None:
        """Shortest path length between the cells of a and b in metres; None if unreachable."""
        return self.lengths_from(a, [b])[0]

    def path_lengths(self, points: Sequence[Point]) -> list[list[float | None]]:
        """All pairs of ``path_length``: row k holds the lengths from points[k] to every point
        (None: unreachable). One call of scipy's Dijkstra for every source not asked before."""
        cells = [self.cell(*p) for p in points]
        rows = self._rows(cells)
        return [[None] * len(cells) if row is None else [self._at(row, d) for d in cells] for row in rows]

    def length_matrix(self, points: Sequence[Point]) -> np.ndarray:
        """``path_lengths`` as an array: [k, m] the length from points[k] to points[m], NaN where
        unreachable (or either is not free). One gather per row, not a call per pair. On a grid
        ``changed`` from another, the pairs the change cannot touch keep the lengths that one
        gave them (``sim.carried``), and only as many points' rows are searched as cover the
        rest (in the 96-object mission, about half the searches a row per point made)."""
        cells = [self.cell(*p) for p in points]
        free = np.array([self._free_cell(c) for c in cells], dtype=bool)
        node = self._node
        idx = np.array([node[c] if ok else 0 for c, ok in zip(cells, free, strict=True)], dtype=np.int64)
        out = np.full((len(cells), len(cells)), np.nan)
        before = self._before[0]() if self._before is not None else None
        both = free[:, None] & free[None, :]
        if before is not None:
            old, proven = carried(before, self._before[1], self._before[2], cells, self._labels)
            out[proven] = old[proven]
            left = both & ~proven
        else:
            left = both.copy()
        # The graph is undirected: a row gives its column too. The rows kept from before are
        # read; then the rows searched are those of the points with the most pairs left, until
        # none is (a new point: its row; a pair the change may touch: one of its two). A pair
        # both of whose rows are read takes its first point's, as a search from each would.
        left |= left.T
        search = [k for k in range(len(cells)) if free[k] and cells[k] in self._lengths]  # no search
        for k in search:
            left[k, :] = left[:, k] = False
        while left.any():
            k = int(np.argmax(left.sum(axis=1)))
            search.append(k)
            left[k, :] = left[:, k] = False
        rows = self._rows([cells[k] for k in search])
        for k, row in zip(search, rows, strict=True):
            out[:, k] = row[idx]
        for k, row in zip(search, rows, strict=True):
            out[k] = row[idx]
        out[:, ~free] = np.nan
        out[~free, :] = np.nan
        out[~np.isfinite(out)] = np.nan
        self._keep(cells, free, out)
        return out

    def _keep(self, cells: list[Cell], free: np.ndarray, out: np.ndarray) -> None:
        """Remember ``length_matrix``'s answer among the free ``cells`` (``_known``)."""
        if self._known is None:
            self._known = Known(self.shape)
        at = np.array(cells, dtype=np.int64).reshape(-1, 2)[free]
        self._known.put(at, out[np.ix_(free, free)])

    def lengths_both_ways(
        self, a: Point, points: Sequence[Point]
    ) -> tuple[list[float | None], list[float | None]]:
        """``path_length`` from a to each of ``points`` and from each of them to a: one search,
        from a. The graph is undirected, so a length back is the length there (a search from
        each of ``points`` summed the same steps in the other order: a length differs, if at
        all, in its last bits, and the map's facts round to the centimetre)."""
        there = self.lengths_from(a, points)
        return there, list(there)

    def lengths_from(self, a: Point, points: Sequence[Point]) -> list[float | None]:
        """``path_length`` from a to each of ``points``, with one Dijkstra."""
        (row,) = self._rows([self.cell(*a)])
        if row is None:
            return [None] * len(points)
        return [self._at(row, self.cell(*p)) for p in points]

    def path(self, a: Point, b: Point) -> list[Point] | None:
        """A shortest path as the polyline of cell centres from a's cell to b's (both included),
        for the base to follow; None if unreachable."""
        ks = self._path_nodes(a, b)
        if ks is None:
            return None
        ij = self._free_ij
        return [self.xy(int(ij[k, 0]), int(ij[k, 1])) for k in ks]

    def path_cells(self, a: Point, b: Point) -> np.ndarray | None:
        """``path``'s cells as flat indices (i * columns + j), in order; None if unreachable."""
        ks = self._path_nodes(a, b)
        if ks is None:
            return None
        ij = self._free_ij[ks]
        return ij[:, 0] * self.shape[1] + ij[:, 1]

    def _path_nodes(self, a: Point, b: Point) -> list[int] | None:
        ca, cb = self.cell(*a), self.cell(*b)
        if not (self._free_cell(ca) and self._free_cell(cb)):
            return None
        before, node = self._tree(ca), self._node
        ka, kb = int(node[ca]), int(node[cb])
        if kb != ka and before[kb] < 0:
            return None
        ks = [kb]
        while ks[-1] != ka:
            ks.append(int(before[ks[-1]]))
        ks.reverse()
        return ks

    def connected(self, a: Point, b: Point) -> bool:
        """Whether a path joins a and b: the same component of the free cells."""
        ca, cb = self.cell(*a), self.cell(*b)
        if not (self._free_cell(ca) and self._free_cell(cb)):
            return False
        return self._labels[ca] == self._labels[cb]

    @property
    def _obstacle_spans(self) -> tuple[np.ndarray, list[Box]]:
        """The obstacles' spans as an (n, 4) array (no cell: an empty span), and the obstacles."""
        if self._spans is None:
            # ``_span`` of every obstacle at once, in the same sums (a call per obstacle, for
            # every grid a new floor changes, grew with the floor items)
            b = np.array([(o.cx, o.cy, o.sx, o.sy) for o in self.obstacles], dtype=float).reshape(-1, 4)
            x0, _x1, y0, _y1 = self.bounds
            r, cell = self.radius, self.cell_size
            lo_i = np.floor((b[:, 0] - b[:, 2] / 2 - r - x0) / cell).astype(np.int64)
            lo_j = np.floor((b[:, 1] - b[:, 3] / 2 - r - y0) / cell).astype(np.int64)
            hi_i = np.floor((b[:, 0] + b[:, 2] / 2 + r - x0) / cell).astype(np.int64)
            hi_j = np.floor((b[:, 1] + b[:, 3] / 2 + r - y0) / cell).astype(np.int64)
            rows = np.stack(
                [
                    np.maximum(lo_i, 0),
                    np.minimum(hi_i + 1, self.shape[0]),
                    np.maximum(lo_j, 0),
                    np.minimum(hi_j + 1, self.shape[1]),
                ],
                axis=1,
            )
            rows[(rows[:, 0] >= rows[:, 1]) | (rows[:, 2] >= rows[:, 3])] = 0  # no cell: empty
            self._spans = (rows, list(self.obstacles))
        return self._spans

    def _span(self, box: Box) -> tuple[int, int, int, int] | None:
        """The cells ``box`` (inflated) may cover, as slices' bounds (i0, i1, j0, j1), clipped
        to the grid; None where it covers none. A cell outside is more than the radius away."""
        r = self.radius
        lo_i, lo_j = self.cell(box.cx - box.sx / 2 - r, box.cy - box.sy / 2 - r)
        hi_i, hi_j = self.cell(box.cx + box.sx / 2 + r, box.cy + box.sy / 2 + r)
        i0, i1 = max(lo_i, 0), min(hi_i + 1, self.shape[0])
        j0, j1 = max(lo_j, 0), min(hi_j + 1, self.shape[1])
        if i0 >= i1 or j0 >= j1:
            return None
        return i0, i1, j0, j1

    def _window(self, box: Box):
        """The cells ``box`` (inflated) may cover, as slices' bounds, and their centres."""
        span = self._span(box)
        if span is None:
            return None
        i0, i1, j0, j1 = span
        x0, _x1, y0, _y1 = self.bounds
        xs = x0 + (np.arange(i0, i1) + 0.5) * self.cell_size
        ys = y0 + (np.arange(j0, j1) + 0.5) * self.cell_size
        x, y = np.meshgrid(xs, ys, indexing="ij")
        return (i0, i1, j0, j1), x, y

    def _clear_of(self, boxes: Sequence[Box], x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Which of the points (x, y) are at least the radius from the walls and every one of
        ``boxes``: ``Box.clearance``'s verdict, as in ``_free_mask`` (numpy decides the clear
        cases, clearance itself those within 1e-9 m of the radius)."""
        x0, x1, y0, y1 = self.bounds
        r = self.radius
        clear = np.minimum(np.minimum(x - x0, x1 - x), np.minimum(y - y0, y1 - y)) >= r
        near = np.zeros(x.shape, dtype=bool)
        for b in boxes:
            d = np.hypot(
                np.maximum(np.abs(x - b.cx) - b.sx / 2, 0.0), np.maximum(np.abs(y - b.cy) - b.sy / 2, 0.0)
            )
            clear &= d >= r
            near |= np.abs(d - r) <= 1e-9
        for k in zip(*np.nonzero(near), strict=True):
            px, py = float(x[k]), float(y[k])
            walls = min(px - x0, x1 - px, py - y0, y1 - py) >= r
            clear[k] = walls and all(b.clearance(px, py) >= r for b in boxes)
        return clear

    @property
    def _labels(self) -> np.ndarray:
        """Each cell's connected component of free cells (0: not free); remembered, since the
        grid never changes."""
        if self._label is None:
            self._label = _components(self.mask)
        return self._label

    def _component_of(self, start: Cell) -> list[Cell]:
        """The free cells 8-connected to ``start`` (a free cell), in index order: its component
        (no graph is built for it: at 96 objects each item's own grid did, 31 s a replan)."""
        return [(int(i), int(j)) for i, j in np.argwhere(self._labels == self._labels[start])]

    def reaches_with(self, box: Box, a: Point, points: Sequence[Point]) -> int:
        """How many of ``points`` the robot at ``a`` still reaches with ``box`` added to the floor
        (-1: the box covers the robot's own cell). This grid changed by the box (its cells only),
        for ranking where to put an item down."""
        grid = self.changed((*self.obstacles, box), (), (box,))
        if not grid.free(*a):
            return -1
        return sum(grid.connected(a, p) for p in points)

    def changed(self, obstacles: Sequence[Box], gone: Sequence[Box], new: Sequence[Box]) -> OccupancyGrid:
        """The grid of ``obstacles``: this one's with ``gone`` taken away and ``new`` added. Only
        their cells are worked out again (a floor differs from the last by a few items; its
        whole mask, every box's cells, was most of a new floor's grids). The free cells are the
        same as a new grid's: a cell's verdict is each obstacle's, and only those whose cells
        meet a changed box's can cover one of its cells."""
        free = self.mask.copy()
        spans, boxes = self._obstacle_spans
        for box in gone:
            window = self._window(box)
            if window is None:
                continue
            (i0, i1, j0, j1), x, y = window
            meet = (spans[:, 0] < i1) & (i0 < spans[:, 1]) & (spans[:, 2] < j1) & (j0 < spans[:, 3])
            left = [boxes[k] for k in np.nonzero(meet)[0] if boxes[k] not in gone]
            left += [b for b in new if _meet(self._span(b), (i0, i1, j0, j1))]
            free[i0:i1, j0:j1] = self._clear_of(left, x, y)
        for box in new:
            window = self._window(box)
            if window is not None:
                (i0, i1, j0, j1), x, y = window
                free[i0:i1, j0:j1] &= self._clear_of((box,), x, y)
        free.flags.writeable = False
        grid = OccupancyGrid(self.bounds, obstacles, cell=self.cell_size, radius=self.radius, mask=free)
        # its lengths may be carried from this one's (length_matrix); weakly: a chain of floors
        # must not keep every grid before it alive
        grid._before = (weakref.ref(self), free & ~self.mask, self.mask & ~free)
        return grid

    def with_obstacles(self, boxes: Iterable[Box]) -> OccupancyGrid:
        """A new grid with ``boxes`` added (e.g. objects seen on the floor); this one is unchanged."""
        return OccupancyGrid(
            self.bounds, self.obstacles + tuple(boxes), cell=self.cell_size, radius=self.radius
        )

    def _rows(self, cells: Sequence[Cell]) -> list[np.ndarray | None]:
        """Each free cell's path lengths to every free cell (by `_node` index; inf: unreachable),
        None for a cell that is not free. The lengths of every map's facts and of the put-down
        checks: networkx's Dijkstra took 8 of 28 s of a pybullet case III mission, in Python;
        scipy's runs the same search in C over a sparse matrix of the same edges and weights
        (docs/world.md). Rows are remembered like the trees."""
        kept = self._lengths
        wanted = sorted({c for c in cells if self._free_cell(c)})
        todo = [c for c in wanted if c not in kept]
        for c in wanted:
            if c in kept:
                kept[c] = kept.pop(c)  # the latest asked last: the first to go is the longest unasked
        if todo:
            found = dijkstra(self._matrix, directed=False, indices=[self._node[c] for c in todo])
            for c, row in zip(todo, np.atleast_2d(found), strict=True):
                kept[c] = row
        rows = [kept.get(c) for c in cells]
        _forget_oldest(kept)
        return rows

    def _at(self, row: np.ndarray, c: Cell) -> float | None:
        if not self._free_cell(c):
            return None
        d = float(row[self._node[c]])
        return d if math.isfinite(d) else None

    @property
    def _node(self) -> np.ndarray:
        """Each cell's index among the free cells (in ``np.nonzero`` order), -1 elsewhere."""
        if self._index is None:
            index = np.full(self.shape, -1, dtype=np.int64)
            index[self.mask] = np.arange(int(self.mask.sum()))
            self._index = index
        return self._index

    @property
    def _matrix(self) -> csr_matrix:
        """The 8-connected graph's edges (to higher neighbours) as a sparse matrix of weights:
        each free cell's row holds its neighbours right, down-left, down and down-right (higher
        cells, in ``_node`` order, so the row's columns are sorted). Made as arrays directly,
        not from a list of pairs (the conversion's sort was most of a new floor's graph)."""
        if self._csr is None:
            n_i, n_j = self.shape
            node = self._node
            diagonal = self.cell_size * math.sqrt(2)
            # the node of each cell, -1 beyond the grid's edges and where not free
            padded = np.full((n_i + 1, n_j + 2), -1, dtype=np.int64)
            padded[:n_i, 1 : n_j + 1] = node
            i, j = np.nonzero(self.mask)
            j = j + 1
            steps = ((0, 1, self.cell_size), (1, -1, diagonal), (1, 0, self.cell_size), (1, 1, diagonal))
            neighbours = np.stack([padded[i + di, j + dj] for di, dj, _w in steps], axis=1)
            weights = np.broadcast_to(np.array([w for *_d, w in steps]), neighbours.shape)
            ok = neighbours >= 0
            indptr = np.zeros(len(i) + 1, dtype=np.int64)
            np.cumsum(ok.sum(axis=1), out=indptr[1:])
            self._csr = csr_matrix((weights[ok], neighbours[ok], indptr), shape=(len(i), len(i)))
        return self._csr

    def _tree(self, c: Cell) -> np.ndarray:
        """Dijkstra from cell c: for each free cell (by ``_node`` index) the index of the cell
        before it on a shortest path from c, -1 where c does not reach (and at c). Remembered,
        since the grid never changes and a mission asks from the same waypoints again and again;
        one tree serves every path from c. scipy's search in C over ``_matrix``, like the lengths
        (networkx's in Python, and its graph built for every new floor, were a quarter of a
        96-object mission's wall time); its ties fall one fixed way for a given grid, so paths
        are a function of the grid alone. An int32 array: up to ``SOURCES_KEPT`` are kept."""
        if c in self._trees:
            self._trees[c] = self._trees.pop(c)  # the latest asked last, as in _rows
        else:
            _lengths, pred = dijkstra(
                self._matrix, directed=False, indices=int(self._node[c]), return_predecessors=True
            )
            before = pred.astype(np.int32)
            before[before < 0] = -1  # scipy's -9999: the source, and cells it does not reach
            self._trees[c] = before
            _forget_oldest(self._trees)
        return self._trees[c]

    @property
    def _free_ij(self) -> np.ndarray:
        """The free cells' (i, j), row k the cell of ``_node`` index k."""
        if self._ij is None:
            self._ij = np.argwhere(self.mask)
        return self._ij

    # ------------------------------------------------------------------ construction
    def _free_cell(self, c: Cell) -> bool:
        i, j = c
        return 0 <= i < self.shape[0] and 0 <= j < self.shape[1] and bool(self.mask[i, j])

    def _free_of(self, reachable_from: Point | None) -> np.ndarray | None:
        """The free cells as a mask, or those of ``reachable_from``'s component; None where that
        point is not free."""
        if reachable_from is None:
            return self.mask
        start = self.cell(*reachable_from)
        return self._labels == self._labels[start] if self._free_cell(start) else None

    def _free_mask(self) -> np.ndarray:
        """Cells whose centre is at least the radius from every wall and obstacle box.

        The verdict must be ``Box.clearance``'s own (a cell near the radius, in the WRS room one
        is 6e-5 m off it, must get the same answer callers get), whatever a vector library's
        ``hypot`` rounds to: numpy decides the cells clearly inside or outside, and the few within
        1e-9 m of the radius are decided by ``clearance`` itself. A two-room floor of 10,000 cells
        with 36 boxes took 0.32 s in a plain loop, ~10 ms so.
        """
        x0, _x1, y0, _y1 = self.bounds
        n_i, n_j = self.shape
        xs = x0 + (np.arange(n_i) + 0.5) * self.cell_size
        ys = y0 + (np.arange(n_j) + 0.5) * self.cell_size
        x, y = np.meshgrid(xs, ys, indexing="ij")
        free = self._clear_of((), x, y)  # the walls
        # each box over the cells it may cover only (a cell's verdict is one box's at a time:
        # over the whole floor, a 96-object room's 130 boxes were most of a new grid's time)
        for b in self.obstacles:
            window = self._window(b)
            if window is not None:
                (i0, i1, j0, j1), bx, by = window
                free[i0:i1, j0:j1] &= self._clear_of((b,), bx, by)
        free.flags.writeable = False  # the grid is a value: with_obstacles makes a new one
        return free


def _meet(span: tuple[int, int, int, int] | None, other: tuple[int, int, int, int]) -> bool:
    """Whether two cell windows (i0, i1, j0, j1) share a cell."""
    return (
        span is not None
        and span[0] < other[1]
        and other[0] < span[1]
        and span[2] < other[3]
        and other[2] < span[3]
    )


_EIGHT = np.ones((3, 3), dtype=bool)  # a cell's eight neighbours: the graph's steps


def _components(free: np.ndarray) -> np.ndarray:
    """Each cell's 8-connected component of ``free`` cells, numbered from 1 (0: not free): the
    graph's components, by scipy's labelling in C (a flood fill in Python took 1-3 s a mission)."""
    labels, _count = _label_components(free, structure=_EIGHT)
    return labels


def _forget_oldest(kept: dict) -> None:
    """Drop a grid's longest unasked sources (the first in ``kept``) past ``SOURCES_KEPT``."""
    while len(kept) > SOURCES_KEPT:
        del kept[next(iter(kept))]
