"""The map's facts remembered per floor (RoomMap._Floor): whatever was asked before, the facts for
a placement are those a fresh map gives for it. The robot moving, an item taken away, a grasp
pose kept (sticky) or avoided, a drawer out: each answer checked against a new RoomMap."""

from __future__ import annotations

import random

import pytest

from sim.grid import Box
from tidyplan.belief.geometry import Placed, RoomMap
from tidyplan.generate.rooms import generate


def _placed(scenario) -> list[Placed]:
    return sorted(
        (Placed(i.name, i.category, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items), key=lambda p: p.name
    )


@pytest.mark.parametrize("seed", [0, 3, 7])
def test_facts_after_moves_takes_and_drawers_are_those_of_a_fresh_map(seed):
    scenario = generate("one", seed)
    rng = random.Random(seed)
    room = RoomMap(scenario)
    items = _placed(scenario)
    free = room.grid(()).free_cells(reachable_from=room.entrance)
    sticky: dict = {}
    avoid: dict = {}
    out: tuple[Box, ...] = ()
    for turn in range(12):
        what = rng.choice(["move", "move", "take", "avoid", "drawer"])
        if what == "take" and items:
            items = [p for p in items if p is not rng.choice(items)]
        elif what == "avoid" and sticky:
            # the robot failed to find an item from the pose it was to grasp it from
            name = rng.choice(sorted(sticky))
            avoid = {**avoid, name: [*avoid.get(name, []), sticky[name]]}
        elif what == "drawer":
            x, y = rng.choice(free)
            out = () if out else (Box(x, y, 0.4, 0.3, "drawer-top"),)
        robot = (f"wp-robot-{turn}", rng.choice(free))
        got = room.facts(items, robot, dict(sticky), avoid, out)
        want = RoomMap(scenario).facts(items, robot, dict(sticky), avoid, out)
        assert got == want, f"turn {turn} ({what})"
        sticky.update((item, got.points[wp]) for item, wp in got.grasp.items())


def test_a_move_alone_works_out_only_the_robots_own_waypoint(monkeypatch):
    """What makes the loop's time per action flat in the room's size: after a move on the same
    floor, no grasp pose is chosen again and no blocked pair's blockers are searched again but
    the robot's own."""
    scenario = generate("one", 1)
    room = RoomMap(scenario)
    items = _placed(scenario)
    free = room.grid(()).free_cells(reachable_from=room.entrance)
    room.facts(items, ("wp-robot", free[0]))
    grasps, searched = [], []
    add_grasp, find = room._add_grasp, room._find_blockers
    monkeypatch.setattr(room, "_add_grasp", lambda *a, **k: grasps.append(a[1]) or add_grasp(*a, **k))
    monkeypatch.setattr(
        room, "_find_blockers", lambda items, pairs, memo: searched.extend(pairs) or find(items, pairs, memo)
    )
    moved = free[len(free) // 2]
    facts = room.facts(items, ("wp-robot", moved))
    assert grasps == []
    assert all(moved in pair for pair in searched)
    assert facts == RoomMap(scenario).facts(items, ("wp-robot", moved))


@pytest.mark.parametrize("seed", range(6))
def test_the_items_near_a_path_are_those_a_distance_to_each_of_its_cells_finds(seed):
    """_near_paths (one gather over the paths' cells) against the plain test it replaced: each
    floor item whose distance to some cell centre of the static path is under the radius + 0.1.
    Items scattered over the room, some on the paths themselves; pairs with no path too."""
    import numpy as np

    scenario = generate("one" if seed % 2 else "two", seed)
    rng = random.Random(seed)
    room = RoomMap(scenario)
    static = room.grid(())
    free = static.free_cells()
    floor = []
    for k in range(60):
        x, y = rng.choice(free)  # on a cell centre (distances on the grid's steps) or off it
        dx, dy = (rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03)) if k % 2 else (0.0, 0.0)
        floor.append(Placed(f"thing-{k}", "food", x + dx, y + dy, "floor", 0.1, 0.1))
    r = room.nav_radius + 0.1
    cells = static.free_cells(reachable_from=room.entrance)
    pairs = [(rng.choice(cells), rng.choice(cells)) for _ in range(150)]
    pairs += [(rng.choice(free), rng.choice(free)) for _ in range(50)]  # some in other components
    pairs.append((cells[0], cells[0]))
    got = room._near_paths(static, floor, pairs)
    assert got.shape == (len(pairs), len(floor))
    for n, (a, b) in enumerate(pairs):
        line = static.path(a, b) or []
        for k, p in enumerate(floor):
            want = any(float(np.hypot(p.x - q[0], p.y - q[1])) < r for q in line)
            assert bool(got[n, k]) == want, (n, k)
    assert got.any() and not got.all()
