"""The pybullet world: the head camera's occlusion, field of view and range, driving around
furniture and stopping short of a floor object, and whole missions in DIRECT mode (a dropped
object found again; a small room tidied). Each room is a scenario file written here, small
enough to read at a glance. The HSR model itself is tested in test_hsr_model.py.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pybullet as p
import pytest

from sim.scenario.read import loads
from tidyplan.belief.geometry import RoomMap
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.worlds.pybullet.world import BACK_OFF, STEP, BulletWorld
from tidyplan.worlds.rates import Rates

NO_FALSE_DETECTIONS = Rates(false_negative=0.0, false_positive=0.0)
BASE_RADIUS = 0.215  # m: the base's collision cylinder, 430 mm across (docs/sources.md)


@pytest.fixture
def world():
    """``world(scenario)``: a BulletWorld without detection errors; every one made is closed."""
    made: list[BulletWorld] = []

    def make(scenario) -> BulletWorld:
        made.append(BulletWorld(scenario, RoomMap(scenario), rates=NO_FALSE_DETECTIONS))
        return made[-1]

    yield make
    for w in made:
        w.close()


def _place(world: BulletWorld, at: tuple[float, float]) -> None:
    world.hsr.set_base(*at)
    world.robot = at


def _events(path) -> list[dict]:
    return [json.loads(line) for line in open(path, encoding="utf-8")]


# ---------------------------------------------------------------------- perception
# A tall box (higher than the lens) stands between vp-hidden and the toy; from vp-open, south of
# the toy, nothing is in the way. Both are 1.4-1.8 m from the toy: in range.
HIDE = """
schema = 1
name = "hide"
title = "a tall box hides a toy from one viewpoint"
[room]
bounds = [0.0, 4.0, 0.0, 4.0]
entrance = [0.5, 0.5]
[[furniture]]
name = "tall-box"
center = [2.4, 2.0]
size = [0.3, 0.6]
height = 1.5
kind = "box"
[[deposit]]
name = "bin"
category = "toy"
position = [0.3, 3.5, 0.0]
[[item]]
name = "toy"
category = "toy"
position = [3.0, 2.0]
[[viewpoint]]
name = "vp-hidden"
position = [1.2, 2.0]
[[viewpoint]]
name = "vp-open"
position = [3.0, 0.6]
"""


def _toys(detections) -> list[tuple[float, float]]:
    return [(d.x, d.y) for d in detections if d.category == "toy"]


def test_an_occluded_item_is_not_seen_then_seen_from_another_viewpoint(world):
    scenario = loads(HIDE, "hide.toml")
    w = world(scenario)
    vp = {v.name: (v.x, v.y) for v in scenario.viewpoints}
    _place(w, vp["vp-hidden"])
    assert _toys(w.look()) == []
    _place(w, vp["vp-open"])
    assert _toys(w.look()) == [pytest.approx((3.0, 2.0), abs=0.01)]
    # It was the box that hid it: without the box, vp-hidden sees it too.
    p.removeBody(w.scene.furniture["tall-box"], physicsClientId=w.client)
    _place(w, vp["vp-hidden"])
    assert _toys(w.look()) == [pytest.approx((3.0, 2.0), abs=0.01)]


def test_the_camera_sees_only_within_its_range_and_field_of_view(world):
    w = world(loads(HIDE, "hide.toml"))
    _place(w, (1.0, 1.0))
    w.hsr.set_head(0.0, 0.0)
    eye, forward, up = w.hsr.camera()
    right = np.cross(forward, up)

    def at(ahead: float, side: float = 0.0, above: float = 0.0) -> tuple:
        return tuple(np.asarray(eye) + ahead * np.asarray(forward) + side * right + above * np.asarray(up))

    cam = w.camera
    assert (cam.range_min, cam.range_max, cam.fov_h_deg, cam.fov_v_deg) == (0.8, 3.5, 58.0, 45.0)
    assert not cam.in_view(eye, forward, up, at(0.5))  # nearer than the range's 0.8 m
    assert cam.in_view(eye, forward, up, at(2.0))
    assert not cam.in_view(eye, forward, up, at(4.0))  # beyond 3.5 m
    assert cam.in_view(eye, forward, up, at(2.0, side=1.0))  # 26.6 deg off: inside 29
    assert not cam.in_view(eye, forward, up, at(2.0, side=1.3))  # 33 deg off
    assert not cam.in_view(eye, forward, up, at(2.0, above=1.0))  # 26.6 deg up: outside 22.5
    assert not cam.in_view(eye, forward, up, at(-2.0))  # behind


# ---------------------------------------------------------------------- navigation
DRIVE = """
schema = 1
name = "drive"
title = "a table to drive around and a toy on the floor"
[room]
bounds = [0.0, 4.0, 0.0, 3.0]
entrance = [0.5, 1.5]
[[furniture]]
name = "table"
center = [2.0, 1.5]
size = [0.6, 1.2]
height = 0.4
kind = "table"
[[deposit]]
name = "bin"
category = "toy"
position = [3.7, 0.3, 0.0]
[[item]]
name = "toy"
category = "toy"
position = [1.0, 0.6]
"""


def test_the_robot_drives_around_a_table_on_a_path_the_grid_finds_free(world):
    scenario = loads(DRIVE, "drive.toml")
    room = RoomMap(scenario)
    floor = [i.box() for i in scenario.items if i.on == "floor"]
    grid = room.grid(floor)
    table = scenario.furniture[0].box()
    start, goal = (1.0, 1.5), (3.0, 1.5)
    assert table.clearance(2.0, 1.5) == 0.0  # the straight line runs through the table
    path = grid.path(start, goal)
    assert path is not None
    assert all(grid.free(*q) for q in path)
    assert all(b.clearance(*q) >= scenario.robot.radius for q in path for b in [table, *floor])
    length = sum(math.dist(a, b) for a, b in zip(path, path[1:], strict=False))
    assert length > math.dist(start, goal) + 0.5  # it goes round

    w = world(scenario)
    _place(w, path[0])
    out = w.follow(path)
    assert out.ok and out.failure is None
    assert w.pose() == path[-1]
    assert w.hsr.base()[:2] == pytest.approx(path[-1], abs=1e-6)
    assert out.metres == pytest.approx(length, abs=1e-6)
    assert out.seconds == pytest.approx(length / scenario.robot.speed, abs=1e-6)


def test_a_drive_straight_through_a_floor_item_stops_short_of_it_and_says_where_it_touched(world):
    scenario = loads(DRIVE, "drive.toml")
    toy = scenario.items[0]
    start, goal = (1.0, 1.5), (1.0, 0.25)
    grid = RoomMap(scenario).grid([toy.box()])
    assert not grid.free(toy.x, toy.y)  # the belief's grid never plans this line

    w = world(scenario)
    body = w.bodies["toy"]
    before = p.getBasePositionAndOrientation(body, physicsClientId=w.client)[0]
    _place(w, start)
    out = w.follow([start, goal])
    assert not out.ok and out.failure == "path_blocked"
    x, y = w.pose()
    assert x == pytest.approx(1.0) and toy.y < y < start[1]  # on its way, before the toy
    assert math.dist((x, y), (toy.x, toy.y)) > BASE_RADIUS
    assert w.hsr.base()[:2] == pytest.approx((x, y))
    # it stopped where the last check passed, then backed off BACK_OFF along its way (to the
    # check at least that far from the contact): the odometer counts both legs
    backed = (out.metres - (start[1] - y)) / 2
    assert BACK_OFF - STEP - 1e-6 <= backed < BACK_OFF
    after = p.getBasePositionAndOrientation(body, physicsClientId=w.client)[0]
    assert after == pytest.approx(before, abs=1e-6)  # stopped, not pushed through
    # the bumper's side: where the base touched the toy, on the base's edge towards it
    tx, ty = out.at
    assert tx == pytest.approx(toy.x, abs=toy.sx / 2 + 0.01) and ty < y - BASE_RADIUS + BACK_OFF
    assert math.dist(out.at, (toy.x, toy.y)) < math.hypot(toy.sx, toy.sy) / 2 + 0.02
    # and it can drive on from there, though the next path's first step (to a grid cell's centre)
    # may lead a step toward the toy: standing where the last check passed, that step was blocked
    assert w.follow([(x, y), (x, y - STEP), (x - 0.3, y - STEP)]).ok
    # a toy off to the side of the way: the bumper's side is that side, not straight ahead
    aside = toy.x + 0.2  # the base's edge (0.215 m out) passes 1.5 cm into the toy's side
    _place(w, (aside, start[1]))
    out = w.follow([(aside, start[1]), (aside, goal[1])])
    assert not out.ok and out.at[0] < aside - 0.15 and out.at[1] == pytest.approx(toy.y, abs=0.06)


# ---------------------------------------------------------------------- missions
MINI = """
schema = 1
name = "mini"
title = "two toys on the floor and a tray on a table"
[room]
bounds = [0.0, 3.0, 0.0, 3.0]
entrance = [2.5, 0.5]
heading_deg = 90.0
[[furniture]]
name = "table"
center = [0.25, 1.5]
size = [0.4, 0.8]
height = 0.4
kind = "table"
[[deposit]]
name = "tray"
category = "toy"
position = [0.25, 1.5, 0.4]
approach = [0.8, 1.5]
[[item]]
name = "ball"
category = "toy"
position = [1.8, 2.2]
[[item]]
name = "block"
category = "toy"
position = [2.2, 1.6]
[[viewpoint]]
name = "vp"
position = [1.5, 0.9]
"""


@pytest.mark.slow
def test_a_dropped_object_is_found_again_and_tidied(tmp_path):
    # At grasp_drop 0.5 seed 7 drops the carried toy twice and both are picked up again (seed 2
    # did before plans lost their detours: fewer carrying drives, fewer draws); at 1.0 every
    # carrying drive would drop it forever.
    trace = tmp_path / "drop.jsonl"
    settings = Settings(
        world="pybullet", planner="lama-first", time_budget=0.5, seed=7, rates=Rates.parse("grasp_drop=0.5")
    )
    run(loads(MINI, "mini.toml"), trace, settings)
    events = _events(trace)
    steps = [e for e in events if e["kind"] in ("unit", "recovery", "action")]
    drops = [i for i, e in enumerate(steps) if e["kind"] == "unit" and e["failure"] == "grasp_drop"]
    assert drops, "no carried object slipped: pick another seed"
    drop = drops[0]
    assert steps[drop]["unit"] == "navigate" and steps[drop]["interrupted"]
    assert steps[drop + 1]["kind"] == "recovery" and steps[drop + 1]["layer"] == "insert_unit"
    # Found again and picked up within the same action, then delivered.
    rest = steps[drop + 2 : next(i for i in range(drop, len(steps)) if steps[i]["kind"] == "action")]
    units = [(e["unit"], e["step"], e["ok"], e["depth"]) for e in rest if e["kind"] == "unit"]
    assert ("grasp", "do", True, 1) in units, units
    end = next(e for e in events if e["kind"] == "end")
    where = {name: at[0] for name, at in end["items"].items()}
    assert where == {"ball": "tidied:tray", "block": "tidied:tray"}, where
    summary = events[-1]
    assert summary["kind"] == "summary" and summary["world"] == "pybullet"
    assert summary["success"] is True and summary["lost_objects"] == 0, summary
    assert summary["delivered"] == summary["objects"] == 2


SMALL = """
schema = 1
name = "small"
title = "a toy and a cup on the floor, a car on a table, two deposits"
[room]
bounds = [0.0, 3.0, 0.0, 3.0]
entrance = [2.5, 0.5]
heading_deg = 90.0
[[furniture]]
name = "shelf"
center = [0.25, 1.5]
size = [0.4, 0.8]
height = 0.4
kind = "table"
[[furniture]]
name = "low-table"
center = [2.3, 2.7]
size = [0.8, 0.4]
height = 0.4
kind = "table"
[[deposit]]
name = "tray"
category = "toy"
position = [0.25, 1.75, 0.4]
approach = [0.8, 1.75]
[[deposit]]
name = "rack"
category = "kitchen"
position = [0.25, 1.15, 0.4]
approach = [0.8, 1.15]
[[item]]
name = "ball"
category = "toy"
position = [1.8, 2.2]
[[item]]
name = "cup"
category = "kitchen"
position = [2.2, 1.6]
[[item]]
name = "car"
category = "toy"
position = [2.3, 2.7]
on = "low-table"
[[viewpoint]]
name = "vp"
position = [1.5, 0.9]
"""


@pytest.mark.slow
def test_a_small_room_is_tidied_end_to_end_in_pybullet(tmp_path):
    trace = tmp_path / "small.jsonl"
    rates = Rates.parse("")  # the default rates: grasps fail at 0.05, looks miss at 0.2 ...
    settings = Settings(world="pybullet", planner="lama-first", time_budget=0.5, seed=0, rates=rates)
    summary = run(loads(SMALL, "small.toml"), trace, settings)
    times = f"sim_time_s={summary['sim_time_s']} wall_time_s={summary['wall_time_s']}: {summary}"
    assert summary["world"] == "pybullet", times
    assert summary["success"] is True, times
    assert summary["delivered"] == summary["objects"] == 3, times
    assert summary["lost_objects"] == 0, times
    end = next(e for e in _events(trace) if e["kind"] == "end")
    assert {name: where[0] for name, where in end["items"].items()} == {
        "ball": "tidied:tray",
        "car": "tidied:tray",
        "cup": "tidied:rack",
    }, times


def test_the_robots_map_is_read_from_the_built_scene(world):
    """The occupancy grid's furniture comes from the pybullet bodies (their bounding boxes), and
    matches the scenario it was built from."""
    w = world(loads(HIDE))
    built = w.scene.as_built()
    assert [f.name for f in built.furniture] == ["tall-box"]
    (f,) = built.furniture
    assert (f.cx, f.cy, f.sx, f.sy, f.height) == (2.4, 2.0, 0.3, 0.6, 1.5)
    p.resetBasePositionAndOrientation(
        w.scene.furniture["tall-box"], (2.0, 2.0, 0.75), (0, 0, 0, 1), physicsClientId=w.client
    )
    assert w.scene.as_built().furniture[0].cx == 2.0  # read from the scene, not the file


# ---------------------------------------------------------------------- manipulation
# A tall box (0.45 m) on the floor and a WRS tray on a 0.4 m table: the hand pointing down could
# not lift the box high enough to stand it in the tray, so it is taken from the side.
TALL = """
schema = 1
name = "tall"
title = "a tall box into a tray on a table"
[room]
bounds = [0.0, 4.0, 0.0, 4.0]
entrance = [0.5, 0.5]
[[furniture]]
name = "table"
center = [0.3, 2.0]
size = [0.4, 1.0]
height = 0.40
kind = "table"
[[deposit]]
name = "tray"
category = "box"
position = [0.3, 2.0, 0.40]
approach = [0.8, 2.0]
[[item]]
name = "crate"
category = "box"
position = [2.5, 2.0]
size = [0.19, 0.19, 0.45]
"""


def _tilt(world: BulletWorld, name: str) -> float:
    orn = p.getBasePositionAndOrientation(world.bodies[name], physicsClientId=world.client)[1]
    return math.acos(min(1.0, p.getMatrixFromQuaternion(orn)[8]))


def test_a_tall_box_is_taken_from_the_side_and_stands_upright_in_the_tray(world):
    w = world(loads(TALL, "tall.toml"))
    near, best, far = w.grasp_distances(0.45)
    assert near > 0.5  # the side grasp reaches farther out than the top grasp (0.35-0.65 m)
    _place(w, (2.5 + best, 2.0))
    grasp = w.grasp((2.5, 2.0))
    assert grasp.ok and w.holds()
    hand = p.getMatrixFromQuaternion(w._held_as[0])  # the hand as it closed on the box
    assert abs(hand[8]) < 0.1  # the fingers level: a side grasp, not from the top
    _place(w, (0.8, 2.0))
    out = w.place("tray", (0.8, 2.0))
    assert out.ok, out.failure
    crate = w.items["crate"]
    assert crate.state == "tidied" and abs(crate.x - 0.3) <= 0.19 and abs(crate.y - 2.0) <= 0.19
    assert _tilt(w, "crate") < 0.05  # it stands as it stood on the floor


def test_the_camera_keeps_frames_on_the_way_looking_where_the_robot_drives(world):
    # Driving north toward the toy with the base facing east (the base drives any way without
    # turning): frames every FRAME_EVERY m, the head turned toward the way no faster than its
    # joints allow, the drive no slower for them; the frames looking north see the toy.
    from tidyplan.worlds.base import FRAME_EVERY

    scenario = loads(HIDE, "hide.toml")
    w = world(scenario)
    _place(w, (3.0, 0.2))
    w.hsr.set_base(3.0, 0.2, 0.0)
    w.hsr.set_head(0.0, -0.35)
    out = w.follow([(3.0, 0.2), (3.0, 1.2)])
    assert out.ok and out.seconds == pytest.approx(1.0 / scenario.robot.speed, abs=1e-6)
    frames = w.glance()
    assert len(frames) == round(1.0 / FRAME_EVERY)  # one on the way, and the glance's own
    # where the lens stood: ahead of the base's centre, the head looking north
    assert [f.at[1] for f in frames] == pytest.approx([0.7 + 0.15, 1.2 + 0.15], abs=0.05)
    # the head turns at 1 rad/s: by 0.5 m (2.3 s) it has turned the quarter turn to look north
    assert [f.heading for f in frames] == pytest.approx([math.pi / 2] * 2, abs=0.05)
    # 1.15 m short of the toy it is in view; 0.65 m short, below the frame's foot (the tilt for
    # driving sees the floor from 1 m out)
    assert [_toys(f.detections) for f in frames] == [[pytest.approx((3.0, 2.0), abs=0.01)], []]
    assert not w._frames and len(w.glance()) == 1  # drained


def test_a_frame_shows_only_its_own_field(world):
    scenario = loads(HIDE, "hide.toml")
    w = world(scenario)
    _place(w, (3.0, 0.6))  # vp-open: the toy 1.4 m north
    w.hsr.set_base(3.0, 0.6, math.pi / 2)
    assert _toys(w.glance()[0].detections) == [pytest.approx((3.0, 2.0), abs=0.01)]
    w.hsr.set_base(3.0, 0.6, -math.pi / 2)  # its back to the toy
    assert _toys(w.glance()[0].detections) == []
    assert w.odometer.sim_time_s == 0.0  # a glance takes no time


# ---------------------------------------------------------------------- looks that pay
def test_a_sweep_of_some_stops_sees_only_their_way_in_the_time_their_head_motions_take(world):
    """A sweep of the stops the belief chose (headings in the room's frame) frames only their
    way: from vp-open the toy is north of the robot; a stop facing north sees it, one facing
    south does not; either takes what its head motions take, a fraction of a whole sweep."""
    from tidyplan.belief.percepts import SWEEP_STOPS
    from tidyplan.worlds.base import sweep_pans, sweep_seconds

    w = world(loads(HIDE, "hide.toml"))
    _place(w, (3.0, 0.6))
    north, south = SWEEP_STOPS[2], SWEEP_STOPS[5]  # 103 and 257 deg: the toy is at 90 deg
    clock = w.odometer.sim_time_s
    assert _toys(w.look((south,))) == []
    one = w.odometer.sim_time_s - clock
    assert one == pytest.approx(sweep_seconds(sweep_pans(w.hsr.base()[2], (south,))), abs=0.05)
    assert _toys(w.look((north,))) == [pytest.approx((3.0, 2.0), abs=0.01)]
    clock = w.odometer.sim_time_s
    assert _toys(w.look()) == [pytest.approx((3.0, 2.0), abs=0.01)]
    whole = w.odometer.sim_time_s - clock
    # a whole sweep pans the head's range (1.75 to -3.84 rad at 1 rad/s), two tilts 0.5 rad apart at each of 7
    assert whole >= (1.75 + 3.84) / 1.0 + 7 * 0.5 and one < whole / 3


def test_on_the_way_the_head_aims_at_the_item_so_the_close_look_is_the_detector_alone(world):
    """The base turns to face the item while it drives; in the drive's last moments the head
    tilts to it too (no faster than 1 rad/s, in no time of the drive's own); the close look
    that follows finds it in the detector's second and the head's remaining motion."""
    from tidyplan.worlds.pybullet.look import RECOGNISE_S

    scenario = loads(DRIVE, "drive.toml")  # the toy at (1.0, 0.6) on the floor
    w = world(scenario)
    _place(w, (0.5, 2.2))
    w.hsr.set_head(0.0, -0.35)
    tilts: list[tuple[float, float]] = []
    arrive = w._arrive

    def spy(q, d, seconds):
        tilts.append((seconds, w.hsr.q("head_tilt_joint")))
        return arrive(q, d, seconds)

    w._arrive = spy
    path = [(0.5, 2.2), (0.5, 1.4), (1.0, 1.4)]
    out = w.follow(path, face=(1.0, 0.6))
    length = math.dist(*path[:2]) + math.dist(*path[1:])
    assert out.ok and out.seconds == pytest.approx(length / scenario.robot.speed, rel=1e-6)
    for (_, before), (seconds, after) in zip(tilts, tilts[1:], strict=False):
        assert abs(after - before) <= 1.0 * seconds + 1e-9
    assert w.hsr.q("head_tilt_joint") < -0.8  # looking down at the toy 0.8 m ahead
    clock = w.odometer.sim_time_s
    seen = w.locate((1.0, 0.6), 0.25, "toy")
    assert seen is not None and (seen.x, seen.y) == pytest.approx((1.0, 0.6), abs=0.02)
    assert w.odometer.sim_time_s - clock < RECOGNISE_S + 0.2


TABLE_TOY = DRIVE.replace("position = [1.0, 0.6]\n", 'position = [1.9, 1.5]\non = "table"\n')


def test_a_close_look_from_too_close_raises_the_torso_first_and_the_grasp_starts_from_there(world):
    """An item on a table right in front is nearer the lens than its 0.8 m: the torso rises
    before the one look (no look from too close first), and stays up for the grasp, whose
    joints move from there; a drive lowers it while it drives, never faster than 0.2 m/s."""
    from tidyplan.worlds.pybullet.look import RECOGNISE_S

    scenario = loads(TABLE_TOY, "table-toy.toml")
    w = world(scenario)
    _place(w, (1.3, 1.5))
    w.hsr.set_base(1.3, 1.5, 0.0)
    clock = w.odometer.sim_time_s
    seen = w.locate((1.9, 1.5), 0.25, "toy")
    assert seen is not None
    spent = w.odometer.sim_time_s - clock
    assert w.hsr.q("arm_lift_joint") == pytest.approx(0.69)  # still up
    # the rise (0.69 m at 0.2 m/s) and one look: no second look, no way down counted
    assert 0.69 / 0.2 + RECOGNISE_S <= spent < 0.69 / 0.2 + RECOGNISE_S + 1.6
    out = w.follow([(1.3, 1.5), (1.2, 1.5)])  # a 0.1 m drive: 0.45 s, the torso's way down 3.45 s
    assert out.ok and out.seconds == pytest.approx(0.69 / 0.2, rel=1e-6)
    assert w.hsr.q("arm_lift_joint") == pytest.approx(0.0)


def test_on_the_way_to_an_item_too_close_below_the_lens_the_torso_rises_in_the_drives_own_time(world):
    """The close look at a toy on a table right in front needs the torso up: it rises in the
    drive's last seconds (no faster than the arm lift's 0.2 m/s, no frames kept meanwhile),
    and the look is then the detector's second and what the head has left to move."""
    from tidyplan.worlds.pybullet.look import RECOGNISE_S

    scenario = loads(TABLE_TOY, "table-toy.toml")
    w = world(scenario)
    w.hsr.set_base(0.3, 1.5, 0.0)
    w.robot = (0.3, 1.5)
    lifts: list[tuple[float, float]] = []
    arrive = w._arrive

    def spy(q, d, seconds):
        lifts.append((seconds, w.hsr.q("arm_lift_joint")))
        return arrive(q, d, seconds)

    w._arrive = spy
    out = w.follow([(0.3, 1.5), (1.3, 1.5)], face=(1.9, 1.5))
    assert out.ok and out.seconds == pytest.approx(1.0 / scenario.robot.speed, rel=1e-6)
    for (_, before), (seconds, after) in zip(lifts, lifts[1:], strict=False):
        assert after - before <= 0.2 * seconds + 1e-9
    assert w.hsr.q("arm_lift_joint") == pytest.approx(0.69)
    # the rise began 0.8 m before the end, before the first frame's half metre: no frame on the way,
    # and none from here with the torso up (the belief's frames are from the lens at its usual height)
    assert w.glance() == []
    clock = w.odometer.sim_time_s
    assert w.locate((1.9, 1.5), 0.25, "toy") is not None
    assert w.odometer.sim_time_s - clock < RECOGNISE_S + 0.3
