"""Which path lengths between points a changed grid keeps from the grid it was changed from.

A floor differs from the last by a few items: cells freed where one was taken away (F),
cells shut where one was seen or put down (B). A length between two points s and t changes only
if a shortest path used a cell of B, or a path through F is now shorter. Both are bounded
without a search: on the 8-connected grid no path between two cells is shorter than their
octile distance (straight steps, then diagonal ones, each its weight), and a path through a
region passes a cell on its border, so

- a path s-t through F is at least min over F's border cells f of oct(s, f) + oct(f, t);
- an old shortest path s-t through a cell of B was at least the same sum over B's border.

A pair whose old length is below both bounds keeps it (an old shortest path avoids B, and no
path through F is as short); one unreachable before stays so where the new grid's components
keep its ends apart. Everything else is left to the caller's search (after a floor item is
taken, the pairs whose path went round it). ``Known`` holds the lengths a grid gave, for the
grid changed from it to read.

Imports: none of sim (the grids it reads are passed in).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.ndimage import binary_erosion

_EIGHT = np.ones((3, 3), dtype=bool)
_SLACK = 1e-9  # m: far above the rounding of a sum of a few hundred steps, far below a step


def carried(before, freed: np.ndarray, shut: np.ndarray, cells, now_labels: np.ndarray):
    """(lengths, proven) for every pair of ``cells`` on the changed grid: ``lengths[s, t]`` the
    old grid's length where ``proven[s, t]`` (NaN: unreachable), from ``before._known`` (the
    lengths the old grid gave between cells, a ``Known``). ``freed``/``shut``: the cells free
    now and not before, and the other way (boolean masks); ``now_labels``: the new grid's
    components."""
    n = len(cells)
    if before._known is None:
        return np.full((n, n), np.nan), np.zeros((n, n), dtype=bool)
    at = np.array(cells, dtype=np.int64).reshape(-1, 2)
    old, have = before._known.get(at)
    if not have.any():
        return old, have
    ok = np.array([before._free_cell(c) for c in cells], dtype=bool)
    through_f = _through(at, freed, before.cell_size)
    through_b = _through(at, shut, before.cell_size)
    reached = np.isfinite(old)
    with np.errstate(invalid="ignore"):
        kept = reached & (through_f > old + _SLACK) & (through_b > old + _SLACK)
    # unreachable before: still so where the new grid's components keep the two apart
    label = np.array([int(now_labels[c]) if _inside(now_labels, c) else 0 for c in cells])
    apart = (label[:, None] != label[None, :]) | (label[:, None] == 0)
    kept |= ~reached & apart & ok[:, None] & ok[None, :]
    return old, have & kept


def _through(at: np.ndarray, region: np.ndarray, cell: float) -> np.ndarray:
    """[s, t]: the least octile length of a path from cell ``at[s]`` to ``at[t]`` through a cell
    of ``region`` (a boolean mask; inf where it is empty), over its border cells only."""
    ii, jj = np.nonzero(region)
    if not len(ii):
        return np.full((len(at), len(at)), np.inf)
    # a cell of the region with a neighbour outside it (beyond the grid's edge is no way in),
    # worked out in the region's own window (a cell to spare), not over the room
    i0, j0 = max(int(ii.min()) - 1, 0), max(int(jj.min()) - 1, 0)
    window = region[i0 : int(ii.max()) + 2, j0 : int(jj.max()) + 2]
    border = np.argwhere(window & ~binary_erosion(window, _EIGHT, border_value=1)) + (i0, j0)
    d = np.abs(at[:, None, :] - border[None, :, :])
    lo, hi = d.min(axis=2), d.max(axis=2)
    octile = cell * (hi - lo) + cell * math.sqrt(2) * lo  # (points, border cells)
    out = np.empty((len(at), len(at)))
    for s in range(len(at)):  # a row at a time: a whole map's waypoints by a border at once is large
        out[s] = (octile[s][None, :] + octile).min(axis=1)
    return out


def _inside(labels: np.ndarray, c) -> bool:
    return 0 <= c[0] < labels.shape[0] and 0 <= c[1] < labels.shape[1]


class Known:
    """Lengths ``length_matrix`` gave between cells (NaN: unreachable), as one square array
    over the cells met (each cell's row in ``at``), so a changed grid reads a floor's
    waypoints' at once (``carried``)."""

    MOST = 256  # cells: a floor's waypoints, the whole map's too; past it, start again

    def __init__(self, shape: tuple[int, int]) -> None:
        self.at = np.full(shape, -1, dtype=np.int32)
        self.count = 0
        self.lengths = np.full((64, 64), np.nan)
        self.set = np.zeros((64, 64), dtype=bool)

    def ids(self, cells: np.ndarray) -> np.ndarray:
        """Each cell's row (-1: not met, or outside the grid)."""
        n_i, n_j = self.at.shape
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < n_i) & (cells[:, 1] >= 0) & (cells[:, 1] < n_j)
        out = np.full(len(cells), -1, dtype=np.int64)
        out[inside] = self.at[cells[inside, 0], cells[inside, 1]]
        return out

    def put(self, cells: np.ndarray, lengths: np.ndarray) -> None:
        """``lengths`` among ``cells`` ((n, 2), in the grid)."""
        ids = self.ids(cells)
        if self.count + int((ids < 0).sum()) > self.MOST:
            self.__init__(self.at.shape)
            ids = self.ids(cells)
        for k in np.nonzero(ids < 0)[0].tolist():
            i, j = cells[k]
            if self.at[i, j] < 0:  # a cell twice: one row
                self.at[i, j], self.count = self.count, self.count + 1
            ids[k] = self.at[i, j]
        if self.count > len(self.lengths):
            size = max(2 * len(self.lengths), self.count)
            grown, seen = np.full((size, size), np.nan), np.zeros((size, size), dtype=bool)
            grown[: len(self.lengths), : len(self.lengths)] = self.lengths
            seen[: len(self.set), : len(self.set)] = self.set
            self.lengths, self.set = grown, seen
        self.lengths[np.ix_(ids, ids)] = lengths
        self.set[np.ix_(ids, ids)] = True

    def get(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lengths, known) among ``cells`` ((n, 2))."""
        ids = self.ids(cells)
        met = ids >= 0
        safe = np.where(met, ids, 0)
        lengths = self.lengths[np.ix_(safe, safe)]
        known = self.set[np.ix_(safe, safe)] & met[:, None] & met[None, :]
        return lengths, known
