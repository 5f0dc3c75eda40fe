"""sim.grid: free space, inflation, path lengths and the tidygen problems built on them."""

import hashlib
import itertools
import math
import random

import numpy as np
import pytest

from sim.grid import Box, OccupancyGrid
from sim.joins import joins_without, pair_cells
from tidyplan.generate import tasks as tidygen  # noqa: E402

ROOM = (0.0, 4.0, 0.0, 3.0)  # 80 x 60 cells of 5 cm
R = 0.22


def octile(grid: OccupancyGrid, a, b) -> float:
    """The 8-connected grid distance between the cells of a and b: diagonal steps, then straight."""
    (ai, aj), (bi, bj) = grid.cell(*a), grid.cell(*b)
    di, dj = abs(ai - bi), abs(aj - bj)
    return grid.cell_size * (math.sqrt(2) * min(di, dj) + abs(di - dj))


@pytest.fixture(scope="module")
def empty() -> OccupancyGrid:
    return OccupancyGrid(ROOM)


@pytest.fixture(scope="module")
def with_box() -> OccupancyGrid:
    return OccupancyGrid(ROOM, [Box(2.0, 1.5, 0.4, 0.4, "table")])


def test_cell_and_xy_are_inverse(empty):
    assert empty.cell(*empty.xy(7, 11)) == (7, 11)
    assert empty.xy(0, 0) == pytest.approx((0.025, 0.025))
    assert empty.shape == (80, 60)


def test_walls_are_inflated_by_the_robot_radius(empty):
    assert not empty.free(0.175, 1.525)  # centre 0.175 m from the wall: the base would touch it
    assert empty.free(0.225, 1.525)  # 0.225 m: just clear
    assert not empty.free(-1.0, 1.0)  # outside the room
    assert empty.free(2.0, 1.5)


def test_a_point_inside_an_inflated_box_is_not_free_and_one_just_outside_is(with_box):
    # the box spans x in [1.8, 2.2]; inflated by 0.22 m it reaches 1.58 and 2.42
    assert not with_box.free(2.0, 1.5)  # inside the box itself
    assert not with_box.free(1.625, 1.525)  # 0.175 m from the face: inside the inflation
    assert with_box.free(1.575, 1.525)  # 0.225 m from the face: just outside
    assert not with_box.free(2.375, 1.525)
    assert with_box.free(2.425, 1.525)
    # past a corner the inflation is round: 0.2 m off both faces is 0.28 m away, so free
    assert with_box.free(1.625, 1.875)  # 0.175 m off both faces at the corner (1.8, 1.7)


def test_empty_room_path_length_is_the_8_connected_distance_near_euclid(empty):
    # An 8-connected path overshoots the straight line by at most 1/sqrt(2 - sqrt(2)) - 1, about
    # 8.2 %, at 22.5 degrees off an axis; along an axis or a diagonal it is exact.
    a = empty.xy(10, 10)
    for far, within in (((60, 10), 1e-9), ((50, 50), 1e-9), ((60, 55), 0.03), ((60, 30), 0.0824)):
        b = empty.xy(*far)
        length = empty.path_length(a, b)
        assert length == pytest.approx(octile(empty, a, b))
        assert math.dist(a, b) - 1e-9 <= length <= math.dist(a, b) * (1 + within) + 1e-9


def test_path_is_a_cell_centre_polyline_of_the_path_length(empty):
    a, b = empty.xy(10, 10), empty.xy(40, 25)
    path = empty.path(a, b)
    assert path[0] == a and path[-1] == b
    assert sum(math.dist(p, q) for p, q in zip(path, path[1:], strict=False)) == pytest.approx(
        empty.path_length(a, b)
    )
    assert all(empty.free(*p) for p in path)


