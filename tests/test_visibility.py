"""sim.visibility: segments against boxes, range limits, and which scenario items a look sees."""

import math

import pytest

from sim.scenario.model import Furniture, Item
from sim.scenario.read import loads
from sim.visibility import Box3, in_field_of_view, segment_hits_box, visible, visible_items

CAMERA = (0.0, 0.0, 1.0)
TARGET = (2.0, 0.0, 0.5)  # 2.06 m away; the ray is at z 0.75 over x = 1
WALL = Box3(0.9, 1.1, -0.5, 0.5, 0.0, 1.2, "wall")  # taller than the ray
LOW = Box3(0.9, 1.1, -0.5, 0.5, 0.0, 0.7, "low")  # lower than the ray there
RANGE = {"range_min": 0.8, "range_max": 3.5}


def test_box3_from_furniture_and_item():
    f = Furniture("table", 1.0, 2.0, 0.4, 1.2, 0.4, "table")
    assert Box3.from_furniture(f) == Box3(0.8, 1.2, 1.4, 2.6, 0.0, 0.4, "table")
    i = Item("cup", "kitchen", 1.0, 2.0, "table", 0.25, 0.5, 0.25)
    assert Box3.from_item(i, 0.5) == Box3(0.875, 1.125, 1.75, 2.25, 0.5, 0.75, "cup")


def test_segment_hits_box():
    assert segment_hits_box(CAMERA, TARGET, WALL)
    assert not segment_hits_box(CAMERA, TARGET, LOW)
    assert not segment_hits_box(CAMERA, (0.5, 0.0, 1.0), WALL)  # stops short of the box
    assert not segment_hits_box(CAMERA, TARGET, Box3(0.9, 1.1, 0.1, 0.5, 0.0, 2.0))  # beside the ray
    assert segment_hits_box(CAMERA, (1.0, 0.0, 1.0), WALL)  # ends inside
    assert segment_hits_box((1.0, 0.0, 1.3), (1.0, 0.0, 0.0), WALL)  # vertical, parallel to 4 faces
    assert not segment_hits_box((0.0, 0.0, 1.0), (2.0, 0.0, 1.0), LOW)  # horizontal, above
    assert segment_hits_box((0.0, 0.0, 0.7), (2.0, 0.0, 0.7), LOW)  # grazes the top: closed box


def test_visible_blocked_by_tall_box_not_by_low_one():
    assert not visible(CAMERA, TARGET, [WALL], **RANGE)
    assert visible(CAMERA, TARGET, [LOW], **RANGE)
    assert visible(CAMERA, TARGET, [], **RANGE)


def test_visible_range():
    assert not visible(CAMERA, (0.5, 0.0, 0.6), [], **RANGE)  # 0.64 m: too near
    assert not visible(CAMERA, (4.0, 0.0, 0.5), [], **RANGE)  # 4.03 m: too far
    assert visible(CAMERA, (0.8, 0.0, 1.0), [], **RANGE)  # both limits included
    assert visible(CAMERA, (3.5, 0.0, 1.0), [], **RANGE)


def test_in_field_of_view():
    assert in_field_of_view((0.0, 0.0), 0.0, (1.0, 0.5), 58.0)  # 26.6 deg off
    assert not in_field_of_view((0.0, 0.0), 0.0, (1.0, 0.6), 58.0)  # 31.0 deg off
    assert in_field_of_view((0.0, 0.0), math.pi, (-1.0, -0.1), 58.0)  # across the +-180 seam
    assert not in_field_of_view((0.0, 0.0), math.pi / 2, (1.0, 0.0), 58.0)
    assert in_field_of_view((1.0, 1.0), 0.0, (1.0, 1.0), 58.0)


ROOM = """\
schema = 1
name = "vis"
title = "Visibility"

[room]
bounds = [0.0, 6.0, 0.0, 4.0]
entrance = [0.5, 2.0]

[sensing]
camera_height = 1.0
range_min = 1.0

[[furniture]]
name = "shelf"
center = [3.0, 3.0]
size = [0.6, 1.0]
height = 1.8
kind = "shelf"

[[furniture]]
name = "cabinet"
center = [2.0, 1.2]
size = [0.2, 1.2]
height = 1.5
kind = "shelf"

[[deposit]]
name = "bin"
category = "toy"
position = [5.5, 3.5, 0.0]

[[item]]
name = "top"
category = "toy"
position = [3.0, 3.0]
on = "shelf"

[[item]]
name = "hidden"
category = "toy"
position = [3.0, 1.0]

[[item]]
name = "open"
category = "toy"
position = [3.0, 2.0]

[[item]]
name = "post"
category = "toy"
position = [5.0, 0.5]
size = [0.1, 0.1, 1.5]
"""


