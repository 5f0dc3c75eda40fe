"""The WRS drawer in the pybullet world: a drawer on a prismatic joint in its carcass
(``sim.drawer``) that the HSR pulls open with its hand, with the symbolic world's faults (jam,
handle slip). The scenario and the symbolic world's drawer: test_drawer_world.py.
"""

from __future__ import annotations

from dataclasses import replace

import pybullet as p
import pytest

from sim.drawer import build
from sim.scenario.model import drawer_layout
from sim.scenario.read import load, loads
from tests.test_drawer_world import SURE, TRAVEL, WRS_DRAWER, _approach
from tidyplan.belief.geometry import RoomMap
from tidyplan.worlds.base import PULL_SPEED
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.symbolic import OPENING_S


@pytest.fixture(scope="module")
def scenario():
    return load(WRS_DRAWER)


@pytest.fixture
def bullet(scenario):
    """``bullet(rates)``: the pybullet world of wrs-drawer.toml; every one made is closed."""
    from tidyplan.worlds.pybullet.world import BulletWorld

    made = []

    def make(rates: Rates = SURE):
        made.append(BulletWorld(scenario, RoomMap(scenario), rates=rates))
        return made[-1]

    yield make
    for w in made:
        w.close()


SLIDES = """
schema = 1
name = "slides"
title = "a chest of drawers by a wall"
[room]
bounds = [0.0, 4.0, 0.0, 4.0]
entrance = [2.0, 2.0]
[[furniture]]
name = "chest"
center = [{cx}, {cy}]
size = [{sx}, {sy}]
height = 0.94
kind = "drawer"
[[deposit]]
name = "drawer"
category = "tool"
position = [{px}, {py}, 0.3]
approach = [{ax}, {ay}]
[deposit.drawer]
travel = 0.25
"""


@pytest.mark.parametrize(
    ("towards", "where"),
    [
        ("+x", dict(cx=0.3, cy=2.0, sx=0.44, sy=0.99, px=0.645, py=2.1, ax=1.12, ay=2.1)),
        ("-x", dict(cx=3.7, cy=2.0, sx=0.44, sy=0.99, px=3.355, py=1.9, ax=2.88, ay=1.9)),
        ("+y", dict(cx=2.0, cy=0.3, sx=0.99, sy=0.44, px=2.1, py=0.645, ax=2.1, ay=1.12)),
        ("-y", dict(cx=2.0, cy=3.7, sx=0.99, sy=0.44, px=1.9, py=3.355, ax=1.9, ay=2.88)),
    ],
)
def test_the_drawer_is_in_its_carcass_closed_and_out_of_it_open_whichever_way_it_slides(towards, where):

    s = loads(SLIDES.format(**where))
    layout = drawer_layout(s.furniture, s.deposits[0])
    k, sign = "xy".index(towards[1]), 1.0 if towards[0] == "+" else -1.0
    assert (layout.k, layout.sign) == (k, sign)
    client = p.connect(p.DIRECT)
    try:
        drawer = build(client, layout, (0.7, 0.7, 0.7), (0.5, 0.2, 0.5))
        (c0, c1) = p.getAABB(drawer.body, -1, physicsClientId=client)
        chest = s.furniture[0]
        assert (c0[k], c1[k]) == pytest.approx(
            ((chest.cx, chest.cy)[k] - 0.22, (chest.cx, chest.cy)[k] + 0.22)
        )
        assert c1[2] == pytest.approx(0.94)  # the carcass's box is the furniture's: the robot's map
        for opening in (0.0, 0.25):
            assert drawer.drive(opening) == opening
            lo, hi = p.getAABB(drawer.body, 0, physicsClientId=client)
            box = sorted((sign * (lo[k] - layout.front), sign * (hi[k] - layout.front)))
            # out of the face: closed all but the handle inside, open all of it out
            assert box == pytest.approx([opening - 0.25, opening + 0.035])
            inside = drawer.interior()
            assert (inside[2 * k], inside[2 * k + 1]) == pytest.approx(
                sorted(layout.front + sign * u for u in (opening - 0.238, opening - 0.012))
            )
            assert drawer.handle()[k] == pytest.approx(layout.front + sign * (opening + 0.0175))
            # the drawer rides in its slot touching nothing of the carcass
            assert p.getClosestPoints(drawer.body, drawer.body, 0.0, -1, 0, physicsClientId=client) == ()
    finally:
        p.disconnect(client)


def test_a_jammed_drawer_goes_no_farther_out_until_pushed_closed():

    s = loads(SLIDES.format(cx=0.3, cy=2.0, sx=0.44, sy=0.99, px=0.645, py=2.1, ax=1.12, ay=2.1))
    client = p.connect(p.DIRECT)
    try:
        drawer = build(client, drawer_layout(s.furniture, s.deposits[0]), (0.7, 0.7, 0.7), (0.5, 0.2, 0.5))
        assert drawer.drive(0.05) == pytest.approx(0.05)
        drawer.jam(0.1)
        assert drawer.drive(0.25) == pytest.approx(0.1)
        assert drawer.drive(0.05) == pytest.approx(0.05)  # in, it goes
        assert drawer.drive(0.25) == pytest.approx(0.1) and drawer.jammed == pytest.approx(0.1)
        assert drawer.drive(0.0) == 0.0 and drawer.jammed is None  # pushed closed: free again
        assert drawer.drive(0.3) == pytest.approx(0.25)  # no farther than its travel
        assert drawer.opening() == pytest.approx(0.25)
    finally:
        p.disconnect(client)


def _joint(world) -> float:
    drawer = world.scene.drawers["drawer"]
    return p.getJointState(drawer.body, 0, physicsClientId=world.client)[0]