def test_a_wall_of_boxes_makes_the_far_side_unreachable():
    wall = [Box(2.0, 0.25 + 0.5 * k, 0.1, 0.5) for k in range(6)]  # x = 2, across the whole room
    grid = OccupancyGrid(ROOM, wall)
    a, b = (1.0, 1.5), (3.0, 1.5)
    assert grid.free(*a) and grid.free(*b)
    assert grid.path_length(a, b) is None
    assert grid.path(a, b) is None
    assert grid.path_lengths([a, b]) == [[0, None], [None, 0]]
    assert grid.nearest_free(2.9, 1.5, reachable_from=a)[0] < 2.0  # snapped to a's side


def test_a_box_put_down_is_ranked_by_how_many_points_the_robot_still_reaches():
    """Where an item goes down (``put_down``): the points the robot still reaches with it on the
    floor, counted (a spot that shuts one way beats one that shuts two), -1 on the robot's cell."""
    wall = [Box(2.0, 0.25 + 0.5 * k, 0.1, 0.5) for k in range(5)]  # x = 2, a gap at the top
    grid = OccupancyGrid(ROOM, wall)
    robot, near, far = (1.0, 1.5), (1.0, 0.5), (3.0, 1.5)
    assert grid.connected(robot, far) and grid.connected(robot, near)
    gap = Box(2.0, 2.75, 0.1, 0.5)  # shuts the way through the wall: far is cut off
    assert grid.reaches_with(gap, robot, [near, far]) == 1
    assert grid.reaches_with(Box(3.5, 0.5, 0.1, 0.1), robot, [near, far]) == 2  # out of the way
    assert grid.reaches_with(Box(*robot, 0.1, 0.1), robot, [near, far]) == -1
    assert grid.reaches_with(gap, robot, []) == 0


def test_a_point_in_an_obstacle_is_unreachable(with_box):
    assert with_box.path_length((2.0, 1.5), (0.5, 0.5)) is None


def test_adding_an_obstacle_lengthens_a_path_and_leaves_the_grid_unchanged(empty):
    a, b = (0.5, 1.525), (3.5, 1.525)
    before = empty.path_length(a, b)
    blocked = empty.with_obstacles([Box(2.0, 1.5, 0.3, 1.0, "bag")])
    assert blocked.path_length(a, b) > before + 0.1
    assert empty.path_length(a, b) == before  # the static map is untouched
    assert not empty.mask.flags.writeable


def test_adding_obstacles_can_block_a_path(empty):
    a, b = (0.5, 1.5), (3.5, 1.5)
    lower, upper = Box(2.0, 0.75, 0.1, 1.5), Box(2.0, 2.25, 0.1, 1.5)  # each half of x = 2
    half = empty.with_obstacles([lower])
    assert half.path_length(a, b) is not None  # around the top
    assert half.with_obstacles([upper]).path_length(a, b) is None


def test_nearest_free_moves_a_point_out_of_an_obstacle(with_box):
    x, y = with_box.nearest_free(1.9, 1.5)  # in the box, near its x = 1.8 face
    assert with_box.free(x, y)
    assert x == pytest.approx(1.575) and 1.3 < y < 1.7
    assert with_box.nearest_free(*with_box.xy(5, 5)) == with_box.xy(5, 5)  # a free cell stays put


def test_tidygen_problems_are_unchanged():
    # Pins the problems every bench number is built on: the SHA-256 of tidygen.generate(0). First
    # computed before the grid moved from bench/tidygen.py into sim/grid.py (commit 51e8ed7); changed
    # on purpose twice since: when the problems began to state (shortest-paths) and nothing else, and
    # when costs became seconds (each distance d written as the travel time round(d / 0.22 + 0.8, 2),
    # the same 380 pairs, the header's note and optimum; checked against the old text pair by pair;
    # the optimum in the header again when the take and put costs were corrected, nothing else).
    text = tidygen.generate(0)
    digest = hashlib.sha256(text.replace("    (shortest-paths)\n", "").encode()).hexdigest()
    assert digest == "e41adc195076c98aaa905f6d8b1a2f0650fe8dfd5325010913a26e14c45d5d91"
    digest = hashlib.sha256(text.encode()).hexdigest()
    assert digest == "16ab119b23c8e033c740ca5d9c0e8b8bb413f1759988237eca43e6e3f6f93313"


