"""Physics after a release is stepped until what was let go has come to rest, not a fixed second:
stepping on moves nothing (sim/motion.py ``settle``)."""

from __future__ import annotations

import math

import pybullet as p
import pytest

from sim.motion import REST_AFTER, REST_SPEED, TIME_STEP, settle
from tidyplan.worlds.pybullet.world import BulletWorld

pytestmark = pytest.mark.slow


def _drop(w: BulletWorld, body: int, height: float) -> None:
    p.resetBasePositionAndOrientation(body, (-0.5, -0.3, height), (0, 0, 0, 1), physicsClientId=w.client)
    p.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=w.client)


def test_a_dropped_object_is_stepped_until_it_rests_and_no_longer(case1):
    body = next(iter(case1.bodies.values()))
    _drop(case1, body, 0.3)
    stepped = settle(case1.hsr, 2.0, [body])
    assert REST_AFTER <= stepped < 2.0
    linear, angular = p.getBaseVelocity(body, physicsClientId=case1.client)
    assert max(map(abs, linear)) < REST_SPEED
    assert max(map(abs, angular)) < 10 * REST_SPEED
    rest = p.getBasePositionAndOrientation(body, physicsClientId=case1.client)[0]
    assert rest[2] < 0.3  # it fell
    # a second more of physics moves it by less than a millimetre: the rest was real
    assert settle(case1.hsr, 1.0) == pytest.approx(round(1.0 / TIME_STEP) * TIME_STEP)
    after = p.getBasePositionAndOrientation(body, physicsClientId=case1.client)[0]
    assert math.dist(rest, after) < 1e-3


def test_without_bodies_to_watch_the_whole_time_is_stepped(case1):
    body = next(iter(case1.bodies.values()))
    _drop(case1, body, 0.3)
    assert settle(case1.hsr, 0.5) == pytest.approx(round(0.5 / TIME_STEP) * TIME_STEP)


def test_a_body_still_falling_at_the_limit_is_stepped_to_the_limit(case1):
    body = next(iter(case1.bodies.values()))
    _drop(case1, body, 5.0)  # 5 m up: a free fall takes 1 s
    assert settle(case1.hsr, 0.5, [body]) == pytest.approx(round(0.5 / TIME_STEP) * TIME_STEP)
