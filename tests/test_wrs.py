"""bench/wrs.py: seeded WRS rooms follow the spawner's rules (docs/sources.md) and load as scenarios.

The rules are checked here from the files written, with their own arithmetic, not the
generator's helpers: zone counts, categories, 0.2 m spacing, clearance from furniture, the
dividing wall's opening and the dining table's free floor.
"""

from __future__ import annotations

import itertools
import math
import re
from collections import Counter
from pathlib import Path

import pytest

from sim.scenario.model import FLOOR
from sim.scenario.read import load
from tidyplan.generate import rooms as wrs  # noqa: E402

SEEDS = range(6)
CASE1 = load(Path(__file__).parent.parent / "problems" / "case1.toml")
CATEGORIES = {"food", "kitchen", "tool", "task"}
# the WRS world's spawn zones in room 1: support -> (x0, x1, y0, y1, objects)
ZONES = {
    "floor": (-1.0, -0.4, -0.35, 1.35, 6),
    "long-table": (-0.45, -0.2, -0.35, 0.7, 4),
    "tall-table": (-0.45, -0.2, 1.0, 1.35, 2),
}


@pytest.fixture(scope="module")
def rooms(tmp_path_factory):
    """(layout, seed) -> the scenario as loaded from the file the script wrote."""
    out = tmp_path_factory.mktemp("wrs")
    for layout in ("one", "two"):
        args = ["--layout", layout, "--rooms", str(len(SEEDS)), "--first-seed", str(SEEDS[0])]
        assert wrs.main([*args, "--out", str(out)]) == 0
    return {(lay, s): load(out / wrs.file_name(lay, s)) for lay in ("one", "two") for s in SEEDS}


def _cases():
    return [(lay, s) for lay in ("one", "two") for s in SEEDS]


def _edges(f):
    return f.cx - f.sx / 2, f.cx + f.sx / 2, f.cy - f.sy / 2, f.cy + f.sy / 2


def _gap(a, b) -> float:
    """Distance between two footprints (0 when they touch or overlap)."""
    ax0, ax1, ay0, ay1 = a
    bx0, bx1, by0, by1 = b
    return math.hypot(max(bx0 - ax1, ax0 - bx1, 0.0), max(by0 - ay1, ay0 - by1, 0.0))


def _overlaps(a, b) -> bool:
    return a[0] < b[1] and b[0] < a[1] and a[2] < b[3] and b[2] < a[3]


@pytest.mark.parametrize("key", _cases())
def test_three_of_each_category_per_room_and_the_prior_says_so(rooms, key):
    s = rooms[key]
    per_room = {"one": 1, "two": 2}[key[0]]
    assert len(s.items) == 12 * per_room
    assert Counter(i.category for i in s.items) == {c: 3 * per_room for c in CATEGORIES}
    assert s.prior_counts() == {c: 3 * per_room for c in CATEGORIES}
    room1 = [i for i in s.items if i.x < 0.5]
    assert Counter(i.category for i in room1) == {c: 3 for c in CATEGORIES}
    assert s.expect.unobservable_items == () and s.expect.unreachable_items == ()
    # lettered, never like the belief's names for what it sees (food-1, ...)
    assert all(re.fullmatch(r"(food|kitchen|tool|task)-[a-f]", i.name) for i in s.items)


@pytest.mark.parametrize("key", _cases())
def test_room1_objects_half_floor_third_long_table_sixth_tall_table_within_the_zones(rooms, key):
    room1 = [i for i in rooms[key].items if i.x < 0.5]
    assert Counter(i.on for i in room1) == {on: z[4] for on, z in ZONES.items()}
    for i in room1:
        x0, x1, y0, y1, _ = ZONES[i.on]
        assert x0 <= i.x <= x1 and y0 <= i.y <= y1, i


@pytest.mark.parametrize("key", _cases())
def test_every_two_objects_are_at_least_0_2_m_apart(rooms, key):
    for a, b in itertools.combinations(rooms[key].items, 2):
        assert math.dist((a.x, a.y), (b.x, b.y)) >= 0.2 - 1e-9, (a.name, b.name)


