"""Orientation items (WRS Task 1: the markers tip down, the fork and the spoon handle up, in
container B): the scenario gives each its axis and down end, the detector reports it, the robot
puts it into the deposit for orientation items standing on that end, and pybullet decides from
its final pose whether it stands the right way (the axis within 30 degrees of straight down)."""

from __future__ import annotations

import json
import math

import numpy as np
import pybullet as p
import pytest

from sim.scenario.model import ORIENTATION, ScenarioError
from sim.scenario.read import loads
from sim.scenario.write import dumps
from tidyplan.belief.geometry import RoomMap
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.trace.score import wrs_score
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.symbolic import SymbolicWorld

ROOM = """
schema = 1
name = "markers"
title = "a marker to stand in container B"
[room]
bounds = [0.0, 3.0, 0.0, 3.0]
entrance = [2.6, 0.4]
heading_deg = 90.0
[[furniture]]
name = "deposit-table"
center = [0.3, 1.5]
size = [0.4, 1.2]
height = 0.4
kind = "table"
[[deposit]]
name = "container-b"
category = "orientation"
position = [0.3, 1.3, 0.4]
approach = [0.8, 1.3]
container = [0.095, 0.095, 0.105]
[[deposit]]
name = "tray"
category = "task"
position = [0.3, 1.8, 0.4]
approach = [0.8, 1.8]
[[item]]
name = "marker"
category = "tool"
position = [1.8, 1.0]
size = [0.121, 0.02, 0.02]
orientation = {{ axis = [{sign}, 0.0, 0.0], down = "tip" }}
[[item]]
name = "box"
category = "task"
position = [1.8, 2.0]
"""
EXACT = Rates(take=1.0, deliver=1.0, drop=1.0, false_negative=0.0, false_positive=0.0)


def _room(sign: float = 1.0, path: str = "m.toml"):
    return loads(ROOM.format(sign=sign), path)


def test_an_orientation_item_is_read_with_its_axis_made_a_unit_vector_and_written_back():
    text = ROOM.format(sign=1.0).replace("axis = [1.0, 0.0, 0.0]", "axis = [2.0, 0.0, 0.0]")
    s = loads(text, "m.toml")
    marker = next(i for i in s.items if i.name == "marker")
    assert marker.orientation.axis == (1.0, 0.0, 0.0) and marker.orientation.down == "tip"
    container = next(d for d in s.deposits if d.name == "container-b")
    assert container.container == (0.095, 0.095, 0.105) and container.takes(marker)
    again = loads(dumps(s), "m.toml")
    assert again.items == s.items and again.deposits == s.deposits


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            'axis = [1.0, 0.0, 0.0], down = "tip"',
            'down = "tip"',
            'item "marker".orientation.axis: missing required key',
        ),
        (
            "axis = [1.0, 0.0, 0.0]",
            "axis = [0, 0, 0]",
            'item "marker".orientation.axis: must not be [0, 0, 0]',
        ),
        ('down = "tip"', 'down = "Tip!"', "item \"marker\".orientation.down: 'Tip!' must match"),
        (
            "container = [0.095, 0.095, 0.105]",
            "container = [0.095, 0.095, 0.105]\n[deposit.drawer]\nclosed = true",
            'deposit "container-b".container: a deposit is a drawer or a container, not both',
        ),
        (
            'category = "task"\nposition = [0.3, 1.8, 0.4]',
            'category = "toys"\nposition = [0.3, 1.8, 0.4]',
            "deposit \"tray\".category: nothing can fill a deposit of 'toys'",
        ),
    ],
)
def test_a_bad_orientation_or_a_deposit_nothing_can_fill_is_refused_with_where(old, new, message):
    text = ROOM.format(sign=1.0)
    assert old in text
    with pytest.raises(ScenarioError) as err:
        loads(text.replace(old, new), "m.toml")
    assert any(m.startswith(f"m.toml: {message}") for m in err.value.messages), err.value.messages


