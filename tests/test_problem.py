"""The belief written as a problem: the atoms the loop keeps as its state are exactly the init the
text states (the loop no longer parses its own text back every tick)."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.problem import write
from tidyplan.belief.state import Belief
from tidyplan.pddl.reader import parse
from tidyplan.worlds.symbolic import SymbolicWorld

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


def test_the_monitors_state_is_the_unfocused_snapshots_atoms_with_and_without_a_domain():
    """belief_state (the map's atoms as a set kept with the map) is write(...).atoms, for the
    shipped domain and for none, before a look and after."""
    from tidyplan.belief.problem import belief_state
    from tidyplan.loop.scenarios import DOMAIN

    tidy = parse(DOMAIN.read_text(), "tidy.pddl")
    for case in ("case1", "case3"):
        scenario = load(ROOT / "problems" / f"{case}.toml")
        belief = Belief(scenario, RoomMap(scenario))
        world = SymbolicWorld(scenario, belief.room, seed=0)
        virtual = [("unseen-toy-1", "food")]
        # before and after a look (a new map, then the same one asked again), after a move (the
        # floor's pairs shared, the robot's own), after a move found blocked (pairs dropped)
        for turn in range(4):
            facts = belief.facts()
            for domain in (None, tidy):
                want = write(belief, facts, [], virtual, "t", domain=domain).atoms
                got = belief_state(belief, facts, virtual, domain)
                assert got == want, (case, turn, got ^ want)
                assert set(got) == want and len(got) == len(want)
                assert any(a[0] == "path" for a in got)
            if turn == 0:
                belief.observe(world.look(), None)
            elif turn == 1:
                free = belief.room.grid(()).free_cells(reachable_from=belief.room.entrance)
                belief.at(free[len(free) // 2], "wp-went-there")  # no waypoint: the robot's own
            elif turn == 2:
                (a, b), _ = next((ab, d) for ab, d in facts.path.items() if facts.kind[ab[0]] != "robot")
                belief.blocked_moves.add((facts.points[a], facts.points[b]))
        assert facts.dropped and facts.own.path  # the layers were there to test


def test_a_robot_shut_in_a_corner_by_an_item_it_dropped_grasps_it_from_where_it_stands():
    """An item dropped at the mouth of a pocket (here between the shelf and two walls) shuts the
    robot in. Its grasp pose must be one the robot reaches from where it stands, not one reached
    from the entrance: with that, every way out was blocked by the item and no plan could start
    (case III with faults, seed 1: a cup dropped beside the container)."""
    from tests.test_loop import _scenario
    from tidyplan.belief.mapfacts import Placed

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
    from tidyplan.belief.percepts import Detection

    scenario = _scenario("fell", [("t1", 1.5, 2.0)])
    belief = Belief(scenario, RoomMap(scenario))
    belief.robot = (1.5, 1.5)
    name = belief.observe([Detection("toy", 1.5, 2.0, "floor")], None).new[0]
    belief.fell(name, belief.robot, 0.6)
    facts = belief.facts()
    robot = next(n for n, k in facts.kind.items() if k == "robot")
    assert (robot, "wp-entrance") in facts.path and (robot, "wp-box") in facts.path
    assert name in facts.grasp and (robot, facts.grasp[name]) in facts.path


def _case1_belief():
    scenario = load(ROOT / "problems" / "case1.toml")
    return scenario, Belief(scenario, RoomMap(scenario))


def test_the_problem_is_the_model_in_what_the_domain_declares():
    """Built for a domain, the problem has its name and only the predicates and functions it
    declares; the text saved beside the trace reads back to the same problem."""
    from tidyplan.loop.scenarios import DOMAIN

    tidy = DOMAIN.read_text()
    lean = tidy.replace("    (p-item-near ?w - waypoint) - number)", ")").replace(
        ":probability (p-item-near ?w)", ":probability 0.5"
    )
    lean = lean.replace("(define (domain tidy)", "(define (domain lean)")
    domain = parse(lean, "lean.pddl")
    scenario, belief = _case1_belief()
    snap = write(belief, belief.facts(), [], [("unseen-tool-1", "tool")], "t", domain=domain)
    assert snap.problem.domain_name == "lean"
    assert {t.name for t, _ in snap.problem.values} == {"total-cost", "travel-time"}
    assert all(domain.predicate(a.predicate) for a in snap.problem.init)
    assert parse(snap.text, "t.pddl").init == snap.problem.init


def test_a_predicate_of_the_domains_own_comes_from_the_scenarios_facts_or_is_false():
    from tidyplan.loop.scenarios import DOMAIN

    own = DOMAIN.read_text().replace(
        "    (shortest-paths))", "    (shortest-paths)\n    (fragile ?d - deposit))"
    )
    domain = parse(own, "own.pddl")
    _, belief = _case1_belief()
    assert not {
        a for a in write(belief, belief.facts(), [], [], "t", domain=domain).atoms if a[0] == "fragile"
    }
    belief.memory |= {("fragile", "tray"), ("fragile", "no-such-deposit")}
    atoms = write(belief, belief.facts(), [], [], "t", domain=domain).atoms
    assert {a for a in atoms if a[0] == "fragile"} == {("fragile", "tray")}  # objects of the problem only


def test_a_scenario_fact_the_domain_cannot_hold_is_refused_before_the_world_starts(tmp_path):
    import pytest

    import tidyplan

    text = (ROOT / "problems" / "case1.toml").read_text()
    for fact, why in [
        ("(fragile tray)", "the domain declares no predicate fragile"),
        ("(closed tray)", "closed is written from the belief, not given"),
        ("(shortest-paths tray)", "shortest-paths takes 0 arguments, given 1"),
    ]:
        path = tmp_path / "facts.toml"
        path.write_text(f'facts = ["{fact}"]\n' + text)
        with pytest.raises(tidyplan.InputError) as err:
            tidyplan.run(path, world="symbolic")
        assert f"{path}: facts[0] {fact}: {why}" in str(err.value)


def test_the_shipped_domains_costs_are_the_robots_seconds():
    """Planned in seconds, the cheapest plan is the fastest (issue 31): each move costs the path's
    length at the robot's speed plus the stop, and R is in seconds too; a domain whose moves cost
    metres gets metres and the default R."""
    from tidyplan.belief.problem import STOP_S
    from tidyplan.loop.scenarios import DOMAIN

    scenario, belief = _case1_belief()
    speed = scenario.robot.speed
    facts = belief.facts()
    snap = write(belief, facts, [], [], "t", domain=parse(DOMAIN.read_text(), "tidy.pddl"))
    times = {t.args: x for t, x in snap.problem.values if t.name == "travel-time"}
    assert {t.name for t, _ in snap.problem.values} == {"total-cost", "travel-time"}
    assert set(times) == set(facts.path) | set(facts.blocked) | set(facts.adjust)
    for pair, d in facts.path.items():
        assert times[pair] == round(d / speed + STOP_S, 2)
    assert snap.problem.goal_reward == round(1000 / speed, 2)
    assert "(:goal-reward 4545.45)" in snap.text and "(= (travel-time " in snap.text

    metres = DOMAIN.read_text().replace("(travel-time ?from ?to", "(distance ?from ?to")
    snap = write(belief, facts, [], [], "t", domain=parse(metres, "metres.pddl"))
    lengths = {t.args: x for t, x in snap.problem.values if t.name == "distance"}
    assert {t.name for t, _ in snap.problem.values} == {"total-cost", "distance"}
    assert all(lengths[pair] == round(d, 2) for pair, d in facts.path.items())
    assert snap.problem.goal_reward is None and ":goal-reward" not in snap.text


@settings(max_examples=300, derandomize=True)
@given(
    st.floats(0.0, 30.0),
    st.floats(0.0, 30.0),
    st.floats(0.0, 30.0),
    st.floats(0.05, 2.0),
)
def test_travel_times_keep_the_triangle_inequality(ab, bc, slack, speed):
    """A path no longer than a detour is no slower than it, rounding included, so the planner's
    move reduction (a stop at an idle waypoint never pays, docs/planner.md) still holds."""
    from tidyplan.belief.problem import travel_time

    ac = max(0.0, ab + bc - slack)
    assert travel_time(ac, speed) <= travel_time(ab, speed) + travel_time(bc, speed)


def test_the_generated_tasks_cost_what_the_shipped_domain_does():
    """tidyplan.generate.tasks imports nothing of tidyplan's planning, so its Held-Karp optimum
    states tidy.pddl's costs itself: they must be the domain's."""
    from tidyplan.belief.problem import STOP_S, travel_time
    from tidyplan.generate import tasks
    from tidyplan.loop.scenarios import DOMAIN
    from tidyplan.pddl import model as m

    def cost(effect):  # the amount of an action's (increase (total-cost) ...)
        if isinstance(effect, m.Increase):
            return effect.amount
        parts = effect.parts if isinstance(effect, m.AndEffect) else ()
        return next((c for c in map(cost, parts) if c is not None), None)

    costs = {a.name: cost(a.effect) for a in parse(DOMAIN.read_text(), "tidy.pddl").actions}
    assert costs["take_object"] == tasks.TAKE_S and costs["deliver_it"] == tasks.DELIVER_S
    assert costs["move"] == m.FunctionTerm("travel-time", ("?from", "?to"))
    assert tasks.STOP_S == STOP_S
    assert all(tasks.travel_time(d) == travel_time(d, tasks.SPEED) for d in (0.0, 0.37, 2.5, 11.04))
