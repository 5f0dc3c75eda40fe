"""The map's facts remembered per floor (RoomMap._Floor): whatever was asked before, the facts for
a placement are those a fresh map gives for it. The robot moving, an item taken away, a grasp
pose kept (sticky) or avoided, a drawer out: each answer checked against a new RoomMap."""

from __future__ import annotations

import random
from dataclasses import replace

import pytest

from sim.grid import Box
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import Placed
from tidyplan.generate.rooms import generate


def _placed(scenario) -> list[Placed]:
    return sorted(
        (Placed(i.name, i.category, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items), key=lambda p: p.name
    )


class Walk:
    """A belief's floor taking one change at a time, drawn from ``rng``: an item seen (one of
    ``everything`` not on the floor yet), moved a few centimetres or across the room, or taken
    away; a grasp pose to avoid (one kept before); a drawer pulled out or pushed in. ``keep``
    takes the poses just chosen as the ones kept (sticky), as the belief does."""

    def __init__(self, items, free, rng, everything=()) -> None:
        self.items, self.free, self.rng, self.everything = list(items), free, rng, list(everything)
        self.sticky: dict = {}
        self.avoid: dict = {}
        self.out: tuple[Box, ...] = ()

    def change(self, what: str, turn: int) -> None:
        rng, items = self.rng, self.items
        if what == "see":
            unseen = [p for p in self.everything if p.name not in {q.name for q in items}]
            if unseen:
                self.items = sorted([*items, rng.choice(unseen)], key=lambda p: p.name)
        elif what == "take" and items:
            self.items = [p for p in items if p is not rng.choice(items)]
        elif what == "shift" and items:
            # the belief corrects where an item lies: a few centimetres, or across the room
            p = rng.choice(items)
            x, y = (
                (p.x + rng.uniform(-0.1, 0.1), p.y + rng.uniform(-0.1, 0.1))
                if turn % 2
                else rng.choice(self.free)
            )
            self.items = [replace(q, x=x, y=y) if q is p else q for q in items]
        elif what == "avoid" and self.sticky:
            # the robot failed to find an item from the pose it was to grasp it from
            name = rng.choice(sorted(self.sticky))
            self.avoid = {**self.avoid, name: [*self.avoid.get(name, []), self.sticky[name]]}
        elif what == "drawer":
            x, y = rng.choice(self.free)
            self.out = () if self.out else (Box(x, y, 0.4, 0.3, "drawer-top"),)

    def keep(self, got) -> None:
        self.sticky.update((item, got.points[wp]) for item, wp in got.grasp.items())


def crowded(seed: int, part: int):
    """Two rooms crowded with items (ten of each category in each room), a walk over them from
    the first 1/``part`` of their items, and what it draws from: (scenario, room, free cells
    the robot reaches, the walk, its random numbers)."""
    scenario = generate("two", seed, per_room=10)
    rng = random.Random(seed)
    room = RoomMap(scenario)
    everything = _placed(scenario)
    free = room.grid(()).free_cells(reachable_from=room.entrance)
    return scenario, room, free, Walk(everything[: len(everything) // part], free, rng, everything), rng


@pytest.mark.parametrize("seed", [0, 3, 7])
def test_facts_after_moves_takes_and_drawers_are_those_of_a_fresh_map(seed):
    scenario = generate("one", seed)
    rng = random.Random(seed)
    room = RoomMap(scenario)
    free = room.grid(()).free_cells(reachable_from=room.entrance)
    nav = room.grid(())
    tight = [c for c in room.grid((), bare=True).free_cells() if not nav.free(*c)]
    walk = Walk(_placed(scenario), free, rng)
    for turn in range(12):
        what = rng.choice(["move", "move", "take", "avoid", "drawer"])
        walk.change(what, turn)
        # now and then left in a tight pose the navigation grid has not free (it backs out)
        robot = (f"wp-robot-{turn}", rng.choice(tight if turn % 4 == 3 else free))
        got = room.facts(walk.items, robot, dict(walk.sticky), walk.avoid, walk.out)
        want = RoomMap(scenario).facts(walk.items, robot, dict(walk.sticky), walk.avoid, walk.out)
        assert got == want, f"turn {turn} ({what})"
        walk.keep(got)


def test_a_move_alone_works_out_only_the_robots_own_waypoint(monkeypatch):
    """What makes the loop's time per action flat in the room's size: after a move on the same
    floor, no grasp pose is chosen again and no blocked pair's blockers are searched again but
    the robot's own."""
    scenario = generate("one", 1)
    room = RoomMap(scenario)
    items = _placed(scenario)
    free = room.grid(()).free_cells(reachable_from=room.entrance)
    room.facts(items, ("wp-robot", free[0]))
    grasps, searched, pairs_of = [], [], []
    add_grasp, find, fixed = room.grasps._add_grasp, room._find_blockers, room._fixed_paths
    monkeypatch.setattr(room.grasps, "_add_grasp", lambda *a, **k: grasps.append(a[1]) or add_grasp(*a, **k))
    monkeypatch.setattr(room, "_fixed_paths", lambda part, *a: pairs_of.append(part) or fixed(part, *a))
    monkeypatch.setattr(
        room, "_find_blockers", lambda items, pairs, memo: searched.extend(pairs) or find(items, pairs, memo)
    )
    moved = free[len(free) // 2]
    facts = room.facts(items, ("wp-robot", moved))
    assert grasps == []
    assert pairs_of == []  # the pairs of the waypoints that did not move were kept
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


def _tight_deposit(scenario):
    """The scenario with its first deposit approached from a cell the bare base fits but the
    navigation grid (with its margin) does not: the deposit gets a pose adjustment."""
    import dataclasses

    room = RoomMap(scenario)
    nav, bare = room.grid(()), room.grid((), bare=True)
    d = scenario.deposits[0]
    tight = sorted(
        (c for c in bare.free_cells(reachable_from=room.entrance) if not nav.free(*c)),
        key=lambda c: (abs(c[0] - d.x) + abs(c[1] - d.y), c),
    )
    deposits = (dataclasses.replace(d, approach=tight[0]), *scenario.deposits[1:])
    return dataclasses.replace(scenario, deposits=deposits)


@pytest.mark.parametrize("seed", [0, 2, 5])
def test_the_robots_pairs_are_its_paths_both_ways_to_every_waypoint(seed):
    """The robot's own pairs (worked out apart from the kept ones): for every other waypoint, a
    path each way of the navigation grid's length where one exists, else blocked where the
    static map has one; a robot in a tight pose backs out by a pose adjustment; a deposit's pose
    adjustment is joined to the robot both ways."""
    scenario = _tight_deposit(generate("one", seed))
    rng = random.Random(seed)
    room = RoomMap(scenario)
    items = _placed(scenario)
    nav0 = room.grid(())
    tight = [
        c for c in room.grid((), bare=True).free_cells(reachable_from=room.entrance) if not nav0.free(*c)
    ]
    free = nav0.free_cells(reachable_from=room.entrance)
    deposit_wp = next(
        n for n, k in room.fixed_kind.items() if k == "deposit" and scenario.deposits[0].name in n
    )
    base_of_deposit = f"{deposit_wp}-base"
    for turn, at in enumerate([rng.choice(free), rng.choice(tight), rng.choice(free)]):
        r = f"wp-robot-{turn}"
        facts = room.facts(items, (r, at))
        nav = room.grid([p.box() for p in items if p.on_floor])
        static = room.grid(())
        assert facts.kind[base_of_deposit] == "adjust"
        for n in facts.points:
            if n == r or facts.kind[n] == "adjust":
                continue
            for pair in ((r, n), (n, r)):
                length, later = (
                    nav.path_length(*(facts.points[x] for x in pair)),
                    static.path_length(*(facts.points[x] for x in pair)),
                )
                if pair[1] in facts.reach_blockers:
                    continue  # entered only once what its reach crosses is gone: blocked
                if length is not None:
                    assert facts.path[pair] == round(length, 2), pair
                elif later is not None:
                    assert facts.blocked[pair] == round(later, 2), pair
                    assert any(t[1:] == pair for t in facts.blocks), f"{pair}: blocked by nothing"
                else:
                    assert pair not in facts.path and pair not in facts.blocked, pair
        length = nav.path_length(at, facts.points[base_of_deposit])
        if length is not None:
            assert facts.path[(r, base_of_deposit)] == facts.path[(base_of_deposit, r)] == round(length, 2)
        if not nav.free(*at):
            assert facts.kind[f"{r}-base"] == "adjust"
            assert (f"{r}-base", r) in facts.adjust and (r, f"{r}-base") in facts.adjust


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_facts_as_items_are_seen_on_a_crowded_floor_are_those_of_a_fresh_map(seed):
    """Items seen a few at a time, moved and taken, on two rooms' floor crowded enough that paths
    are blocked by several items at once: the items near a blocked path, asked again only of
    the items seen since (``RoomMap._near``), are those a fresh map finds among them all."""
    scenario, room, free, walk, rng = crowded(seed, 3)
    blocks = 0
    for turn in range(14):
        walk.change(rng.choice(["move", "see", "see", "see", "take", "shift"]), turn)
        robot = (f"wp-robot-{turn}", rng.choice(free))
        got = room.facts(walk.items, robot, dict(walk.sticky), walk.avoid, walk.out)
        want = RoomMap(scenario).facts(walk.items, robot, dict(walk.sticky), walk.avoid, walk.out)
        assert got == want, f"turn {turn}"
        walk.keep(got)
        # every blocked pair waits for some item: one that frees it alone, else those near its
        # path (the fresh map above answers with the same code; this it cannot share)
        waits = {(a, b) for _item, a, b in got.blocks}
        assert set(got.blocked) <= waits, f"turn {turn}"
        blocks += len(got.blocks)
    assert blocks  # some path was blocked: the test is of something


@pytest.mark.parametrize("seed", [0, 4])
def test_an_item_taken_from_furniture_searches_no_blocked_pair_again(monkeypatch, seed):
    """A blocked pair's blockers depend on the floor items and the open drawers alone: a floor
    that differs from the last only off the floor (an item taken from a table) searches none
    again, and its facts are a fresh map's."""
    scenario, room, free, walk, _rng = crowded(seed, 1)
    robot = ("wp-robot", free[0])
    before = room.facts(walk.items, robot)
    assert before.blocks  # a crowded floor: pairs only a floor item's removal joins
    taken = next(p for p in walk.items if not p.on_floor)
    rest = [p for p in walk.items if p is not taken]
    searched = []
    find = room._find_blockers
    monkeypatch.setattr(
        room, "_find_blockers", lambda items, pairs, memo: searched.extend(pairs) or find(items, pairs, memo)
    )
    facts = room.facts(rest, robot)
    # only a pair with a point new to the facts (a grasp pose chosen again: the taken item's
    # pose no longer rules out ring cells near it) is searched
    known = set(before.points.values())
    assert all(a not in known or b not in known for a, b in searched)
    assert facts == RoomMap(scenario).facts(rest, robot)
    # a floor item taken is another floor: its pairs are searched
    floor_item = next(p for p in rest if p.on_floor)
    room.facts([p for p in rest if p is not floor_item], robot)
    assert searched


def test_a_move_within_a_component_asks_no_floor_item_again(monkeypatch):
    """Which single floor item joins a blocked pair depends on the components its two ends are
    in: after a move that stays in the robot's component, its new pairs are of kinds already
    answered on this floor, so no floor item is taken away again (``joins_without``), and the
    facts are a fresh map's."""
    import tidyplan.belief.geometry as geometry

    scenario, room, free, walk, _rng = crowded(0, 1)
    items = walk.items
    first = room.facts(items, ("wp-robot", free[0]))
    assert any(a == "wp-robot" or b == "wp-robot" for _item, a, b in first.blocks)  # blocked pairs
    nav = room._floor_of(items).grids[1]
    here = nav.component(*free[0])
    there = next(c for c in reversed(free) if c != free[0] and nav.component(*c) == here)
    asked = []
    joins = geometry.joins_without
    monkeypatch.setattr(geometry, "joins_without", lambda *a: asked.append(a[1]) or joins(*a))
    facts = room.facts(items, ("wp-robot", there))
    assert asked == []
    assert any(a == "wp-robot" or b == "wp-robot" for _item, a, b in facts.blocks)
    assert facts == RoomMap(scenario).facts(items, ("wp-robot", there))


@pytest.mark.parametrize("seed", [0, 1])
def test_an_item_put_aside_is_not_one_a_pair_no_single_item_frees_waits_for(seed):
    """A pair no single floor item frees waits for every item near its path (any one taken, the
    planner believes it open; the replan after sees it is not). An item the robot put aside is
    not one of them (listed, it was taken and put aside again, over and over, in a crowded
    room); one that alone frees a pair still is."""
    scenario = generate("two", seed, per_room=10)
    items = _placed(scenario)
    facts = RoomMap(scenario).facts(items)
    waits: dict[tuple[str, str], list[str]] = {}
    for item, a, b in sorted(facts.blocks):
        waits.setdefault((a, b), []).append(item)
    without: dict[str, object] = {}

    def frees(item: str, pair) -> bool | None:
        """Whether taking ``item`` alone opens ``pair`` (None: the pair's ends moved)."""
        if item not in without:
            without[item] = RoomMap(scenario).facts([p for p in items if p.name != item])
        other = without[item]
        if any(other.points.get(w) != facts.points[w] for w in pair):
            return None
        return pair not in other.blocked

    all_must_go = alone = None
    for pair, who in sorted(waits.items(), key=lambda kv: len(kv[1])):
        if alone is None and len(who) == 1 and frees(who[0], pair):
            alone = (pair, who[0])
        if all_must_go is None and len(who) >= 2 and frees(who[0], pair) is False:
            all_must_go = (pair, who)
        if alone and all_must_go:
            break
    assert alone and all_must_go, "the crowded floor has both kinds of blocked pair"

    (pair, who), (single_pair, single) = all_must_go, alone
    put_aside = {who[0], single}
    marked = [replace(p, aside=True) if p.name in put_aside else p for p in items]
    after = RoomMap(scenario).facts(marked)
    assert pair in after.blocked
    assert (who[0], *pair) not in after.blocks
    assert all((w, *pair) in after.blocks for w in who[1:] if w not in put_aside)
    assert (single, *single_pair) in after.blocks  # taken alone it opens the pair: still listed
