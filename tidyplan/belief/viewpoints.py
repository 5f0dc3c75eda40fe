"""Viewpoints generated from the map where the scenario's own are too few.

Goebelbecker et al. search from a set of places the robot may look from, each with the chance
that an object is revealed there. A scenario names a few; a room nobody tuned (a second room
with no viewpoint, a corner behind a shelf) needs more. They are chosen here by a greedy cover:
candidate poses on a lattice over the floor the robot can reach, each with the placement points
(floor and table tops, ``Exploration.points``) it sees within the camera's range with furniture
occluding; the pose that reveals most of what no chosen viewpoint reveals yet is added, until
none adds a meaningful share. The probability each gets (``p-item-near``) is computed later,
from what is still unseen, by the belief.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from sim.scenario.model import Scenario

Point = tuple[float, float]

SPACING = 0.40  # m between candidate poses
MIN_GAIN = 0.01  # share of the viewable points a new viewpoint must add (12 points in case I)
MAX_NEW = 16  # viewpoints one call may add: enough for two rooms at the default range


def lattice(cells: Sequence[Point], spacing: float = SPACING) -> list[Point]:
    """One cell per ``spacing`` square: the one nearest the square's centre (cells in sorted order,
    so the choice depends on the cells alone)."""
    best: dict[tuple[int, int], tuple[float, Point]] = {}
    for c in sorted(cells):
        key = (round(c[0] / spacing), round(c[1] / spacing))
        d = (c[0] - key[0] * spacing) ** 2 + (c[1] - key[1] * spacing) ** 2
        if key not in best or d < best[key][0]:
            best[key] = (d, c)
    return [c for _, c in sorted(best.values(), key=lambda v: v[1])]


def cover(
    candidates: Sequence[Point],
    view: Callable[[Point], np.ndarray],
    covered: np.ndarray,
    wanted: np.ndarray | None = None,
    min_gain: float = MIN_GAIN,
    max_new: int = MAX_NEW,
) -> list[Point]:
    """Greedy set cover: poses from ``candidates`` that see the ``wanted`` points (default all)
    not yet ``covered``, most new points first, each adding at least ``min_gain`` of what the
    candidates can see at all. Ties go to the earlier candidate."""
    views = [view(c) for c in candidates]
    if not views:
        return []
    wanted = np.ones_like(covered) if wanted is None else wanted
    viewable = np.logical_or.reduce(views) & wanted
    need = max(1, int(np.ceil(min_gain * int(viewable.sum()))))
    left = viewable & ~covered
    chosen: list[Point] = []
    while len(chosen) < max_new and left.any():
        gains = [int((v & left).sum()) for v in views]
        k = int(np.argmax(gains))
        if gains[k] < need:
            break
        chosen.append(candidates[k])
        left &= ~views[k]
    return chosen


def placement_points(
    scenario: Scenario, spacing: float
) -> tuple[list[tuple[float, float, float]], list[str]]:
    """Where an item may lie: a lattice of ``spacing`` over the floor clear of furniture, and over
    the top of every table; 5 cm above the surface (an item's middle)."""
    x0, x1, y0, y1 = scenario.bounds
    points, support = [], []
    xs = np.arange(x0 + spacing / 2, x1, spacing)
    ys = np.arange(y0 + spacing / 2, y1, spacing)
    for x in xs:
        for y in ys:
            x, y = round(float(x), 3), round(float(y), 3)
            on = [f for f in scenario.furniture if f.box().clearance(x, y) == 0.0]
            if not on:
                if all(f.box().clearance(x, y) >= 0.05 for f in scenario.furniture):
                    points.append((x, y, 0.05))
                    support.append("floor")
            elif on[0].kind == "table":
                points.append((x, y, on[0].height + 0.05))
                support.append(on[0].name)
    return points, support
