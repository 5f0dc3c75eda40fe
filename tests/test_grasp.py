"""tidyplan.belief.grasp: each item's grasp pose, chosen again only near what changed, and the
ring's sums done at once giving what they gave cell by cell."""

from __future__ import annotations

import random

from sim.grid import Box
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import Placed
from tidyplan.generate.rooms import generate


def _placed(scenario) -> list[Placed]:
    return sorted(
        (Placed(i.name, i.category, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items), key=lambda p: p.name
    )


def test_an_item_taken_away_chooses_again_only_the_poses_near_it(monkeypatch):
    """After a floor item is taken, only items whose ring or neighbourhood it touched have their
    pose chosen anew (not every item of the room), and the poses are a fresh map's."""
    scenario = generate("two", 0, per_room=6)
    room = RoomMap(scenario)
    items = _placed(scenario)
    robot = ("wp-robot", room.entrance)
    room.poses(items, robot)
    chosen = []
    add_grasp = room.grasps._add_grasp
    monkeypatch.setattr(
        room.grasps, "_add_grasp", lambda *a, **k: chosen.append(a[1].name) or add_grasp(*a, **k)
    )
    on_floor = [p for p in items if p.on_floor]
    gone = on_floor[len(on_floor) // 2]
    after = [p for p in items if p is not gone]
    got = room.poses(after, robot)
    assert got == RoomMap(scenario).poses(after, robot)
    assert chosen and len(chosen) < len(after) / 2, (len(chosen), len(after))


def test_the_cells_whose_reach_crosses_a_box_are_those_found_one_by_one():
    """_crossing_cells samples every cell's reach at once; it finds what _crosses finds cell by
    cell, boxes whose sides lie on the samples themselves included (a grid of 5 cm cells)."""
    import numpy as np

    from tidyplan.belief.grasp import _crosses, _crossing_cells

    rng = random.Random(3)
    found = 0
    for _ in range(600):
        at = (0.025 + 0.05 * rng.randrange(20, 60), 0.025 + 0.05 * rng.randrange(20, 40))
        ring = [
            (at[0] + 0.05 * rng.randrange(-13, 14), at[1] + 0.05 * rng.randrange(-13, 14)) for _ in range(30)
        ]
        # sides on the cells' centres half the time: a sample on the edge counts as on the box
        cx, cy = at[0] + 0.05 * rng.randrange(-8, 9), at[1] + 0.05 * rng.randrange(-8, 9)
        sx, sy = (
            (0.1 * rng.randrange(1, 5), 0.1 * rng.randrange(1, 5))
            if rng.random() < 0.5
            else (rng.uniform(0.02, 0.4), rng.uniform(0.02, 0.4))
        )
        box = Box(cx, cy, sx, sy, "b")
        cells = np.arange(len(ring))
        want = tuple(k for k in range(len(ring)) if _crosses(ring[k], at, box))
        assert _crossing_cells(ring, cells, at, box) == want
        found += len(want)
    assert found  # some reach crossed a box: the test is of something
