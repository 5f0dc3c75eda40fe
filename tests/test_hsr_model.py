"""The HSR model (sim/hsr.urdf, sim/robot.py) against its published figures (docs/sources.md):
joints, limits, speeds and axes, the base's size, the height with the torso down and up, the
torso following the arm lift, the gripper's opening."""

from __future__ import annotations

import math

import pybullet as p
import pytest

from sim.robot import GRIPPER_OPEN, HSR


@pytest.fixture
def client():
    """A physics server of its own (no window), closed after the test."""
    c = p.connect(p.DIRECT)
    yield c
    p.disconnect(c)


@pytest.fixture
def hsr(client) -> HSR:
    return HSR(client)


# ---------------------------------------------------------------------- the model
# name: (type, lower, upper, top speed, axis), from hsrb_description as docs/sources.md cites it
JOINTS = {
    "torso_lift_joint": (p.JOINT_PRISMATIC, 0.0, 0.345, 0.1, (0, 0, 1)),
    "head_pan_joint": (p.JOINT_REVOLUTE, -3.84, 1.75, 1.0, (0, 0, 1)),
    "head_tilt_joint": (p.JOINT_REVOLUTE, -1.57, 0.52, 1.0, (0, -1, 0)),
    "arm_lift_joint": (p.JOINT_PRISMATIC, 0.0, 0.69, 0.2, (0, 0, 1)),
    "arm_flex_joint": (p.JOINT_REVOLUTE, -2.62, 0.0, 1.2, (0, -1, 0)),
    "arm_roll_joint": (p.JOINT_REVOLUTE, -1.92, 3.67, 2.0, (0, 0, 1)),
    "wrist_flex_joint": (p.JOINT_REVOLUTE, -1.75, 1.22, 1.5, (0, -1, 0)),
    "wrist_roll_joint": (p.JOINT_REVOLUTE, -1.92, 3.67, 1.5, (0, 0, 1)),
    "hand_l_finger_joint": (p.JOINT_PRISMATIC, 0.0, 0.0675, None, (0, 1, 0)),
    "hand_r_finger_joint": (p.JOINT_PRISMATIC, 0.0, 0.0675, None, (0, -1, 0)),
}
BASE_JOINTS = {"base_x_joint": (1, 0, 0), "base_y_joint": (0, 1, 0), "base_yaw_joint": (0, 0, 1)}


def test_hsr_joints_have_the_types_limits_speeds_and_axes_of_hsrb_description(hsr):
    movable = {n for n, j in hsr.joints.items() if j.kind != p.JOINT_FIXED}
    assert movable == set(JOINTS) | set(BASE_JOINTS)
    for name, (kind, lower, upper, speed, axis) in JOINTS.items():
        j = hsr.joints[name]
        assert j.kind == kind, name
        assert (j.lower, j.upper) == pytest.approx((lower, upper), abs=1e-6), name
        if speed is not None:
            assert j.speed == pytest.approx(speed), name
        assert p.getJointInfo(hsr.body, j.index)[13] == pytest.approx(axis), name
    # the holonomic base: x and y slide, yaw turns without limit (0.22 m/s, 0.75 rad/s)
    for name, axis in BASE_JOINTS.items():
        j = hsr.joints[name]
        assert j.kind == (p.JOINT_REVOLUTE if name == "base_yaw_joint" else p.JOINT_PRISMATIC)
        assert p.getJointInfo(hsr.body, j.index)[13] == pytest.approx(axis), name
    assert hsr.joints["base_x_joint"].speed == pytest.approx(0.22)
    assert hsr.joints["base_yaw_joint"].speed == pytest.approx(0.75)


def test_hsr_base_is_430_mm_across_and_1_0_m_tall_torso_down_1_35_m_torso_up(hsr):
    (x0, y0, z0), (x1, y1, z1) = p.getAABB(hsr.body, hsr.base_link)
    assert 0.42 <= x1 - x0 <= 0.44 and 0.42 <= y1 - y0 <= 0.44, (x1 - x0, y1 - y0)
    assert z0 < 0.05  # the base stands on the floor

    def top(links) -> float:
        return max(p.getAABB(hsr.body, hsr.links[n])[1][2] for n in links)

    hsr.set_head(0.0, 0.0)  # the lens level, as the figures are given
    hsr.set_joints({"arm_lift_joint": 0.0})
    assert hsr.camera()[0][2] == pytest.approx(1.0, abs=0.05)
    assert top(hsr.links) == pytest.approx(1.0, abs=0.05)  # the whole robot, arm stowed
    hsr.set_joints({"arm_lift_joint": 0.69})
    assert hsr.camera()[0][2] == pytest.approx(1.35, abs=0.05)
    # the head's top (the raised arm, held upright, may rise above it)
    head = ("torso_lift_link", "head_pan_link", "head_tilt_link", "head_rgbd_sensor_link")
    assert top(head) == pytest.approx(1.35, abs=0.05)


def test_torso_follows_the_arm_lift_at_half_its_travel(hsr):
    seconds = hsr.set_joints({"arm_lift_joint": 0.4})
    assert hsr.q("arm_lift_joint") == pytest.approx(0.4)
    assert hsr.q("torso_lift_joint") == pytest.approx(0.2)
    assert seconds == pytest.approx(0.4 / 0.2)  # the lift at 0.2 m/s, the torso at 0.1 m/s
    hsr.set_joints({"arm_lift_joint": 0.69})
    assert hsr.q("torso_lift_joint") == pytest.approx(0.345)
    hsr.set_joints({"arm_lift_joint": 0.0})
    assert hsr.q("torso_lift_joint") == pytest.approx(0.0)


def test_gripper_opens_135_mm_between_its_two_prismatic_fingers(hsr):
    def gap() -> float:
        left = p.getLinkState(hsr.body, hsr.links["hand_l_finger_link"], computeForwardKinematics=True)[4]
        right = p.getLinkState(hsr.body, hsr.links["hand_r_finger_link"], computeForwardKinematics=True)[4]
        return math.dist(left, right)

    assert GRIPPER_OPEN == pytest.approx(0.0675)
    hsr.set_gripper(GRIPPER_OPEN)
    assert gap() == pytest.approx(0.135, abs=1e-4)
    hsr.set_gripper(0.2)  # no wider than the limits
    assert gap() == pytest.approx(0.135, abs=1e-4)
    hsr.set_gripper(0.0)
    assert gap() == pytest.approx(0.0, abs=1e-4)
