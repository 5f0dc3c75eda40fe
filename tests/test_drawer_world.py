"""The WRS drawer, the world side: problems/wrs-drawer.toml's tools' deposit is a closed drawer
that must be pulled open by its handle (RoboCup 2021 DSPL rules). The symbolic world models it
as a number (how far it is out) with the same faults as the pybullet world, where it is a
drawer on a prismatic joint in its carcass (``sim.drawer``) that the HSR pulls with its hand
(those tests: test_drawer_bullet.py).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from sim.scenario.model import drawer_layout
from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.worlds.base import PULL_SPEED
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.symbolic import HANDLE_S, OPENING_S, SymbolicWorld

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
    rates = Rates.parse("handle_slip=0.3,drawer_jam=0.2")
    assert (rates.handle_slip, rates.drawer_jam) == (0.3, 0.2)
    # by default a pull slips at 1 - open_drawer's probability in tidy.pddl (0.95); no jams
    assert (Rates().handle_slip, Rates().drawer_jam) == (0.05, 0.0)
    assert Rates.parse("").handle_slip == 0.05


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
