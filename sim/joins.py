"""What taking one box away from a grid joins: the question a blocked pair's blockers ask.

For pairs of points the grid does not join, which obstacle, taken away alone, would let a path
join them. Answered from the cells around the box alone: taking it away frees only cells of its
window, and those join the components they touch there (nothing is labelled over the whole
grid: per floor item and new floor, that was a fifth of a 96-object turn). Functions of an
``OccupancyGrid``: the grid holds free space and the paths over it, this the one question the
map's blocker search asks of it; a grid's ``_local`` keeps their window parts where the caller
keeps none.

Imports: sim.box (the obstacles), sim.grid (the grid asked about).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from sim.box import Box
from sim.grid import OccupancyGrid, Point, _components


def pair_cells(
    grid: OccupancyGrid, pairs: Sequence[tuple[Point, Point]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pairs' cells as index arrays (n, 2), clipped into the grid, and which are inside it."""
    cells = np.array([grid.cell(*p) for pair in pairs for p in pair], dtype=np.int64).reshape(-1, 2, 2)
    i, j = cells[..., 0], cells[..., 1]
    inside = (i >= 0) & (i < grid.shape[0]) & (j >= 0) & (j < grid.shape[1])
    return np.clip(i, 0, grid.shape[0] - 1), np.clip(j, 0, grid.shape[1] - 1), inside


def joins_without(
    grid: OccupancyGrid, box: Box, pairs: tuple[np.ndarray, np.ndarray, np.ndarray], memo: dict | None = None
) -> np.ndarray:
    """For each of the ``pair_cells`` pairs: would a path join them with ``box``, one of the
    grid's obstacles, taken away? The same answers as ``connected`` on a new grid without it.
    ``memo``: a dict the caller keeps across grids (the window's parts depend on the obstacles
    near it only); without one, the grid's own."""
    i, j, inside = pairs
    labels = grid._labels
    old = np.where(inside, labels[i, j], 0)  # (n, 2) each end's component now
    span = grid._span(box)
    if span is not None:
        # a box whose window holds no end and meets the components of no pair's two ends
        # joins no pair: its freed cells join only the components they touch, all in the
        # window (most floor items of a crowded floor's blocker search: in the open, one
        # component; the parts and unions below were a third of its time)
        e0, e1 = max(span[0] - 1, 0), min(span[1] + 1, grid.shape[0])
        f0, f1 = max(span[2] - 1, 0), min(span[3] + 1, grid.shape[1])
        near = labels[e0:e1, f0:f1]
        ends_near = inside & (i >= e0) & (i < e1) & (j >= f0) & (j < f1)
        if not ends_near.any():
            touched = np.unique(near[near > 0])
            apart = (old[:, 0] != old[:, 1]) & np.isin(old, touched).all(axis=1)
            if not apart.any():
                return (old[:, 0] != 0) & (old[:, 0] == old[:, 1])
    local = _without(grid, box, grid._local if memo is None else memo)
    if local is None:  # it covers no cell: nothing is freed
        return (old[:, 0] != 0) & (old[:, 0] == old[:, 1])
    (e0, e1, f0, f1), parts, freed = local
    # each freed part joins the components of the cells it touches; parts touching a common
    # component are one (they meet through it): union by the smallest label
    window = labels[e0:e1, f0:f1]
    top = int(labels.max()) + 1
    remap = np.arange(top + len(freed) + 1)
    for n, part in enumerate(freed):
        touched = np.unique(window[(parts == part) & (window > 0)])
        ids = [top + n, *(int(t) for t in touched)]
        roots = {int(_root(remap, x)) for x in ids}
        low = min(roots)
        for r in roots:
            remap[r] = low
    for x in range(len(remap)):
        remap[x] = _root(remap, x)
    ends = remap[old]
    # an end in a freed part (a cell only ``box`` covered) is in that part's component
    within = inside & (i >= e0) & (i < e1) & (j >= f0) & (j < f1)
    for n, part in enumerate(freed):
        at = np.zeros(within.shape, dtype=bool)
        at[within] = parts[i[within] - e0, j[within] - f0] == part
        ends[at & (old == 0)] = remap[top + n]
    return (ends[:, 0] != 0) & (ends[:, 0] == ends[:, 1])


def _without(grid: OccupancyGrid, box: Box, memo: dict):
    """The window around ``box`` (its span and a cell beyond), its free cells' parts with
    ``box`` taken away (labels, 8-connected, within the window), and which parts hold a cell
    that only ``box`` covered; None where it covers no cell. Kept in ``memo`` by the box, the
    obstacles near it and the grid's make."""
    window = grid._window(box)
    if window is None:
        return None
    (i0, i1, j0, j1), x, y = window
    spans, boxes = grid._obstacle_spans
    meet = (spans[:, 0] < i1) & (i0 < spans[:, 1]) & (spans[:, 2] < j1) & (j0 < spans[:, 3])
    others = tuple(boxes[k] for k in np.nonzero(meet)[0] if boxes[k] != box)
    key = (box, others, grid.bounds, grid.cell_size, grid.radius)
    if key in memo:
        return memo[key]
    mask = grid.mask
    span_free = mask[i0:i1, j0:j1] | grid._clear_of(others, x, y)
    e0, e1 = max(i0 - 1, 0), min(i1 + 1, grid.shape[0])
    f0, f1 = max(j0 - 1, 0), min(j1 + 1, grid.shape[1])
    free = mask[e0:e1, f0:f1].copy()
    free[i0 - e0 : i1 - e0, j0 - f0 : j1 - f0] = span_free
    parts = _components(free)
    new = free & ~mask[e0:e1, f0:f1]
    freed = sorted(int(k) for k in np.unique(parts[new]))
    if len(memo) > 8192:
        memo.clear()
    memo[key] = ((e0, e1, f0, f1), parts, freed)
    return memo[key]


def _root(parent: np.ndarray, x: int) -> int:
    while parent[x] != x:
        x = int(parent[x])
    return x
