"""The robot's clock: every motion takes the time the HSR's speeds give it (../shared/HSR.md, as
docs/sources.md cites it), in both worlds; joints that move together take the slowest one's time,
not the sum; nothing moves faster than its limit. The figures below are the published ones,
written out here, not read from the code under test."""

from __future__ import annotations

import math

import pybullet as p
import pytest

from sim.robot import HSR
from sim.scenario.read import loads
from tests.test_bullet import DRIVE
from tidyplan.belief.geometry import RoomMap
from tidyplan.worlds.pybullet.world import BulletWorld
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.symbolic import SymbolicWorld

BASE = 0.22  # m/s: the design target, 0.8 km/h
YAW = 0.75  # rad/s: the yaw rate seen in one configuration
LIFT = 0.2  # m/s: arm_lift_joint (the torso follows at half its travel)
ARM_FLEX, ARM_ROLL, WRIST_FLEX, WRIST_ROLL = 1.2, 2.0, 1.5, 1.5  # rad/s
HEAD = 1.0  # rad/s: head_pan_joint and head_tilt_joint

# a path round the table: straight runs and corners, 5.1 m
PATH = [(0.8, 1.5), (1.4, 0.5), (2.6, 0.5), (3.2, 1.5), (2.6, 2.5), (1.4, 2.5), (0.8, 1.5)]
LENGTH = sum(math.dist(a, b) for a, b in zip(PATH, PATH[1:], strict=False))
QUIET = Rates(false_negative=0.0, false_positive=0.0)


@pytest.fixture
def hsr():
    client = p.connect(p.DIRECT)
    yield HSR(client)
    p.disconnect(client)


@pytest.fixture(params=["pybullet", "symbolic"])
def world(request):
    scenario = loads(DRIVE.replace("position = [1.0, 0.6]", "position = [3.8, 2.8]"), "drive.toml")
    room = RoomMap(scenario)
    w = (
        BulletWorld(scenario, room, rates=QUIET)
        if request.param == "pybullet"
        else SymbolicWorld(scenario, room)
    )
    if request.param == "pybullet":
        w.hsr.set_base(*PATH[0])
    w.robot = PATH[0]
    yield w
    if request.param == "pybullet":
        w.close()


@pytest.mark.parametrize("careful", [False, True])
def test_a_drive_takes_its_length_over_the_base_speed_in_both_worlds(world, careful):
    out = world.follow(PATH, careful=careful)
    assert out.ok
    assert out.metres == pytest.approx(LENGTH, abs=1e-6)
    # a pose adjustment (careful) runs at half the speed
    assert out.seconds == pytest.approx(LENGTH / (BASE / 2 if careful else BASE), rel=1e-6)


@pytest.mark.parametrize("world", ["pybullet"], indirect=True)  # the symbolic world has no head joints
def test_the_head_turns_toward_the_way_no_faster_than_its_joints(world):
    """Driving, the head pans toward the way: between two steps of the drive it turns at most
    what 1 rad/s gives in the step's time (the base itself does not turn while it drives)."""
    pans: list[tuple[float, float]] = []  # (seconds of the step, pan after it)
    arrive = world._arrive

    def spy(q, d, seconds):
        pans.append((seconds, world.hsr.q("head_pan_joint")))
        return arrive(q, d, seconds)

    world._arrive = spy
    yaw = world.hsr.base()[2]
    assert world.follow(PATH).ok
    assert world.hsr.base()[2] == pytest.approx(yaw)
    for (_, before), (seconds, after) in zip(pans, pans[1:], strict=False):
        assert abs(after - before) <= HEAD * seconds + 1e-9
    assert max(pan for _, pan in pans) - min(pan for _, pan in pans) > 1.0  # it did turn round


@pytest.mark.parametrize("world", ["pybullet"], indirect=True)  # the symbolic base has no heading
@pytest.mark.parametrize("length", [0.2, 1.2])  # shorter and longer than half a turn takes
def test_a_drive_that_turns_to_face_a_point_takes_the_longer_of_the_drive_and_the_turn(world, length):
    """The base is omnidirectional: it turns at its yaw rate while it drives, never faster, and
    what the drive was too short for is turned after it; it arrives facing the point."""
    world.hsr.set_base(1.4, 0.5, 0.0)  # along the table's south side (PATH's second leg)
    world.robot = (1.4, 0.5)
    end = (1.4 + length, 0.5)
    face = (end[0] - 1.0, 0.5)  # straight behind it: half a turn
    yaws: list[tuple[float, float]] = []  # (seconds of the step, yaw after it)
    arrive = world._arrive

    def spy(q, d, seconds):
        yaws.append((seconds, world.hsr.base()[2]))
        return arrive(q, d, seconds)

    world._arrive = spy
    out = world.follow([(1.4, 0.5), end], face=face)
    assert out.ok
    assert out.seconds == pytest.approx(max(length / BASE, math.pi / YAW), rel=1e-6)
    assert abs(abs(world.hsr.base()[2]) - math.pi) < 1e-9  # facing the point
    before = 0.0
    for seconds, yaw in yaws:
        assert abs(abs(yaw) - abs(before)) <= YAW * seconds + 1e-9
        before = yaw


@pytest.mark.parametrize("degrees", [30, 90, 180])
def test_a_turn_takes_its_angle_over_the_yaw_rate(hsr, degrees):
    hsr.set_base(0.0, 0.0, 0.0)
    a = math.radians(degrees)
    seconds = hsr.turn_to(math.cos(a), math.sin(a))
    assert seconds == pytest.approx(a / YAW)
    assert abs((hsr.base()[2] - a + math.pi) % (2 * math.pi) - math.pi) < 1e-9  # facing the point


@pytest.mark.parametrize(
    ("motion", "want"),
    [
        ({"arm_lift_joint": 0.69}, 0.69 / LIFT),  # the torso's 0.345 m at 0.1 m/s ends with it
        ({"arm_flex_joint": -1.2}, 1.2 / ARM_FLEX),
        ({"arm_roll_joint": 1.0}, 1.0 / ARM_ROLL),
        ({"wrist_flex_joint": -1.5}, 1.5 / WRIST_FLEX),
        ({"wrist_roll_joint": 3.0}, 3.0 / WRIST_ROLL),
        ({"head_pan_joint": -1.0}, 1.0 / HEAD),
        ({"head_tilt_joint": -0.8}, 0.8 / HEAD),
        # together: the slowest joint's time, not the sum
        ({"arm_lift_joint": 0.4, "arm_flex_joint": -1.2, "wrist_flex_joint": -1.5}, max(2.0, 1.0, 1.0)),
        ({"head_pan_joint": 0.5, "head_tilt_joint": -0.9}, 0.9 / HEAD),
    ],
)
def test_joints_take_their_travel_over_their_speed_the_slowest_of_those_moving_together(hsr, motion, want):
    hsr.set_joints({name: 0.0 for name in motion})  # from a posture where every delta is within limits
    start = {name: hsr.q(name) for name in motion}
    seconds = hsr.set_joints({name: hsr.q(name) + delta for name, delta in motion.items()})
    assert seconds == pytest.approx(want)
    for name, delta in motion.items():
        assert hsr.q(name) == pytest.approx(start[name] + delta)  # within the limits: all of it moved