def test_free_mask_gives_the_verdict_of_box_clearance_on_seeded_random_rooms():
    # The mask is computed with numpy; every cell must get the verdict Box.clearance gives a
    # caller, also the cells a rounding away from the radius (naive reference, cell by cell).
    import random

    rng = random.Random(5)
    for _ in range(12):
        bounds = (0.0, rng.uniform(2.0, 5.0), 0.0, rng.uniform(2.0, 5.0))
        boxes = [
            Box(
                rng.uniform(0, bounds[1]),
                rng.uniform(0, bounds[3]),
                rng.uniform(0.05, 1.0),
                rng.uniform(0.05, 1.0),
            )
            for _ in range(rng.randrange(1, 15))
        ]
        # a box whose inflated edge falls exactly on a cell centre: the borderline case
        boxes.append(Box(1.025 + 0.27 + 0.1, 1.0, 0.2, 0.2))
        grid = OccupancyGrid(bounds, boxes, radius=rng.choice((0.22, 0.27)))
        x0, x1, y0, y1 = bounds
        for i in range(grid.shape[0]):
            for j in range(grid.shape[1]):
                x, y = grid.xy(i, j)
                walls = min(x - x0, x1 - x, y - y0, y1 - y)
                expected = walls >= grid.radius and all(b.clearance(x, y) >= grid.radius for b in boxes)
                assert grid.mask[i, j] == expected, (i, j)


def test_joined_without_a_box_agrees_with_a_new_grid_on_seeded_random_rooms():
    import random

    rng = random.Random(11)
    for _ in range(15):
        bounds = (0.0, 3.0, 0.0, 3.0)
        boxes = [
            Box(rng.uniform(0, 3), rng.uniform(0, 3), rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3), f"b{k}")
            for k in range(rng.randrange(3, 12))
        ]
        grid = OccupancyGrid(bounds, boxes, radius=0.25)
        points = [(rng.uniform(0, 3), rng.uniform(0, 3)) for _ in range(8)]
        pairs = [(a, b) for a in points for b in points if a < b]
        cells = pair_cells(grid, pairs)
        for box in boxes:
            fresh = OccupancyGrid(bounds, [b for b in boxes if b is not box], radius=0.25)
            assert joins_without(grid, box, cells).tolist() == [fresh.connected(a, b) for a, b in pairs]


def test_paths_from_one_tree_are_shortest_by_networkx_and_the_same_on_a_fresh_grid():
    """``path`` and ``lengths_from`` read one remembered Dijkstra per source (scipy's); networkx's
    own search is the oracle: each path is a chain of free 8-neighbour cells from a's cell to
    b's whose length is networkx's shortest, the lengths are its lengths, and a fresh grid asked
    for the pair alone gives the same path (the memo's order never changes which is taken)."""
    import random

    import networkx as nx

    boxes = [Box(2.0, 1.5, 0.4, 1.6), Box(1.0, 0.8, 0.3, 0.3)]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    cells = [(int(i), int(j)) for i, j in zip(*grid.mask.nonzero(), strict=True)]
    # the oracle's graph: 8-connected over the free cells, a step weighs its length
    graph = nx.Graph()
    graph.add_nodes_from(cells)
    straight, diagonal = grid.cell_size, grid.cell_size * math.sqrt(2)
    for i, j in cells:
        for di, dj, w in ((1, 0, straight), (0, 1, straight), (1, 1, diagonal), (1, -1, diagonal)):
            if grid.free(*grid.xy(i + di, j + dj)):
                graph.add_edge((i, j), (i + di, j + dj), weight=w)
    rng = random.Random(0)
    unreachable = 0
    for _ in range(60):
        a, b = grid.xy(*rng.choice(cells)), grid.xy(*rng.choice(cells))
        ca, cb = grid.cell(*a), grid.cell(*b)
        if not nx.has_path(graph, ca, cb):
            assert grid.path(a, b) is None and grid.lengths_from(a, [b]) == [None]
            unreachable += 1
            continue
        want = nx.dijkstra_path_length(graph, ca, cb, weight="weight")
        path = grid.path(a, b)
        steps = [grid.cell(*p) for p in path]
        assert steps[0] == ca and steps[-1] == cb
        assert all(grid.free(*p) for p in path)
        assert all(max(abs(u[0] - v[0]), abs(u[1] - v[1])) == 1 for u, v in itertools.pairwise(steps))
        assert math.isclose(sum(math.dist(u, v) for u, v in itertools.pairwise(path)), want, abs_tol=1e-9)
        assert grid.lengths_from(a, [b]) == [want]
        assert OccupancyGrid(ROOM, boxes, radius=R).path(a, b) == path
    assert unreachable < 60  # the pairs asked were mostly joined: the loop tested paths