def test_tidyplan_run_refuses_an_orientation_item_without_an_axis_before_any_world_starts(tmp_path):
    import subprocess
    import sys

    f = tmp_path / "m.toml"
    f.write_text(ROOM.format(sign=1.0).replace('axis = [1.0, 0.0, 0.0], down = "tip"', 'down = "tip"'))
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "tidyplan",
            "run",
            str(f),
            "--world",
            "symbolic",
            "--trace",
            str(tmp_path / "t.jsonl"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2, out.stderr
    assert f'{f}: item "marker".orientation.axis: missing required key' in out.stderr
    assert "Traceback" not in out.stderr and not (tmp_path / "t.jsonl").exists()


def test_the_referee_counts_an_orientation_item_in_its_box_or_in_its_categorys_deposit():
    s = _room()
    world = SymbolicWorld(s, RoomMap(s), seed=0, rates=EXACT)
    marker, box = world.items["marker"], world.items["box"]
    assert world.look() and all((d.down is not None) == (d.category == "tool") for d in world.look())
    marker.state, marker.deposit = "tidied", "container-b"
    box.state, box.deposit = "tidied", "container-b"  # a task item in the orientation box: wrong
    assert world.untidied() == ["box"]
    box.deposit = "tray"
    assert world.untidied() == []


def test_whether_an_item_is_an_orientation_item_follows_what_the_detector_says_of_it_now():
    """The object a look or a close look finds of a category near a believed one may be another
    one: a box beside a marker, both tools. Believed a marker still, the box was stood on its end
    in container B, out of which it toppled and fell off the table (wrs-task1-s002, pybullet)."""
    from tidyplan.belief.percepts import Detection
    from tidyplan.belief.state import Belief

    s = _room()
    belief = Belief(s, RoomMap(s))
    belief.robot = (1.8, 2.5)
    marker = Detection("tool", 1.8, 1.0, "floor", 0.121, 0.02, 0.02, down=(1.0, 0.0, 0.0))
    name = belief.observe([marker], None).new[0]
    assert belief.items[name].oriented
    box = Detection("tool", 1.81, 1.0, "floor", 0.07, 0.06, 0.15)  # no down end: not a marker
    assert belief.observe([box], None).confirmed == [name] and not belief.items[name].oriented
    belief.relocate(name, 1.8, 1.0, (0.121, 0.02, 0.02), oriented=True)  # a close look: the marker
    assert belief.items[name].oriented
    belief.relocate(name, 1.8, 1.0)  # a look that says nothing of it keeps what was known
    assert belief.items[name].oriented


def test_the_mission_stands_the_marker_in_container_b_and_scores_its_orientation(tmp_path):
    trace = tmp_path / "m.jsonl"
    summary = run(_room(), trace, Settings(world="symbolic", planner="lama-first", rates=EXACT))
    assert summary["success"], summary["reason"]
    events = [json.loads(line) for line in open(trace)]
    end = next(e for e in events if e["kind"] == "end")
    assert end["items"]["marker"][0] == "tidied:container-b" and end["standing"] == ["marker"]
    delivered = [e["action"] for e in events if e["kind"] == "action" and "deliver_it" in e["action"]]
    assert any("container-b" in a and ORIENTATION in a for a in delivered), delivered
    # 2 objects x (10 + 10), +10 the marker standing, +50 all put away in time; no drawers here
    assert summary["wrs_score"] == wrs_score(events) == 2 * 20 + 10 + 50


@pytest.fixture
def bullet():
    from tidyplan.worlds.pybullet.world import BulletWorld

    made = []

    def make(scenario):
        made.append(BulletWorld(scenario, RoomMap(scenario), rates=EXACT))
        return made[-1]

    yield make
    for w in made:
        w.close()


def _stand(world, at: tuple[float, float]) -> None:
    world.hsr.set_base(*at)
    world.robot = at


def _down(world, name: str) -> np.ndarray:
    orn = p.getBasePositionAndOrientation(world.bodies[name], physicsClientId=world.client)[1]
    m = np.reshape(p.getMatrixFromQuaternion(orn), (3, 3))
    return m @ np.asarray(world.items[name].orientation.axis)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_in_pybullet_a_lying_marker_is_stood_tip_down_in_container_b(bullet, sign):
    w = bullet(_room(sign))
    _stand(w, (2.25, 1.0))
    assert w.grasp((1.8, 1.0)).ok and w.holds()
    _stand(w, (0.8, 1.3))
    out = w.place("container-b", (0.8, 1.3))
    assert out.ok, out.failure
    marker = w.items["marker"]
    assert marker.state == "tidied" and marker.deposit == "container-b"
    down = _down(w, "marker")
    assert -down[2] >= math.cos(math.radians(30)), down  # the tip end down, within 30 degrees
    assert marker.stands is True and w.standing() == ["marker"]


def test_in_pybullet_a_marker_lying_in_container_b_does_not_stand(bullet):
    w = bullet(_room())
    marker = w.items["marker"]
    # laid across the box's rim as if let go flat: its axis level
    p.resetBasePositionAndOrientation(
        w.bodies["marker"], (0.3, 1.3, 0.52), (0, 0, 0, 1), physicsClientId=w.client
    )
    marker.state, marker.deposit = "tidied", "container-b"
    w._judge_stance("marker")
    assert marker.stands is False and w.standing() == []
    # upside down, the tip up: not standing the right way either
    flip = p.getQuaternionFromEuler((0.0, -math.pi / 2, 0.0))  # +x to +z
    p.resetBasePositionAndOrientation(w.bodies["marker"], (0.3, 1.3, 0.47), flip, physicsClientId=w.client)
    w._judge_stance("marker")
    assert _down(w, "marker")[2] > 0.9 and marker.stands is False


def test_in_pybullet_an_object_piled_on_another_on_a_tray_is_not_deposited(bullet):
    w = bullet(_room())
    # the box on the tray, the marker lying on top of it
    p.resetBasePositionAndOrientation(
        w.bodies["box"], (0.3, 1.8, 0.46), (0, 0, 0, 1), physicsClientId=w.client
    )
    p.resetBasePositionAndOrientation(
        w.bodies["marker"], (0.3, 1.8, 0.521), (0, 0, 0, 1), physicsClientId=w.client
    )
    for _ in range(120):
        p.stepSimulation(physicsClientId=w.client)
    tray = next(d for d in w.scenario.deposits if d.name == "tray")
    assert w._off_tray("box", tray) is None
    assert w._off_tray("marker", tray) == "piled on box"
    # on the table beside the tray: it touches the table
    p.resetBasePositionAndOrientation(
        w.bodies["box"], (0.3, 1.05, 0.451), (0, 0, 0, 1), physicsClientId=w.client
    )
    for _ in range(60):
        p.stepSimulation(physicsClientId=w.client)
    assert w._off_tray("box", tray) == "touches the table"
