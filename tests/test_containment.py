"""Objects stay in the room: nothing physics moves gets through or over a wall or the shut door,
or through a tray's rim, however it is dropped, pushed or knocked (the robot's part:
test_containment_robot.py).

The physics tests use case I's room (problems/case1.toml: the deposit table, the drawer and a
bin along the west wall, the shelf and the chair along the north wall, the door in the
south-east corner) and its own items, moved to every wall, corner and the door and sent towards
them at 1 to 3 m/s; the robot tests a bare room written here. Physics is stepped a fixed number
of steps: nothing depends on the machine's speed.
"""

from __future__ import annotations

import math
from pathlib import Path

import pybullet as p
import pytest

from sim.motion import settle
from sim.room import DOOR
from tidyplan.worlds.pybullet.world import BulletWorld

pytestmark = pytest.mark.slow

CASE1 = Path(__file__).resolve().parents[1] / "problems" / "case1.toml"  # the `case1` fixture's room
SPEEDS = (1.0, 2.0, 3.0)  # m/s towards the wall
IN = 0.15  # m from a wall to an item's centre
KNOCK = 12.0  # rad/s: an item tipped over towards the wall as it goes


def _outside(world: BulletWorld) -> dict[str, tuple[float, float]]:
    """Items whose centre (as pybullet has it) is outside the scenario's bounds: name -> x, y."""
    x0, x1, y0, y1 = world.scenario.bounds
    out = {}
    for name, body in world.bodies.items():
        x, y, _ = p.getBasePositionAndOrientation(body, physicsClientId=world.client)[0]
        if not (x0 <= x <= x1 and y0 <= y <= y1):
            out[name] = (round(x, 2), round(y, 2))
    return out


def _floor_spots(world: BulletWorld) -> dict[str, list[tuple[float, float, tuple[float, float]]]]:
    """(x, y, outward direction) on the floor IN from every wall (every 0.3 m, clear of the
    furniture), in every corner and in front of the door."""
    s = world.scenario
    x0, x1, y0, y1 = s.bounds
    walls = {
        "west": [(x0 + IN, y, (-1.0, 0.0)) for y in _steps(y0, y1)],
        "east": [(x1 - IN, y, (1.0, 0.0)) for y in _steps(y0, y1)],
        "south": [(x, y0 + IN, (0.0, -1.0)) for x in _steps(x0, x1)],
        "north": [(x, y1 - IN, (0.0, 1.0)) for x in _steps(x0, x1)],
    }
    h = math.sqrt(0.5)
    walls["corners"] = [
        (x0 + IN, y0 + IN, (-h, -h)),
        (x0 + IN, y1 - IN, (-h, h)),
        (x1 - IN, y0 + IN, (h, -h)),
        (x1 - IN, y1 - IN, (h, h)),
    ]
    ex, _ = s.entrance  # case I's door: in the south wall, DOOR wide about the entrance
    lo, hi = max(x0, ex - DOOR / 2), min(x1, ex + DOOR / 2)
    walls["door"] = [(x, y0 + IN, (0.0, -1.0)) for x in _steps(lo, hi, 0.25)]
    clear = {}
    for side, spots in walls.items():
        clear[side] = [q for q in spots if all(f.box().clearance(q[0], q[1]) > 0.2 for f in s.furniture)]
    return clear


def _steps(lo: float, hi: float, step: float = 0.3) -> list[float]:
    n = int((hi - lo - 2 * IN) / step)
    return [lo + IN + (hi - lo - 2 * IN) * k / max(n, 1) for k in range(n + 1)]


def _send(world: BulletWorld, body: int, at: tuple[float, float, float], towards, speed: float, knock: bool):
    """Put ``body`` upright at ``at`` and send it ``towards`` at ``speed``, tipping over towards
    it too when ``knock``."""
    p.resetBasePositionAndOrientation(body, at, (0, 0, 0, 1), physicsClientId=world.client)
    dx, dy = towards
    spin = (-dy * KNOCK, dx * KNOCK, 0.0) if knock else (0.0, 0.0, 0.0)  # about the axis along the wall
    p.resetBaseVelocity(body, (dx * speed, dy * speed, 0.0), spin, physicsClientId=world.client)


def _park(world: BulletWorld) -> None:
    """Every item out of the way, far outside the room, at rest (a test puts back what it uses)."""
    for k, body in enumerate(world.bodies.values()):
        p.resetBasePositionAndOrientation(
            body, (20.0 + k, 20.0, 1.0), (0, 0, 0, 1), physicsClientId=world.client
        )
        p.resetBaseVelocity(body, (0, 0, 0), (0, 0, 0), physicsClientId=world.client)