def test_a_remembered_tree_costs_a_few_bytes_per_free_cell():
    """The trees ``path`` remembers (up to ``SOURCES_KEPT`` a grid) are kept as arrays: as networkx's dicts a
    two-room floor's were ~100 bytes a cell and a 96-object mission's memory grew by half."""
    import random
    import tracemalloc

    grid = OccupancyGrid(ROOM, [Box(2.0, 1.5, 0.4, 1.6)], radius=R)
    cells = [(int(i), int(j)) for i, j in zip(*grid.mask.nonzero(), strict=True)]
    rng = random.Random(1)
    grid.path(grid.xy(*cells[0]), grid.xy(*cells[-1]))  # the graph and index built first
    sources = rng.sample(cells[1:], 20)
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        for c in sources:
            assert grid.path(grid.xy(*c), grid.xy(*cells[0])) is not None
        grown = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    assert grown / (len(sources) * len(cells)) < 8


def test_a_grid_forgets_its_longest_unasked_sources_and_answers_as_a_fresh_one(monkeypatch):
    """Past ``SOURCES_KEPT`` sources a grid drops the trees and lengths asked longest ago (a
    source asked again is the latest), so a long mission's memory does not grow with its steps;
    a call that asks more sources at once than it keeps is still answered whole."""
    from sim import grid as grid_module

    monkeypatch.setattr(grid_module, "SOURCES_KEPT", 6)
    boxes = [Box(2.0, 1.5, 0.4, 1.6)]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    rng = random.Random(3)
    free = [grid.xy(int(i), int(j)) for i, j in zip(*grid.mask.nonzero(), strict=True)]
    hot, goal = free[0], free[-1]
    for p in rng.sample(free[1:-1], 20):
        assert grid.path(p, goal) is not None and grid.path(hot, goal) is not None
        grid.length_matrix([hot, p])
        assert len(grid._trees) <= 6 and len(grid._lengths) <= 6
        assert grid.cell(*hot) in grid._trees and grid.cell(*hot) in grid._lengths
    points = rng.sample(free, 15)
    fresh = OccupancyGrid(ROOM, boxes, radius=R)
    assert _same_lengths(grid.length_matrix(points), fresh.path_lengths(points))
    assert grid.path_lengths(points) == fresh.path_lengths(points)
    assert len(grid._lengths) <= 6
    assert [grid.path(p, goal) for p in points] == [fresh.path(p, goal) for p in points]


def _same_lengths(got, want) -> bool:
    """Two tables of lengths (NaN or None: unreachable) agree: the same pairs unreachable, the
    others within 1e-9 m (a length read from the other end's search sums the same steps in
    another order)."""

    def table(lengths):
        rows = np.asarray(lengths, dtype=float).tolist()  # None: NaN
        return [[None if math.isnan(v) else v for v in row] for row in rows]

    got, want = table(got), table(want)
    return all(
        (a is None) == (b is None) and (a is None or abs(a - b) <= 1e-9)
        for ra, rb in zip(got, want, strict=True)
        for a, b in zip(ra, rb, strict=True)
    )


