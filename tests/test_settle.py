"""Physics after a release is stepped until what was let go has come to rest, not a fixed second:
stepping on moves nothing (sim/motion.py ``settle``)."""

from __future__ import annotations

import math
from pathlib import Path

import pybullet as p
import pytest

from sim.motion import REST_AFTER, REST_SPEED, TIME_STEP, settle
from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.worlds.pybullet.world import BulletWorld
from tidyplan.worlds.rates import Rates

pytestmark = pytest.mark.slow

CASE1 = Path(__file__).resolve().parents[1] / "problems" / "case1.toml"


@pytest.fixture(scope="module")
def world():
    scenario = load(CASE1)
    w = BulletWorld(scenario, RoomMap(scenario), rates=Rates(false_negative=0.0, false_positive=0.0))
    w.hsr.set_base(-1.4, -0.3)
    yield w
    w.close()


def _drop(w: BulletWorld, body: int, height: float) -> None:
    p.resetBasePositionAndOrientation(body, (-0.5, -0.3, height), (0, 0, 0, 1), physicsClientId=w.client)
    p.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=w.client)


def test_a_dropped_object_is_stepped_until_it_rests_and_no_longer(world):
    body = next(iter(world.bodies.values()))
    _drop(world, body, 0.3)
    stepped = settle(world.hsr, 2.0, [body])
    assert REST_AFTER <= stepped < 2.0
    linear, angular = p.getBaseVelocity(body, physicsClientId=world.client)
    assert max(map(abs, linear)) < REST_SPEED
    assert max(map(abs, angular)) < 10 * REST_SPEED
    rest = p.getBasePositionAndOrientation(body, physicsClientId=world.client)[0]
    assert rest[2] < 0.3  # it fell
    # a second more of physics moves it by less than a millimetre: the rest was real
    assert settle(world.hsr, 1.0) == pytest.approx(round(1.0 / TIME_STEP) * TIME_STEP)
    after = p.getBasePositionAndOrientation(body, physicsClientId=world.client)[0]
    assert math.dist(rest, after) < 1e-3


def test_without_bodies_to_watch_the_whole_time_is_stepped(world):
    body = next(iter(world.bodies.values()))
    _drop(world, body, 0.3)
    assert settle(world.hsr, 0.5) == pytest.approx(round(0.5 / TIME_STEP) * TIME_STEP)


def test_a_body_still_falling_at_the_limit_is_stepped_to_the_limit(world):
    body = next(iter(world.bodies.values()))
    _drop(world, body, 5.0)  # 5 m up: a free fall takes 1 s
    assert settle(world.hsr, 0.5, [body]) == pytest.approx(round(0.5 / TIME_STEP) * TIME_STEP)