@pytest.fixture(scope="module")
def room():
    return loads(ROOM, "vis.toml")


def test_visible_items(room):
    # from (1, 2): "top" stands on a shelf taller than the camera, so the ray climbs through the
    # shelf's box and only leaving that box out lets it be seen; "hidden" is behind the cabinet;
    # "post" is 4.3 m away
    assert visible_items(room, (1.0, 2.0)) == ["top", "open"]
    assert visible_items(room, (1.0, 2.0), items=["hidden", "open"]) == ["open"]
    assert visible_items(room, (3.0, 0.1)) == ["top", "hidden", "open", "post"]  # cabinet not between
    assert visible_items(room, (3.0, 2.0)) == ["top", "hidden", "post"]  # "open" 0.9 m below: too near


def test_supporting_shelf_is_left_out(room):
    # the ray from (1, 2, 1) to the top of "top" (3, 3, 1.9) enters the 1.8 m shelf below its top
    camera, target = (1.0, 2.0, 1.0), (3.0, 3.0, 1.9)
    shelf = Box3.from_furniture(room.furniture_named("shelf"))
    assert segment_hits_box(camera, target, shelf)
    assert not visible(camera, target, [shelf], range_min=1.0, range_max=3.5)
    assert "top" in visible_items(room, (1.0, 2.0))


def test_visible_items_moved(room):
    # the cabinet is out of the way once "hidden" is moved next to "open"; None takes an item away
    assert visible_items(room, (1.0, 2.0), moved={"hidden": (3.0, 2.3, 0.0)}) == ["top", "hidden", "open"]
    assert visible_items(room, (1.0, 2.0), moved={"open": None}) == ["top"]
    assert visible_items(room, (1.0, 2.0), moved={"hidden": (3.0, 3.1, 1.8)}) == ["top", "hidden", "open"]
    # the 1.5 m post between the camera and "top" hides it; other items occlude too
    assert visible_items(room, (1.0, 2.0), moved={"post": (2.0, 2.5, 0.0)}) == ["open", "post"]
    with pytest.raises(KeyError):
        visible_items(room, (1.0, 2.0), items=["ghost"])


def test_visible_points_agrees_with_visible_on_seeded_random_scenes():
    # The array form the belief uses for its placement points, against the scalar one.
    import random

    import numpy as np

    from sim.visibility import visible_points

    rng = random.Random(3)
    for _ in range(20):
        boxes = []
        for k in range(rng.randrange(1, 8)):
            x, y, z = rng.uniform(0, 4), rng.uniform(0, 4), rng.uniform(0.2, 1.5)
            boxes.append(Box3(x, x + rng.uniform(0.1, 1), y, y + rng.uniform(0.1, 1), 0.0, z, f"b{k}"))
        camera = (rng.uniform(0, 4), rng.uniform(0, 4), 1.0)
        targets = [(rng.uniform(0, 4), rng.uniform(0, 4), rng.choice((0.05, 0.45))) for _ in range(200)]
        support = [rng.choice(["floor", *(b.name for b in boxes)]) for _ in targets]
        got = visible_points(camera, np.array(targets), boxes, support, range_min=0.8, range_max=3.5)
        for n, t in enumerate(targets):
            occ = [b for b in boxes if b.name != support[n]]
            assert got[n] == visible(camera, t, occ, range_min=0.8, range_max=3.5), n