@pytest.mark.parametrize("seed", range(4))
def test_the_length_matrix_and_both_ways_are_path_lengths_read_another_way(seed):
    """``length_matrix`` (NaN for None) and ``lengths_both_ways`` give ``path_lengths``' values:
    points free and not, in two components, the same cell twice. A length there is read from
    its source's search, exactly; one read from the other end's, to the last bits."""
    import random

    rng = random.Random(seed)
    wall = [
        Box(2.0, y, 0.1, 0.3, "wall") for y in (0.15, 0.45, 0.75, 1.05, 1.35, 1.65, 1.95, 2.25, 2.55, 2.85)
    ]
    grid = OccupancyGrid(ROOM, wall + [Box(rng.uniform(0.5, 3.5), rng.uniform(0.5, 2.5), 0.4, 0.3, "t")])
    points = [(rng.uniform(0.0, 4.0), rng.uniform(0.0, 3.0)) for _ in range(25)]
    points.append(points[0])
    want = grid.path_lengths(points)
    got = grid.length_matrix(points)
    assert _same_lengths(got, want)
    assert any(v is None for row in want for v in row) and any(v for row in want for v in row)
    for k, a in enumerate(points):
        there, back = grid.lengths_both_ways(a, points)
        assert there == want[k]
        assert _same_lengths([back], [[row[k] for row in want]])


@pytest.mark.parametrize("seed", range(16))
def test_a_changed_grid_keeps_the_lengths_a_change_cannot_touch_and_searches_for_the_rest(seed):
    """Floor after floor of boxes taken away and added (``changed``): each floor's
    ``length_matrix`` among mostly the same points (a few leave, one comes) is a grid made
    anew's, though it searches from fewer than half of them (``sim.carried``'s bounds keep the
    rest; with none kept, a search from all but one would cover them)."""
    import random

    rng = random.Random(seed)

    def box(k):
        x, y = rng.uniform(0.3, 3.7), rng.uniform(0.3, 2.7)
        return Box(x, y, *(rng.uniform(0.1, 0.6) for _ in "xy"), f"b{k}")

    boxes = [box(k) for k in range(rng.randint(6, 14))]
    points = [(rng.uniform(0.0, 4.0), rng.uniform(0.0, 3.0)) for _ in range(20)]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    grid.length_matrix(points)
    searched, asked = 0, 0
    for step in range(8):
        gone = rng.sample(boxes, min(len(boxes), rng.choice([1, 1, 1, 2, 0])))
        new = [box(100 * seed + 10 * step + k) for k in range(rng.choice([0, 0, 1, 2]))]
        after = [b for b in boxes if b not in gone] + new
        changed = grid.changed(after, gone, new)
        points = points[rng.randint(0, 2) :] + [(rng.uniform(0.0, 4.0), rng.uniform(0.0, 3.0))]
        got = changed.length_matrix(points)
        fresh = OccupancyGrid(ROOM, after, radius=R)
        assert _same_lengths(got, fresh.path_lengths(points)), (step, gone, new)
        searched += len(changed._lengths)
        asked += sum(changed.free(*p) for p in points)
        grid, boxes = changed, after
    assert searched < asked / 2


def test_the_free_cells_near_a_point_are_those_of_its_component_there():
    """free_cells_near (a grasp pose's adjustment looks only around the pose) gives the cells of
    free_cells(reachable_from) within r of the point, whichever component asks, and none for a
    start that is not free."""
    # a wall of boxes splits the room: two components
    grid = OccupancyGrid(ROOM, [Box(2.0, 1.5, 0.1, 3.2, "wall")], radius=R)
    for start in ((0.5, 1.5), (3.5, 1.5)):
        component = grid.free_cells(reachable_from=start)
        for at in ((1.7, 1.5), (2.3, 0.4), (0.1, 0.1), (3.9, 2.9)):
            r = 0.6
            near = [q for q in grid.free_cells_near(at, r, reachable_from=start) if math.dist(q, at) <= r]
            want = [q for q in component if math.dist(q, at) <= r]
            assert sorted(near) == sorted(want)
        assert any(grid.free_cells_near((1.7, 1.5), 0.6, reachable_from=(0.5, 1.5)))
    assert grid.free_cells_near((1.7, 1.5), 0.6, reachable_from=(2.0, 1.5)) == []  # in the wall
    every = grid.free_cells()  # and, asked of no component, those of every free cell
    for at in ((1.7, 1.5), (2.3, 0.4), (0.1, 0.1), (3.9, 2.9)):
        near = [q for q in grid.free_cells_near(at, 0.65) if math.dist(q, at) <= 0.65]
        assert sorted(near) == sorted(q for q in every if math.dist(q, at) <= 0.65)