def _drive_to(world, goal) -> None:
    """Drive the robot along a path of the grid from where it stands to ``goal``."""
    floor = [i.box() for i in world.scenario.items if i.on == "floor"]
    path = world.room.grid(floor).path(world.pose(), goal)
    assert path is not None
    out = world.follow(path + [goal])
    assert out.ok, out.failure


def _take(world, name: str) -> None:
    """Stand the grasp distance east of ``name`` and take it."""
    item = world.items[name]
    _, best, _ = world.grasp_distances(item.sz)
    world.hsr.set_base(item.x + best, item.y)
    world.robot = (item.x + best, item.y)
    out = world.grasp((item.x, item.y))
    assert out.ok and world.holds(), out.failure


@pytest.mark.slow
def test_pybullet_pull_opens_the_drawer_and_a_tool_put_in_is_tidied(bullet, scenario):
    w = bullet()
    approach = _approach(scenario)
    assert _joint(w) == pytest.approx(0.0)
    _drive_to(w, approach)
    assert w.pose() == approach
    clock = w.odometer.sim_time_s
    out = w.pull_handle("drawer")
    assert out.ok, out.failure
    assert _joint(w) == pytest.approx(TRAVEL, abs=1e-6)
    assert w.drawer_opening("drawer") == TRAVEL
    assert w.pose() == pytest.approx(approach, abs=1e-6)  # back where it pulled from
    # the base backed off by the travel with the drawer, and back: at least that, plus the hand
    assert out.metres >= 2 * TRAVEL and out.seconds > TRAVEL / PULL_SPEED + 2 * TRAVEL / 0.11
    assert w.odometer.sim_time_s - clock == pytest.approx(out.seconds + OPENING_S)
    assert w.openings["drawer"] == pytest.approx(w.scene.drawers["drawer"].interior())

    _take(w, "wrench")
    w.hsr.set_base(*approach)
    w.robot = approach
    put = w.place("drawer", approach)
    assert put.ok, put.failure
    wrench = w.items["wrench"]
    x0, x1, y0, y1 = w.scene.drawers["drawer"].interior()
    assert (wrench.state, wrench.deposit) == ("tidied", "drawer")
    assert x0 <= wrench.x <= x1 and y0 <= wrench.y <= y1
    (_, _, bottom), _ = p.getAABB(w.bodies["wrench"], physicsClientId=w.client)
    assert bottom == pytest.approx(0.30, abs=0.01)  # on the drawer's floor
    assert "wrench" not in w.untidied()

    # pushed closed, the wrench goes in with the drawer and stays tidied
    assert w.push_drawer("drawer").ok
    assert _joint(w) == pytest.approx(0.0, abs=1e-6)
    assert w.items["wrench"].x < -2.48 and "wrench" not in w.untidied()


@pytest.mark.slow
def test_pybullet_place_into_the_closed_drawer_keeps_the_tool_in_hand(bullet, scenario):
    w = bullet()
    _take(w, "wrench")
    approach = _approach(scenario)
    w.hsr.set_base(*approach)
    w.robot = approach
    out = w.place("drawer", approach)
    assert not out.ok and out.failure == "deposit_closed"
    assert w.holds() and w.items["wrench"].state == "held"
    assert "wrench" in w.untidied()
    assert w.pull_handle("drawer").failure == "hand_full"
    assert _joint(w) == pytest.approx(0.0)


@pytest.mark.slow
def test_pybullet_a_handle_out_of_the_arms_reach_is_not_pulled(bullet, scenario):
    w = bullet()
    approach = _approach(scenario)
    w.hsr.set_base(*approach)
    w.robot = approach
    drawer = w.scene.drawers["drawer"]
    # the robot told the handle is 0.3 m farther in than it is: 0.88 m out, past the whole-body reach
    drawer.layout = replace(drawer.layout, front=drawer.layout.front - 0.3)
    out = w.pull_handle("drawer")
    assert not out.ok and out.failure == "handle_unreached"
    assert _joint(w) == pytest.approx(0.0) and w.pose() == approach
    assert w.hsr.q("arm_lift_joint") == pytest.approx(0.0)  # stowed again


@pytest.mark.slow
def test_pybullet_jam_leaves_the_drawer_part_way_until_pushed_closed(bullet, scenario):
    w = bullet(Rates(drawer_jam=1.0, handle_slip=0.0))
    approach = _approach(scenario)
    w.hsr.set_base(*approach)
    w.robot = approach
    out = w.pull_handle("drawer")
    assert not out.ok and out.failure == "drawer_jammed"
    stuck = _joint(w)
    assert 0.3 * TRAVEL <= stuck <= 0.7 * TRAVEL
    assert w.pose() == pytest.approx(approach, abs=1e-6)
    again = w.pull_handle("drawer")
    assert again.failure == "drawer_jammed" and _joint(w) == pytest.approx(stuck)
    push = w.push_drawer("drawer")
    assert push.ok, push.failure
    assert _joint(w) == pytest.approx(0.0, abs=1e-6)
    assert w.scene.drawers["drawer"].jammed is None
    w.rates = SURE
    assert w.pull_handle("drawer").ok and _joint(w) == pytest.approx(TRAVEL)


@pytest.mark.slow
def test_pybullet_handle_slip_leaves_the_drawer_where_it_got(bullet, scenario):
    w = bullet(Rates(handle_slip=1.0))
    approach = _approach(scenario)
    w.hsr.set_base(*approach)
    w.robot = approach
    out = w.pull_handle("drawer")
    assert not out.ok and out.failure == "handle_slip"
    part = _joint(w)
    assert 0.0 < part < TRAVEL
    w.rates = SURE
    assert w.pull_handle("drawer").ok  # gripped again from as far off, it goes on
    assert _joint(w) == pytest.approx(TRAVEL)
