"""The WRS drawer, the world side: problems/wrs-drawer.toml's tools' deposit is a closed drawer
that must be pulled open by its handle (RoboCup 2021 DSPL rules). The symbolic world models it
as a number (how far it is out) with the same faults as the pybullet world, where it is a
drawer on a prismatic joint in its carcass (``sim.drawer``) that the HSR pulls with its hand.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pybullet as p
import pytest

from sim.drawer import build
from sim.scenario import drawer_layout
from sim.scenario_file import load, loads
from tidyplan.cli_run import parse_faults
from tidyplan.exec.symbolic import HANDLE_S, OPENING_S, SymbolicWorld
from tidyplan.exec.world import PULL_SPEED, Rates
from tidyplan.geometry import RoomMap

WRS_DRAWER = Path(__file__).resolve().parents[1] / "problems" / "wrs-drawer.toml"
SURE = Rates(take=1.0, deliver=1.0, drop=1.0, false_negative=0.0, false_positive=0.0, handle_slip=0.0)
TRAVEL = 0.25


@pytest.fixture(scope="module")
def scenario():
    return load(WRS_DRAWER)


def _approach(scenario) -> tuple[float, float]:
    return next(d.approach for d in scenario.deposits if d.name == "drawer")


def _symbolic(scenario, rates: Rates = SURE, seed: int = 0) -> SymbolicWorld:
    w = SymbolicWorld(scenario, RoomMap(scenario), seed=seed, rates=rates)
    w.robot = _approach(scenario)
    return w


def _hold(world, name: str) -> None:
    """Put ``name`` in the hand, as a grasp would (the symbolic world's truth)."""
    world.items[name].state, world.holding = "held", name


# ---------------------------------------------------------------------- the scenario
def test_wrs_drawer_is_case1s_room_with_the_tools_deposit_a_closed_drawer(scenario):
    case1 = load(WRS_DRAWER.with_name("case1.toml"))
    assert scenario.items == case1.items and scenario.viewpoints == case1.viewpoints
    assert scenario.prior == case1.prior and scenario.expect == case1.expect
    (tools,) = [d for d in scenario.deposits if d.category == "tool"]
    assert tools.name == "drawer" and tools.drawer.closed and tools.drawer.travel == TRAVEL
    chest = drawer_layout(scenario.furniture, tools).carcass
    old = case1.furniture_named("drawer")
    assert (chest.name, chest.cx, chest.cy, chest.sx, chest.sy, chest.height) == (
        "chest", old.cx, old.cy, old.sx, old.sy, old.height,
    )  # fmt: skip
    assert [d for d in scenario.deposits if d.name != "drawer"] == [
        d for d in case1.deposits if d.name != "drawer-top"
    ]


def test_the_drawer_slides_out_towards_the_approach_and_clears_the_base(scenario):
    d = next(d for d in scenario.deposits if d.name == "drawer")
    layout = drawer_layout(scenario.furniture, d)
    assert (layout.k, layout.sign, layout.front) == (0, 1.0, pytest.approx(-2.48))
    assert layout.depth == pytest.approx(0.25)  # closed flush with the carcass's face
    assert layout.interior(TRAVEL) == pytest.approx((-2.468, -2.242, 0.8, 1.2))
    assert layout.exposed(0.0)[1] - layout.exposed(0.0)[0] == pytest.approx(0.0)  # closed: nothing to put in
    assert layout.exposed(TRAVEL) == pytest.approx(layout.interior(TRAVEL))  # open: all of it is out
    handle = layout.handle(0.0)
    assert 0.2 <= handle[2] <= 0.5  # where the level hand reaches, 0.45-0.70 m out (bench/reach.py)
    assert 0.45 <= math.dist(handle[:2], d.approach) <= 0.70
    open_front = layout.point(TRAVEL + 0.035)[0]  # the open drawer's handle, outermost
    assert d.approach[0] - scenario.robot.radius - open_front == pytest.approx(0.095)


def test_faults_name_the_drawer_rates():
    rates = parse_faults("handle_slip=0.3,drawer_jam=0.2")
    assert (rates.handle_slip, rates.drawer_jam) == (0.3, 0.2)
    # by default a pull slips at 1 - open_drawer's probability in tidy.pddl (0.95); no jams
    assert (Rates().handle_slip, Rates().drawer_jam) == (0.05, 0.0)
    assert parse_faults("").handle_slip == 0.05


# ---------------------------------------------------------------------- the symbolic world
def test_symbolic_pull_opens_the_drawer_by_its_travel(scenario):
    w = _symbolic(scenario)
    assert w.drawer_opening("drawer") == 0.0
    assert w.odometer.sim_time_s == OPENING_S
    out = w.pull_handle("drawer")
    assert out.ok and out.failure is None
    assert out.seconds == pytest.approx(HANDLE_S + TRAVEL / PULL_SPEED)
    assert w.drawer_opening("drawer") == TRAVEL
    assert w.pull_handle("drawer").seconds == OPENING_S  # out already


def test_symbolic_pull_needs_an_empty_hand_at_the_approach(scenario):
    w = _symbolic(scenario)
    _hold(w, "wrench")
    assert w.pull_handle("drawer").failure == "hand_full"
    w.holding, w.items["wrench"].state = None, "placed"
    w.robot = (-1.5, 0.3)
    assert w.pull_handle("drawer").failure == "not_at_deposit"
    assert w.drawer_opening("drawer") == 0.0


def test_a_pull_draws_the_same_numbers_whatever_happens(scenario):
    refused, pulled = _symbolic(scenario, seed=7), _symbolic(scenario, seed=7)
    _hold(refused, "wrench")
    assert refused.pull_handle("drawer").failure == "hand_full"
    assert pulled.pull_handle("drawer").ok
    assert refused.rng.random() == pulled.rng.random()


def test_symbolic_handle_slip_leaves_the_drawer_part_way_and_the_next_pull_goes_on(scenario):
    w = _symbolic(scenario, Rates(handle_slip=1.0))
    out = w.pull_handle("drawer")
    assert not out.ok and out.failure == "handle_slip"
    part = w.drawer_opening("drawer")
    assert 0.0 < part < TRAVEL
    assert out.seconds == pytest.approx(HANDLE_S + part / PULL_SPEED, abs=0.01)
    w.rates = SURE
    assert w.pull_handle("drawer").ok
    assert w.drawer_opening("drawer") == TRAVEL


def test_symbolic_jam_sticks_the_drawer_until_pushed_closed(scenario):
    w = _symbolic(scenario, Rates(drawer_jam=1.0, handle_slip=0.0))
    out = w.pull_handle("drawer")
    assert not out.ok and out.failure == "drawer_jammed"
    stuck = w.drawer_opening("drawer")
    assert 0.3 * TRAVEL <= stuck <= 0.7 * TRAVEL
    w.rates = SURE  # no new jam: it is the old one that holds it
    assert w.pull_handle("drawer").failure == "drawer_jammed"
    assert w.drawer_opening("drawer") == stuck
    push = w.push_drawer("drawer")
    assert push.ok and push.seconds == pytest.approx(HANDLE_S + stuck / PULL_SPEED, abs=0.01)
    assert w.drawer_opening("drawer") == 0.0
    assert w.pull_handle("drawer").ok and w.drawer_opening("drawer") == TRAVEL


def test_the_same_seed_jams_the_drawer_at_the_same_point(scenario):
    faults = Rates(drawer_jam=0.5, handle_slip=0.5)
    runs = []
    for _ in range(2):
        w = _symbolic(scenario, faults, seed=3)
        runs.append([(w.pull_handle("drawer").failure, w.drawer_opening("drawer")) for _ in range(4)])
    assert runs[0] == runs[1]


def test_symbolic_place_into_a_closed_drawer_keeps_the_item_in_hand(scenario):
    w = _symbolic(scenario)
    _hold(w, "wrench")
    out = w.place("drawer", _approach(scenario))
    assert not out.ok and out.failure == "deposit_closed"
    assert w.holds() and w.items["wrench"].state == "held"
    assert "wrench" in w.untidied()


def test_symbolic_place_into_the_open_drawer_tidies_the_item(scenario):
    w = _symbolic(scenario)
    assert w.pull_handle("drawer").ok
    inside = drawer_layout(scenario.furniture, next(d for d in scenario.deposits if d.name == "drawer"))
    for name in ("wrench", "screwdriver", "tool-hidden"):
        _hold(w, name)
        out = w.place("drawer", _approach(scenario))
        assert out.ok and not w.holds()
        x0, x1, y0, y1 = inside.interior(TRAVEL)
        item = w.items[name]
        assert (item.state, item.deposit) == ("tidied", "drawer")
        assert x0 <= item.x <= x1 and y0 <= item.y <= y1
    assert not {"wrench", "screwdriver", "tool-hidden"} & set(w.untidied())
    # pushed closed, they go in with it, still tidied
    assert w.push_drawer("drawer").ok
    x0, x1, y0, y1 = inside.interior(0.0)
    assert all(x0 <= w.items[n].x <= x1 for n in ("wrench", "screwdriver", "tool-hidden"))
    assert not {"wrench", "screwdriver", "tool-hidden"} & set(w.untidied())


# ---------------------------------------------------------------------- the pybullet world
@pytest.fixture
def bullet(scenario):
    """``bullet(rates)``: the pybullet world of wrs-drawer.toml; every one made is closed."""
    from tidyplan.exec.bullet import BulletWorld

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