def _volley(world: BulletWorld, spots, speed: float, turn: int = 0) -> list[str]:
    """One item at every spot (at most as many as there are items), each sent towards its wall
    at ``speed`` in one of four ways, ``turn`` choosing which spot goes which way: pushed along
    what it stands on, knocked over as well, or either of them from 0.3 m up (falling from the
    hand as it goes); 2 s of physics; the items that ended outside the room."""
    _park(world)
    names = list(world.bodies)[: len(spots)]
    assert len(spots) == len(names), "more spots than items: split the volley"
    for k, ((x, y, z, towards), name) in enumerate(zip(spots, names, strict=True)):
        way = (k + turn) % 4
        body = world.bodies[name]
        (lo, hi) = p.getAABB(body, physicsClientId=world.client)
        up = 0.3 if way >= 2 else 0.0
        _send(world, body, (x, y, z + (hi[2] - lo[2]) / 2 + up), towards, speed, knock=way % 2 == 1)
    settle(world.hsr, 2.0)
    return [f"{n} at {xy}" for n, xy in _outside(world).items() if n in names]


@pytest.mark.parametrize("side", ["west", "east", "south", "north", "corners", "door"])
def test_items_sent_at_a_wall_or_the_door_stay_in_the_room(case1, side):
    spots = [(x, y, 0.0, d) for x, y, d in _floor_spots(case1)[side]]
    assert spots, f"no clear floor along the {side}"
    n = len(case1.bodies)
    escaped = []
    for turn, speed in enumerate(SPEEDS):
        for k in range(0, len(spots), n):
            escaped += [f"{o} ({speed} m/s)" for o in _volley(case1, spots[k : k + n], speed, turn)]
    assert not escaped, escaped


def test_items_knocked_off_the_deposits_by_the_wall_stay_in_the_room(case1):
    # the trays stand on the deposit table, the drawer and the bin by the west wall: a tall box
    # knocked off one towards the wall at 2 m/s went over 0.6 m walls
    spots = []
    for d in case1.scenario.deposits:
        spots += [(d.x, d.y, d.z + 0.01, (-1.0, 0.0)), (d.x + 0.1, d.y, d.z + 0.01, (-1.0, 0.0))]
    escaped = []
    for turn, speed in enumerate(SPEEDS):
        escaped += [f"{o} ({speed} m/s)" for o in _volley(case1, spots, speed, turn)]
    assert not escaped, escaped


def test_an_item_thrown_hard_at_a_trays_rim_does_not_pass_through_it(case1):
    # The rim is 2 cm thick: at 20 m/s an item moves 8 cm a step, and without continuous
    # collision detection it can be on the far side of the rim in the next (from 2 of 4 starts).
    d = case1.scenario.deposits[0]
    body = case1.bodies["banana"]
    rim = d.x - 0.2  # the west rim's centre
    through = []
    for speed in (20.0, 30.0, 40.0):
        for k in range(4):
            _park(case1)
            at = (d.x + 0.02 * k, d.y, d.z + 0.01 + 0.025)
            p.resetBasePositionAndOrientation(body, at, (0, 0, 0, 1), physicsClientId=case1.client)
            p.resetBaseVelocity(body, (-speed, 0.0, 0.0), (0, 0, 0), physicsClientId=case1.client)
            for _ in range(12):  # 0.05 s: long enough to cross the tray, not to come back
                p.stepSimulation(physicsClientId=case1.client)
            x = p.getBasePositionAndOrientation(body, physicsClientId=case1.client)[0][0]
            if x < rim:
                through.append(f"{speed} m/s from {at[0]:.2f}: x {x:.2f}")
    assert not through, through


def test_an_item_pushed_into_a_wall_comes_out_on_the_rooms_side(case1):
    # Its centre 6 cm (a small item, half in) to 12 cm (a tall box) past the wall's face: the
    # wall is 0.3 m thick, so the way back into the room is the shorter one. A 0.10 m wall
    # let each out on the far side (measured; one wholly inside a 0.3 m wall stays in it).
    x0, _, _, _ = case1.scenario.bounds
    outside = []
    for name, depth in (("banana", 0.06), ("box-task", 0.06), ("box-task", 0.12)):
        _park(case1)
        body = case1.bodies[name]
        (lo, hi) = p.getAABB(body, physicsClientId=case1.client)
        at = (x0 - depth, -1.2, (hi[2] - lo[2]) / 2 + 0.001)
        p.resetBasePositionAndOrientation(body, at, (0, 0, 0, 1), physicsClientId=case1.client)
        settle(case1.hsr, 1.0)
        x = p.getBasePositionAndOrientation(body, physicsClientId=case1.client)[0][0]
        if x < x0:
            outside.append(f"{name} {depth} m in: x {x:.2f}")
    assert not outside, outside
