"""The belief written as a problem: the atoms the loop keeps as its state are exactly the init the
text states (the loop no longer parses its own text back every tick)."""

from __future__ import annotations

from pathlib import Path

from sim.scenario_file import load
from tidyplan.belief import Belief
from tidyplan.exec.symbolic import SymbolicWorld
from tidyplan.geometry import RoomMap
from tidyplan.pddl.reader import parse
from tidyplan.problem import write

ROOT = Path(__file__).resolve().parent.parent


def test_the_snapshots_atoms_are_the_init_its_text_states():
    for case in ("case1", "case2", "case3"):
        scenario = load(ROOT / "problems" / f"{case}.toml")
        room = RoomMap(scenario)
        belief = Belief(scenario, room)
        world = SymbolicWorld(scenario, room, seed=0)
        belief.observe(world.look(), None)
        goal = [k.name for k in belief.untidied()]
        assert goal, case  # something seen, so items, paths and blocks are all written
        for focused in (False, True):
            snap = write(belief, belief.facts(), goal, [("unseen-toy-1", "food")], "t", focused)
            init = {(x.predicate, *x.args) for x in parse(snap.text, "t.pddl").init}
            assert snap.atoms == init, (case, focused, snap.atoms ^ init)


def test_a_robot_shut_in_a_corner_by_an_item_it_dropped_grasps_it_from_where_it_stands():
    """An item dropped at the mouth of a pocket (here between the shelf and two walls) shuts the
    robot in. Its grasp pose must be one the robot reaches from where it stands, not one reached
    from the entrance: with that, every way out was blocked by the item and no plan could start
    (case III with faults, seed 1: a cup dropped beside the container)."""
    from tests.test_loop import _scenario
    from tidyplan.geometry import Placed

    scenario = _scenario("pocket", [("t1", 0.9, 2.5)])
    room = RoomMap(scenario)
    robot = (0.4, 2.5)
    cup = Placed("cup", "toy", 0.9, 2.5, sx=0.1, sy=0.6)  # a tray lying across the mouth
    facts = room.facts([cup], ("wp-robot", robot))
    assert ("wp-robot", "wp-entrance") in facts.blocked  # shut in, as the test means
    assert ("wp-robot", facts.grasp["cup"]) in facts.path or ("wp-robot", facts.grasp["cup"]) in facts.adjust


def test_an_item_that_fell_unseen_is_no_obstacle_where_the_robot_stands():
    """A dropped item is put where the robot stood until a look finds it (its place is not known):
    as an obstacle there it shut every way from the robot, and no plan could start (case III with
    faults, seed 1, a cup dropped four times on the way to the container). It still gets a grasp
    pose, from which the pick-up looks for it."""
    from tests.test_loop import _scenario
    from tidyplan.belief import Detection

    scenario = _scenario("fell", [("t1", 1.5, 2.0)])
    belief = Belief(scenario, RoomMap(scenario))
    belief.robot = (1.5, 1.5)
    name = belief.observe([Detection("toy", 1.5, 2.0, "floor")], None).new[0]
    belief.fell(name, belief.robot, 0.6)
    facts = belief.facts()
    robot = next(n for n, k in facts.kind.items() if k == "robot")
    assert (robot, "wp-entrance") in facts.path and (robot, "wp-box") in facts.path
    assert name in facts.grasp and (robot, facts.grasp[name]) in facts.path