@pytest.mark.parametrize("key", _cases())
def test_floor_objects_keep_a_few_cm_from_furniture_and_table_objects_stay_on_the_top(rooms, key):
    s = rooms[key]
    for i in s.items:
        box = (i.x - i.sx / 2, i.x + i.sx / 2, i.y - i.sy / 2, i.y + i.sy / 2)
        assert 0.05 <= i.sx <= 0.10 and 0.05 <= i.sy <= 0.10 and 0.05 <= i.sz <= 0.15, i
        if i.on == FLOOR:
            assert all(_gap(box, _edges(f)) >= 0.03 for f in s.furniture), i
            x0, x1, y0, y1 = s.bounds
            assert x0 + 0.03 <= box[0] and box[1] <= x1 - 0.03 and y0 + 0.03 <= box[2] and box[3] <= y1 - 0.03
        else:
            edge = 0.05 if i.on == "dining-table" else 0.0
            t = _edges(s.furniture_named(i.on))
            assert t[0] + edge <= box[0] + 1e-9 and box[1] <= t[1] - edge + 1e-9, i
            assert t[2] + edge <= box[2] + 1e-9 and box[3] <= t[3] - edge + 1e-9, i


@pytest.mark.parametrize("seed", SEEDS)
def test_layout_one_is_case1_without_its_items(rooms, seed):
    s = rooms[("one", seed)]
    for key in (
        "bounds",
        "entrance",
        "heading_deg",
        "furniture",
        "deposits",
        "viewpoints",
        "robot",
        "sensing",
    ):
        assert getattr(s, key) == getattr(CASE1, key), key


@pytest.mark.parametrize("seed", SEEDS)
def test_layout_two_joins_the_dining_room_through_a_1_2_m_opening(rooms, seed):
    s = rooms[("two", seed)]
    assert s.bounds == (-3.0, 3.3, -2.0, 2.0)
    assert (s.furniture[: len(CASE1.furniture)], s.deposits, s.viewpoints) == (
        CASE1.furniture,
        CASE1.deposits,
        CASE1.viewpoints,
    )
    assert all(v.x < 0.5 for v in s.viewpoints)  # the dining room has none, on purpose
    walls = sorted((f for f in s.furniture if f.kind == "wall"), key=lambda f: f.cy)
    assert len(walls) == 2 and all(f.height == 2.0 for f in walls)
    (sx0, sx1, sy0, sy1), (nx0, nx1, ny0, ny1) = (_edges(w) for w in walls)
    assert all(math.isclose(a, b, abs_tol=1e-9) for a, b in ((sx0, 0.5), (sx1, 0.8), (nx0, 0.5), (nx1, 0.8)))
    assert math.isclose(sy0, -2.0) and math.isclose(ny1, 2.0)
    assert math.isclose(ny0 - sy1, 1.2, abs_tol=1e-6) and sy1 >= -2.0 + 0.3 - 1e-9 and ny0 <= 2.0 - 0.3 + 1e-9
    table = s.furniture_named("dining-table")
    assert (table.sx, table.sy, table.height, table.kind) == (0.8, 1.2, 0.7, "table")
    tx0, tx1, ty0, ty1 = _edges(table)
    assert min(tx0 - 0.8, 3.3 - tx1, ty0 + 2.0, 2.0 - ty1) >= 0.7 - 1e-9  # free floor around it
    dining = [i for i in s.items if i.x > 0.8]
    assert len(dining) == 12 and Counter(i.on for i in dining) == {FLOOR: 6, "dining-table": 6}
    assert Counter(i.category for i in dining) == {c: 3 for c in CATEGORIES}
    for i in dining:  # clear of the doorway behind the opening
        box = (i.x - i.sx / 2, i.x + i.sx / 2, i.y - i.sy / 2, i.y + i.sy / 2)
        assert not _overlaps(box, (0.8, 1.6, sy1, ny0)), i


def test_the_entrance_door_stays_in_the_wall_at_y_minus_2(rooms):
    # sim/room.py puts the door in the outer wall nearest the entrance
    for s in (rooms[("one", 0)], rooms[("two", 0)]):
        (x0, x1, y0, y1), (ex, ey) = s.bounds, s.entrance
        gaps = {"south": ey - y0, "north": y1 - ey, "west": ex - x0, "east": x1 - ex}
        assert min(gaps, key=gaps.get) == "south" and y0 == -2.0


def test_room1_of_layout_two_is_layout_one_of_the_same_seed(rooms):
    for seed in SEEDS:
        one, two = rooms[("one", seed)], rooms[("two", seed)]
        assert one.items == tuple(i for i in two.items if i.x < 0.5)


def test_the_same_seed_gives_the_same_file_and_seeds_differ():
    for layout in ("one", "two"):
        texts = [wrs.dumps(wrs.generate(layout, seed)) for seed in (0, 0, 1)]
        assert texts[0] == texts[1] != texts[2]