@pytest.mark.parametrize("seed", range(8))
def test_the_nearest_free_cell_is_the_one_every_cell_measured_gives(seed):
    """``nearest_free`` finds its few candidates at once: it answers as the least distance over
    every free cell of the component, then the least cell, does (points in boxes, on cell
    centres, where several cells are equally near)."""
    rng = random.Random(seed)
    boxes = [Box(rng.uniform(0.5, 3.5), rng.uniform(0.5, 2.5), rng.uniform(0.2, 0.9), rng.uniform(0.2, 0.9))]
    boxes += [Box(2.0, 1.5, 0.1, rng.choice((1.0, 3.2)), "wall")]
    grid = OccupancyGrid(ROOM, boxes, radius=R)

    def every(x, y, reachable_from=None):
        cells = [grid.cell(*q) for q in grid.free_cells(reachable_from=reachable_from)]
        return grid.xy(*min(cells, key=lambda c: (math.dist(grid.xy(*c), (x, y)), c)))

    starts = [None, (0.5, 1.5), (3.5, 1.5)]
    for _ in range(60):
        x, y = rng.uniform(-0.2, 4.2), rng.uniform(-0.2, 3.2)
        if rng.random() < 0.3:  # on a line between two cell centres: ties
            x = grid.xy(rng.randrange(80), 0)[0] + grid.cell_size / 2
        start = rng.choice(starts)
        if start is not None and not grid.free(*start):
            continue
        assert grid.nearest_free(x, y, reachable_from=start) == every(x, y, start)
    with pytest.raises(ValueError):
        grid.nearest_free(1.0, 1.0, reachable_from=(2.0, 1.5))  # the start is in the wall
    # within a radius: the same cell where it is that near, else none
    for _ in range(60):
        at, r = (rng.uniform(-0.2, 4.2), rng.uniform(-0.2, 3.2)), rng.choice((0.3, 0.6, 0.65))
        start = rng.choice(starts)
        if start is not None and not grid.free(*start):
            continue
        nearest = every(*at, start)
        want = nearest if math.dist(nearest, at) <= r else None
        assert grid.nearest_free_within(at, r, reachable_from=start) == want
    assert grid.nearest_free_within((1.0, 1.0), 0.6, reachable_from=(2.0, 1.5)) is None


@pytest.mark.parametrize("seed", range(12))
def test_what_taking_one_box_away_joins_is_what_a_grid_without_it_joins(seed):
    """joins_without works from the box's window only (the parts its cells make there, joined
    through the components they touch); whatever the floor, it answers as a grid made without
    the box does, for pairs anywhere (in the box's cells too, outside the room too)."""
    import random

    rng = random.Random(seed)
    # crowded floors: boxes that shut passages, touch each other, stand in corners
    boxes = [
        Box(rng.uniform(0.2, 3.8), rng.uniform(0.2, 2.8), *(rng.uniform(0.05, 0.9) for _ in "xy"), f"b{k}")
        for k in range(rng.randint(6, 18))
    ]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    points = [(rng.uniform(-0.2, 4.2), rng.uniform(-0.2, 3.2)) for _ in range(60)]
    points += [(b.cx, b.cy) for b in boxes]  # ends under a box: free only once it is gone
    pairs = [(rng.choice(points), rng.choice(points)) for _ in range(300)]
    cells = pair_cells(grid, pairs)
    memo: dict = {}
    joined_any = 0
    now = [grid.connected(a, b) for a, b in pairs]
    for box in boxes:
        fresh = OccupancyGrid(ROOM, [b for b in boxes if b is not box], radius=R)
        want = [fresh.connected(a, b) for a, b in pairs]
        got = joins_without(grid, box, cells, memo)
        assert got.tolist() == want, box
        again = joins_without(OccupancyGrid(ROOM, boxes, radius=R), box, cells, memo)  # from the memo
        assert again.tolist() == want
        joined_any += sum(a and not b for a, b in zip(want, now, strict=True))
    assert joined_any  # some box, taken away, joined a pair: the test is of something