def test_the_boxes_near_a_segment_decide_visible_as_every_box_does():
    # BoxTable.near_segment drops the boxes beyond the segment's bounding box: the verdict with
    # the rest must be the verdict with all. Segments along an axis, and boxes whose faces lie
    # on the bounding box's (or a hair beyond it), are where a dropped box could have mattered.
    import random

    from sim.visibility import BoxTable

    rng = random.Random(5)
    dropped = 0
    for _ in range(300):
        p = (rng.uniform(0, 4), rng.uniform(0, 4), 1.0)
        q = [rng.uniform(0, 4), rng.uniform(0, 4), rng.choice((0.05, 0.45, 1.0))]
        if rng.random() < 0.3:
            q[rng.randrange(2)] = p[rng.randrange(2)]  # along an axis (or on the camera's line)
        q = tuple(q)
        boxes = []
        for k in range(rng.randrange(1, 12)):
            x, y = rng.uniform(-0.5, 4.5), rng.uniform(-0.5, 4.5)
            if rng.random() < 0.3:  # a face on the segment's bounding box, or just past it
                x = max(p[0], q[0]) + rng.choice((0.0, 1e-12, -1e-12, 1e-6))
            z = rng.choice((0.0, rng.uniform(0.2, 1.2)))  # on the floor, or on a table
            box = Box3(
                x, x + rng.uniform(0.05, 1), y, y + rng.uniform(0.05, 1), z, z + rng.uniform(0.02, 1.5)
            )
            boxes.append((k, box))
        split = rng.randrange(len(boxes) + 1)  # the first ones as fixed boxes (furniture)
        table = BoxTable(boxes[split:], fixed=[b for _, b in boxes[:split]])
        fixed, near = table.near_segment(p, q)
        dropped += len(boxes) - len(fixed) - len(near)
        every = visible(p, q, [b for _, b in boxes], range_min=0.0, range_max=10.0)
        assert visible(p, q, fixed + [b for _, b in near], range_min=0.0, range_max=10.0) == every
        # and a box meeting the segment is never dropped
        kept = {id(b) for b in fixed} | {id(b) for _, b in near}
        assert all(id(b) in kept for _, b in boxes if segment_hits_box(p, q, b))
    assert dropped > 300  # the test dropped boxes: it tested something


def test_visible_points_tests_the_occluders_near_its_targets_as_all_of_them():
    # A frame's targets lie in a part of the room: visible_points leaves out the occluders
    # beyond the box around the camera and them. Its verdict must be the one every occluder
    # gives (the array test over all of them, as before), boxes a hair inside or outside that
    # box included.
    import random

    import numpy as np

    from sim.visibility import _unoccluded, visible_points

    rng = random.Random(11)
    dropped = 0
    for _ in range(60):
        camera = np.array((rng.uniform(1, 3), rng.uniform(1, 3), 1.0))
        cx, cy = rng.uniform(0, 4), rng.uniform(0, 4)  # the targets: a cluster, as a frame's field
        targets = np.array(
            [
                (cx + rng.uniform(-0.6, 0.6), cy + rng.uniform(-0.6, 0.6), rng.choice((0.05, 0.45)))
                for _ in range(80)
            ]
        )
        lo = np.minimum(targets.min(axis=0), camera)
        hi = np.maximum(targets.max(axis=0), camera)
        boxes = []
        for k in range(rng.randrange(4, 14)):
            x, y = rng.uniform(-0.5, 4.5), rng.uniform(-0.5, 4.5)
            if rng.random() < 0.4:  # a face on the box around them, or just past it
                x = rng.choice((hi[0], lo[0] - 0.3)) + rng.choice((0.0, 1e-12, -1e-12, 1e-6, -1e-6))
            z = rng.choice((0.0, rng.uniform(0.2, 0.8)))
            boxes.append(
                Box3(x, x + 0.3, y, y + rng.uniform(0.1, 0.8), z, z + rng.uniform(0.02, 1.2), f"b{k}")
            )
        support = [rng.choice(["floor", *(b.name for b in boxes)]) for _ in targets]
        got = visible_points(tuple(camera), targets, boxes, support, range_min=0.0, range_max=10.0)
        every = _unoccluded(camera, targets - camera, boxes, np.asarray(support, dtype=object))
        assert (got == every).all()
        dropped += sum(
            not (
                b.x0 <= hi[0] + 1e-9
                and b.x1 >= lo[0] - 1e-9
                and b.y0 <= hi[1] + 1e-9
                and b.y1 >= lo[1] - 1e-9
            )
            for b in boxes
        )
    assert dropped > 100  # boxes beyond the targets' box were there to leave out
