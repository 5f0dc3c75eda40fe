"""The rules of where and how the hand lets go (tidyplan/worlds/pybullet/put.py) and how far the arm
reaches (sim/robot.py), each checked on its own: pybullet's maths and one robot, no room."""

from __future__ import annotations

import math

import pybullet as p
import pytest

from sim.robot import HSR, REACHED, hand_level
from tidyplan.worlds.pybullet.put import fits, heading, held_as, stood_up

CRATE = (0.19, 0.19, 0.45)
BIN = (-0.175, 0.175, -0.15, 0.15)  # a WRS bin's inside: 0.35 x 0.30


@pytest.fixture(scope="module")
def client():
    c = p.connect(p.DIRECT)
    yield c
    p.disconnect(c)


def test_a_box_fits_a_deposit_only_with_both_sides_inside_turned_square():
    assert fits((0.19, 0.19), BIN)
    assert fits((0.08, 0.30 - 0.01), BIN)  # along the bin's long side is the one way in
    assert not fits((0.19, 0.45), BIN)  # a crate lying
    assert not fits((0.36, 0.08), BIN)


def test_a_standing_crate_is_held_as_it_stands_and_not_stood_up(client):
    hand_at, hand = (0.0, 0.0, 0.3), hand_level(0.0)  # its side, half way up
    centre, upright = (0.085, 0.0, 0.225), p.getQuaternionFromEuler((0, 0, 0.3))
    held = held_as(hand_at, hand, centre, upright, CRATE)
    assert held.footprint == (0.19, 0.19)
    assert held.centre_height == pytest.approx(0.225)
    assert held.hand_height == pytest.approx(0.3)
    assert held.heading == pytest.approx(0.3)
    assert stood_up(hand_at, hand, centre, upright, CRATE) is None


@pytest.mark.parametrize("yaw", [0.0, 0.4, -1.2, math.pi / 2])
def test_a_lying_crate_taken_from_the_top_is_stood_on_its_end_with_the_hand_level(client, yaw):
    lying = p.getQuaternionFromEuler((math.pi / 2, 0.0, yaw))  # its long side along the floor
    centre = (1.0, 2.0, 0.095)
    hand_at = (1.0, 2.0, 0.16)  # the top grasp: 3 cm below its top, over its centre
    down = p.getQuaternionFromEuler((0.0, math.pi, 0.0))
    held = held_as(hand_at, down, centre, lying, CRATE)
    assert sorted(held.footprint) == [0.19, 0.45]
    assert held.centre_height == pytest.approx(0.095, abs=1e-6)
    stood = stood_up(hand_at, down, centre, lying, CRATE)
    assert stood is not None
    assert stood.footprint == (0.19, 0.19)
    assert stood.centre_height == pytest.approx(0.225, abs=1e-6)
    assert stood.hand_height == pytest.approx(0.225, abs=1e-6)  # the grip half way along it
    fingertips = p.getMatrixFromQuaternion(stood.hand)[8]  # the hand's z axis, vertical part
    assert abs(fingertips) < 1e-6  # level: the side grasp of the standing crate
    # its sides keep their heading about the vertical (modulo a quarter turn)
    off = (stood.heading - heading(lying) + math.pi / 4) % (math.pi / 2) - math.pi / 4
    assert off == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize(
    "height, out", [(0.1, 0.55), (0.1, 0.6), (0.2, 0.65), (0.3, 0.45), (0.3, 0.7), (0.4, 0.65), (0.4, 0.7)]
)
def test_a_level_hand_pointing_across_the_base_is_reached_low_and_far(client, height, out):
    # From the four arm postures alone, pybullet's solver did not reach a level hand pointing 90
    # degrees from the base's heading at these (bench/reach.py at 00c6237: 0.5-0.6 m out at 0.2
    # and 0.3 m up, 0.5 m at 0.1 m), and stopped 3 to 16 cm short of a crate held over case
    # III's bin. The level postures start it where the hand is level at that height and reach.
    robot = HSR(client)
    try:
        _, err = robot.reach((out, 0.0, height), hand_level(math.pi / 2), strict=True)
        assert err <= REACHED
    finally:
        p.removeBody(robot.body, physicsClientId=client)