def test_wall_height_option_and_refusing_to_overwrite(tmp_path, capsys):
    args = ["--layout", "two", "--rooms", "1", "--out", str(tmp_path)]
    assert wrs.main([*args, "--wall-height", "0.6"]) == 0
    assert {f.height for f in load(tmp_path / "wrs-two-s000.toml").furniture if f.kind == "wall"} == {0.6}
    capsys.readouterr()
    with pytest.raises(SystemExit) as e:
        wrs.main(args)
    err = capsys.readouterr().err
    assert e.value.code == 2 and len(err.splitlines()) == 1 and "--force" in err
    assert wrs.main([*args, "--force"]) == 0
    assert {f.height for f in load(tmp_path / "wrs-two-s000.toml").furniture if f.kind == "wall"} == {2.0}


@pytest.mark.parametrize(
    "bad",
    [
        ["--layout", "three"],
        ["--layout", "one", "--rooms", "0"],
        ["--layout", "one", "--first-seed", "-1"],
        ["--layout", "one", "--wall-height", "1"],
        ["--layout", "two", "--wall-height", "0"],
        ["--layout", "two", "--wall-height", "nan"],
        ["--layout", "one", "--rooms", "x"],
    ],
)
def test_bad_options_exit_2_with_one_message(tmp_path, capsys, bad):
    with pytest.raises(SystemExit) as e:
        wrs.main([*bad, "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert e.value.code == 2 and len(err.splitlines()) == 1 and err.startswith("wrs.py: "), err
    assert not list(tmp_path.iterdir())


# ---------------------------------------------------------------------- WRS Task 1
TASK1_SEEDS = range(10)


@pytest.fixture(scope="module")
def task1_rooms():
    return {seed: wrs.task1(seed) for seed in TASK1_SEEDS}


def test_task1_rooms_hold_30_objects_5_known_of_each_category_and_an_unknown_one_each(task1_rooms):
    for seed, s in task1_rooms.items():
        assert len(s.items) == 30, seed
        known = Counter(i.category for i in s.items if not i.unknown)
        unknown = Counter(i.category for i in s.items if i.unknown)
        assert known == {c: 5 for c in wrs.TASK1_CATEGORIES}, seed
        assert unknown == {c: 1 for c in wrs.TASK1_CATEGORIES}, seed
        assert dict(s.prior) == {**{c: 5 for c in wrs.TASK1_CATEGORIES}, "unknown": 5}
        assert all(i.name.startswith("unknown-") == i.unknown for i in s.items)


def test_task1_objects_keep_the_spawners_rules(task1_rooms):
    for seed, s in task1_rooms.items():
        for a, b in itertools.combinations(s.items, 2):
            assert math.dist((a.x, a.y), (b.x, b.y)) >= wrs.SPACING - 1e-9, (seed, a.name, b.name)
        for i in s.items:
            if i.on != FLOOR:
                f = s.furniture_named(i.on)
                assert (
                    abs(i.x - f.cx) + i.sx / 2 <= f.sx / 2 + 1e-9
                    and abs(i.y - f.cy) + i.sy / 2 <= f.sy / 2 + 1e-9
                )


def test_the_shipped_task1_room_is_the_generators_seed_0_and_loads():
    from tidyplan.loop.scenarios import load_scenario

    shipped = load_scenario("wrs-task1")
    assert shipped.items == wrs.task1(0).items and shipped.prior == wrs.task1(0).prior
    drawers = [d.name for d in shipped.deposits if d.drawer]
    assert drawers == ["drawer-left", "drawer-bottom", "drawer-top"]
    assert {d.category for d in shipped.deposits} == {*wrs.TASK1_CATEGORIES, "unknown", "orientation"}
    box = next(d for d in shipped.deposits if d.category == "orientation")
    assert box.name == "container-b" and box.container == (0.095, 0.095, 0.105)


def test_task1_rooms_hold_the_four_orientation_items_each_fitting_where_it_lies(task1_rooms):
    for seed, s in task1_rooms.items():
        oriented = {i.name: i for i in s.items if i.orientation is not None}
        assert sorted(oriented) == ["fork", "marker-large", "marker-small", "spoon"], seed
        assert {i.category for i in oriented.values()} == {"tool", "kitchen"}
        assert not any(i.unknown for i in oriented.values())
        for i in oriented.values():
            length = max(i.sx, i.sy)
            assert length >= 0.1 and abs(i.orientation.axis[0 if i.sx > i.sy else 1]) == 1.0
            for o in s.items:
                if o is not i and o.on == i.on:
                    apart = abs(i.x - o.x) >= (i.sx + o.sx) / 2 or abs(i.y - o.y) >= (i.sy + o.sy) / 2
                    assert apart, (seed, i.name, o.name)


def test_task1_rooms_write_and_read_back(tmp_path, task1_rooms):
    for seed in (0, 7):
        target = tmp_path / wrs.file_name("task1", seed)
        wrs.write(task1_rooms[seed], target)
        assert load(target).items == task1_rooms[seed].items