def test_a_box_that_alone_shuts_a_room_in_two_joins_its_halves_with_no_end_near_it():
    """A wall across the room with a door-sized box in its gap, and a box on the open floor, all
    far from every end: the door, taken away, joins the two halves (its window meets both); the
    box in the open joins nothing (its window meets one part: the quick verdict), as grids made
    without each say."""
    door = Box(2.0, 1.5, 1.0, 0.3, "door")
    left, right = Box(0.75, 1.5, 1.5, 0.3, "left"), Box(3.25, 1.5, 1.5, 0.3, "right")
    lone = Box(1.0, 0.6, 0.2, 0.2, "lone")
    boxes = [left, door, right, lone]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    pairs = [((0.3, 0.3), (3.7, 2.7)), ((0.3, 0.3), (3.7, 0.3)), ((0.3, 2.7), (2.0, 2.7))]
    cells = pair_cells(grid, pairs)
    assert [grid.connected(a, b) for a, b in pairs] == [False, True, True]
    joins = {}
    for box in boxes:
        fresh = OccupancyGrid(ROOM, [b for b in boxes if b is not box], radius=R)
        got = joins_without(grid, box, cells).tolist()
        assert got == [fresh.connected(a, b) for a, b in pairs], box
        joins[box.name] = got[0]
    assert joins["door"] and not joins["lone"]


def test_the_array_answers_are_the_point_by_point_ones():
    """free_at, reaches and path_cells (the map's facts ask them of a ring or a path at once)
    answer as free, connected and path do, cell centres and points between them alike."""
    import random

    rng = random.Random(5)
    grid = OccupancyGrid(ROOM, [Box(2.0, 1.5, 0.1, 3.2, "wall"), Box(1.0, 1.0, 0.4, 0.4, "crate")], radius=R)
    points = [(rng.uniform(-0.3, 4.3), rng.uniform(-0.3, 3.3)) for _ in range(400)]
    points += [grid.xy(i, j) for i in range(0, 80, 7) for j in range(0, 60, 7)]
    arr = np.array(points)
    assert grid.free_at(arr).tolist() == [grid.free(*q) for q in points]
    for start in ((0.5, 2.5), (3.5, 1.5), (2.0, 1.5)):
        want = [grid.free(*start) and grid.connected(start, q) for q in points]
        assert grid.reaches(arr, start).tolist() == want
    for a, b in [((0.4, 0.4), (1.8, 2.6)), ((0.4, 0.4), (3.5, 1.5)), ((2.5, 0.3), (3.8, 2.8))]:
        path = grid.path(a, b)
        cells = grid.path_cells(a, b)
        if path is None:
            assert cells is None
        else:
            assert cells.tolist() == [i * grid.shape[1] + j for i, j in (grid.cell(*q) for q in path)]


@pytest.mark.parametrize("seed", range(10))
def test_a_grid_changed_by_a_box_or_two_is_the_grid_made_anew(seed):
    """OccupancyGrid.changed (a new floor's grid from the last one's) frees and covers exactly
    the cells a grid made from scratch with the new obstacles does: boxes taken away, added,
    both at once, one to five of each, touching each other and the walls."""
    import random

    rng = random.Random(seed)

    def box(k):
        return Box(
            rng.uniform(0.0, 4.0), rng.uniform(0.0, 3.0), *(rng.uniform(0.05, 0.8) for _ in "xy"), f"b{k}"
        )

    boxes = [box(k) for k in range(rng.randint(4, 16))]
    grid = OccupancyGrid(ROOM, boxes, radius=R)
    for step in range(6):
        gone = rng.sample(boxes, min(len(boxes), rng.choice([0, 1, 1, 2, 5])))
        new = [box(100 * seed + 10 * step + k) for k in range(rng.choice([0, 1, 1, 2, 5]))]
        after = [b for b in boxes if b not in gone] + new
        changed = grid.changed(after, gone, new)
        fresh = OccupancyGrid(ROOM, after, radius=R)
        assert (changed.mask == fresh.mask).all(), (step, gone, new)
        assert changed.obstacles == fresh.obstacles
        grid, boxes = changed, after


