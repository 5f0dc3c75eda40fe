"""The arm's geometry as a first answer to a reach (sim/robot.py ``HSR._may_reach_down``): a
target it rules out is one no solve reaches, so a reach answers the same with it as without it,
only without the hundred-iteration solves that fail."""

from __future__ import annotations

import math
import random

import pybullet as p
import pytest

from sim.robot import ARM, HAND_DOWN, HSR, NEAR_DOWN, REACHED, TILT


@pytest.fixture(scope="module")
def hsr():
    """A physics server of its own (no window), closed after the tests."""
    c = p.connect(p.DIRECT)
    yield HSR(c)
    p.disconnect(c)


def _fingertips_from_down(orientation) -> float:
    return math.acos(max(-1.0, min(1.0, -p.getMatrixFromQuaternion(orientation)[8])))


def test_no_posture_of_the_arm_is_ruled_out(hsr):
    """Every posture of the arm's five joints and the base's yaw (random, uniform in the limits)
    whose fingertips point near down puts the hand's frame, and a point it carries, where the
    check says the arm may reach: the check never says no to what the arm does."""
    rng = random.Random(7)
    hsr.set_base(0.3, -0.2, 0.0)
    checked = 0
    for _ in range(20000):
        q = {n: rng.uniform(hsr.joints[n].lower, hsr.joints[n].upper) for n in ARM}
        hsr.set_joints({**q, "base_yaw_joint": rng.uniform(-math.pi, math.pi)})
        pos, orn = hsr.hand()
        if _fingertips_from_down(orn) > NEAR_DOWN - TILT:
            continue
        checked += 1
        carried = (rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03), rng.uniform(0.0, 0.12))
        target = p.multiplyTransforms(pos, orn, carried, (0, 0, 0, 1))[0]
        offset = p.multiplyTransforms((0, 0, 0), orn, carried, (0, 0, 0, 1))[0]
        aim = tuple(t - o for t, o in zip(target, offset, strict=True))
        assert hsr._may_reach_down(aim, orn, offset), (q, pos)
    assert checked > 300  # enough postures near down were drawn to mean something


def test_what_it_rules_out_the_solver_does_not_reach_and_the_rest_it_answers_alike(hsr, monkeypatch):
    """On a grid of targets around the base, hand down: where the check says no, the whole
    solver (the check turned off) does not reach either; a reach answers the same either way,
    and the check does say no to some (it saves their solves)."""
    hsr.set_base(0.0, 0.0, 0.0)
    targets = [(r, z) for r in (0.25, 0.45, 0.6, 0.75, 0.95) for z in (0.05, 0.5, 0.95, 1.3)]
    with_check = {t: hsr.reach((t[0], 0.0, t[1]), HAND_DOWN, strict=True) for t in targets}
    ruled_out = {t for t in targets if not hsr._may_reach_down((t[0], 0.0, t[1]), HAND_DOWN, (0, 0, 0))}
    monkeypatch.setattr(HSR, "_may_reach_down", lambda self, aim, wanted, offset: True)
    for t in targets:
        _, err = hsr.reach((t[0], 0.0, t[1]), HAND_DOWN, strict=True)
        assert (err <= REACHED) == (with_check[t][1] <= REACHED), t
        if t in ruled_out:
            assert err > REACHED and with_check[t] == ({}, math.inf), t
    assert len(ruled_out) >= 5 and len(ruled_out) < len(targets)


def test_an_orientation_far_from_down_is_not_judged(hsr):
    level = p.getQuaternionFromEuler((0.0, math.pi / 2, 0.0))  # fingertips ahead: a side grasp
    assert _fingertips_from_down(level) + TILT > NEAR_DOWN
    hsr.set_base(0.0, 0.0, 0.0)
    assert hsr._may_reach_down((5.0, 0.0, 3.0), level, (0, 0, 0))  # left to the solver
    assert not hsr._may_reach_down((5.0, 0.0, 3.0), HAND_DOWN, (0, 0, 0))
