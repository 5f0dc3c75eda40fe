"""Where to look again for an item the belief forgot: a viewpoint near where it was last
believed, added to the exploration for each round (``tidyplan.belief.state.Belief.explore_again``
asks). The belief is read through a small protocol (``Remembers``), as the grasp poses read the
map: this module knows nothing of how the belief is kept.
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Protocol

from sim.visibility import Box3
from tidyplan.belief import viewpoints
from tidyplan.belief.exploration import Exploration
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.known import Known
from tidyplan.belief.mapfacts import Point

FORGOTTEN_FROM = 0.9  # m: the nearest a viewpoint at a forgotten item's place stands (a sweep's floor
# frame starts about 0.6 m out)


class Remembers(Protocol):
    """What the choice needs of the belief (``tidyplan.belief.state.Belief``)."""

    prior: dict[str, int] | None
    categories: list[str]
    items: dict[str, Known]
    forgotten: dict[str, Known]  # the items forgotten, by name
    exploration: Exploration
    room: RoomMap

    def item_boxes(self) -> list[tuple[Known, Box3]]: ...

    def should_see(self, k: Known, at: Point | None = None, boxes: list | None = None) -> bool: ...


def viewpoints_at_forgotten(belief: Remembers) -> list[str]:
    """A viewpoint close to where each forgotten item of a category the prior still misses
    was last believed: the likeliest place for it, and one the looks that forgot it may have
    had hidden (the belief's boxes occlude less than the world's furniture: wrs-task1-s007, a
    shape seen three times beside a tall table, then missed by three frames and forgotten,
    and never seen again from the viewpoints, whose cover of the map said they showed it).
    Each round one more, from another side, not near a viewpoint that shows it, and from which
    the item itself would be seen there (``should_see``: not a cell that sees only the floor
    around it, over a table that hides it): the latest pose it was seen from, else the free
    cell nearest the place at least FORGOTTEN_FROM m from it. In wrs-task1-s106 a box behind
    a tall table, between a chair and two walls, was in sight of no cell near it but from
    the pose its first sweep found it from. Returns the names of the viewpoints added."""
    if belief.prior is None:
        return []
    have = Counter(k.category for k in belief.items.values())
    lacking = {c for c in belief.categories if belief.prior[c] > have[c]}
    taken = belief.exploration.taken()
    room = belief.room
    grid = room.grid(())
    cells = viewpoints.lattice(grid.free_cells(reachable_from=room.entrance), 0.2)
    names = []
    boxes = belief.item_boxes()
    for name, k in sorted(belief.forgotten.items()):
        if k.category not in lacking or name in belief.items:
            continue
        # near a viewpoint that shows it there is no new one; beside one too close to show it
        # (the camera cannot look that far down) there may be
        showing = [q for q in taken if belief.should_see(k, q, boxes)]
        shown = [grid.nearest_free(*at, reachable_from=room.entrance) for at in reversed(k.seen_from)]
        options = [c for c in shown if _away(c, showing) and belief.should_see(k, c, boxes)] or [
            c
            for _, c in sorted(
                (math.dist(c, (k.x, k.y)), c)
                for c in cells
                if math.dist(c, (k.x, k.y)) >= FORGOTTEN_FROM
                and _away(c, showing)
                and belief.should_see(k, c, boxes)
            )
        ]
        if not options:
            continue
        taken.append(options[0])
        names.append(belief.exploration.add_viewpoint(options[0], forgotten=k.name))
    return names


def _away(c: Point, points: list[Point]) -> bool:
    """Whether c is more than 0.5 m from every one of ``points`` (a viewpoint of its own)."""
    return all(math.dist(c, q) > 0.5 for q in points)