@pytest.mark.parametrize("seed", range(8))
def test_the_graph_made_as_arrays_is_the_one_made_from_its_pairs(seed):
    """``_matrix`` (each free cell's higher neighbours, built as CSR arrays directly) is the
    sparse matrix scipy makes from the list of edges, entry for entry and in the same order: the
    searches over it, and so every path and tie, are as they were."""
    import random

    from scipy.sparse import csr_matrix

    rng = random.Random(seed)
    boxes = [
        Box(rng.uniform(0.0, 4.0), rng.uniform(0.0, 3.0), rng.uniform(0.05, 0.8), rng.uniform(0.05, 0.8), "b")
        for _ in range(rng.randint(0, 12))
    ]
    grid = OccupancyGrid(ROOM, boxes, radius=rng.choice([0.05, R]))
    n_i, n_j = grid.shape
    rows, cols, weights = [], [], []
    for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
        for i, j in zip(*np.nonzero(grid.mask), strict=True):
            a, b = i + di, j + dj
            if 0 <= a < n_i and 0 <= b < n_j and grid.mask[a, b]:
                rows.append(grid._node[i, j])
                cols.append(grid._node[a, b])
                weights.append(grid.cell_size * (math.sqrt(2) if di and dj else 1.0))
    n = int(grid.mask.sum())
    want = csr_matrix((weights, (rows, cols)), shape=(n, n))
    got = grid._matrix
    assert got.shape == want.shape
    assert got.indptr.tolist() == want.indptr.tolist()
    assert got.indices.tolist() == want.indices.tolist()
    assert got.data.tolist() == want.data.tolist()


def test_the_obstacles_spans_worked_out_at_once_are_each_obstacles_own():
    """``_obstacle_spans`` (every obstacle's span in one pass of arrays) against ``_span`` box by
    box: boxes inside the room, across its walls, wholly outside, thin and large, on cell
    borders and off them, for both radii."""
    rng = random.Random(5)
    for radius in (0.215, 0.265):
        for _ in range(20):
            boxes = []
            for k in range(rng.randint(1, 30)):
                cx = rng.choice([rng.uniform(-3.5, 3.5), round(rng.uniform(-3, 3), 2), rng.uniform(-9, 9)])
                cy = rng.choice([rng.uniform(-3.5, 3.5), round(rng.uniform(-3, 3), 2), rng.uniform(-9, 9)])
                boxes.append(
                    Box(
                        cx,
                        cy,
                        rng.choice([0.01, 0.1, rng.uniform(0.02, 2.5)]),
                        rng.uniform(0.01, 2.5),
                        f"b{k}",
                    )
                )
            for k in range(10):  # an inflated side on a cell border, where the sums' order tells
                sx, sy = rng.choice([0.1, 0.3, rng.uniform(0.02, 1.0)]), rng.uniform(0.02, 1.0)
                cx = -3.0 + rng.randint(0, 120) * 0.05 + sx / 2 + radius
                cy = -2.5 + rng.randint(0, 100) * 0.05 - sy / 2 - radius
                boxes.append(Box(cx, cy, sx, sy, f"edge{k}"))
            grid = OccupancyGrid((-3.0, 3.0, -2.5, 2.5), boxes, radius=radius)
            spans, listed = grid._obstacle_spans
            assert listed == list(grid.obstacles)
            want = [grid._span(b) or (0, 0, 0, 0) for b in grid.obstacles]
            assert [tuple(int(v) for v in row) for row in spans] == want
