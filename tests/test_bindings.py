"""Bindings declared in the domain (`:units`) and checked before anything runs: `tidyplan check`
names an unbound action, an unknown unit or a wrong argument at its place; `tidyplan run --domain`
refuses a domain it cannot run before a world is made; the executor binds arguments by name."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import pytest

from sim.scenario.read import load
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.problem import write
from tidyplan.belief.state import Belief
from tidyplan.cli.main import main
from tidyplan.exec import catalogue
from tidyplan.exec.binding_check import check_bindings
from tidyplan.exec.bindings import BUILD, MonitoredExecutor
from tidyplan.exec.units import AdjustBase, Context, Grasp
from tidyplan.loop.scenarios import DOMAIN, project_file
from tidyplan.pddl.reader import parse
from tidyplan.planning.planner import Step

TIDY = DOMAIN.read_text()


def _edit(old: str, new: str, text: str = TIDY) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def _place(text: str, needle: str) -> tuple[int, int]:
    """Line and column (1-based) of ``needle``'s first occurrence."""
    at = text.index(needle)
    return text.count("\n", 0, at) + 1, at - text.rfind("\n", 0, at)


def _check(capsys, path: Path) -> tuple[int, str, str]:
    status = main(["check", str(path)])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_every_catalogue_unit_has_a_constructor_and_the_shipped_domain_is_bound():
    assert set(BUILD) == set(catalogue.UNITS)
    domain = parse(TIDY, "tidy.pddl")
    assert check_bindings(domain, for_run=True) == []
    assert all(a.units for a in domain.actions if not a.is_assumption)


def test_check_lists_the_units_the_worlds_offer(capsys):
    status, out, _ = _check(capsys, DOMAIN)
    assert status == 0
    executable = sum(not a.is_assumption for a in parse(TIDY, "tidy.pddl").actions)
    assert f"{executable} actions bound to behaviour units" in out
    for name, spec in catalogue.UNITS.items():
        line = next(x for x in out.splitlines() if x.strip().startswith(f"({name}"))
        assert spec.signature in line
        assert "symbolic" in line and "pybullet" in line, line


@pytest.mark.parametrize(
    "old, new, needle, message",
    [
        (  # an action with no :units
            "    :units ((put_down ?o))\n",
            "",
            "drop_object",
            "action 'drop_object' has no :units: nothing can execute it",
        ),
        (
            "(adjust_base ?o) (grasp ?o)",
            "(adjust_base ?o) (grab ?o)",
            "grab",
            "unknown unit 'grab' in 'take_object'",
        ),
        (
            "(adjust_base ?o) (grasp ?o)",
            "(adjust_base ?o) (grasp ?w)",
            "grasp ?w",
            "unit 'grasp' takes a item as item; '?w' is a waypoint",
        ),
        (
            "(adjust_base ?o) (grasp ?o)",
            "(adjust_base ?o) (grasp ?o ?w)",
            "grasp ?o ?w",
            "unit (grasp item:item) takes 1 argument, given 2",
        ),
        (
            "(adjust_base ?o) (grasp ?o)",
            "(adjust_base ?o) (grasp ?x)",
            "grasp ?x",
            "'?x' in (grasp ...) is not a parameter of 'take_object'",
        ),
    ],
)
def test_check_reports_a_bad_binding_where_it_is(write, capsys, old, new, needle, message):
    text = _edit(old, new)
    path = write("mine.pddl", text)
    status, _, err = _check(capsys, path)
    assert status == 2
    line, col = _place(text, needle if needle != "drop_object" else "drop_object")
    if needle == "drop_object":
        line, col = _place(text, "(:action drop_object")
        col += len("(:action ")
    assert f"{path}:{line}:{col}: {message}" in err, err
    assert "Traceback" not in err


def test_a_word_of_the_problems_declared_otherwise_is_refused(write, capsys):
    text = _edit("(holding ?o - item)", "(holding ?o - waypoint)")
    status, _, err = _check(capsys, write("mine.pddl", text))
    assert status == 2
    line, col = _place(text, "holding ?o - waypoint")
    assert f":{line}:{col}: 'holding' is written from the belief with (item); declared with (waypoint)" in err


def test_run_refuses_a_domain_it_cannot_run_before_the_world_starts(write, tmp_path, capsys, monkeypatch):
    import tidyplan.loop.mission as mission

    made = []
    monkeypatch.setattr(mission, "make_world", lambda *a, **k: made.append(a))
    path = write("mine.pddl", _edit("(adjust_base ?o) (grasp ?o)", "(adjust_base ?o) (grab ?o)"))
    trace = tmp_path / "t.jsonl"
    status = main(
        [
            "run",
            "--world",
            "symbolic",
            "--planner",
            "lama-first",
            "--domain",
            str(path),
            "--trace",
            str(trace),
            "--quiet",
        ]
    )
    err = capsys.readouterr().err
    assert status == 2 and "unknown unit 'grab'" in err and "Traceback" not in err
    assert made == [] and not trace.exists()


def test_run_refuses_a_planning_domain_without_units(tmp_path, capsys, corpus_pairs):
    pair = corpus_pairs[0]
    status = main(
        [
            "run",
            "--world",
            "symbolic",
            "--planner",
            "lama-first",
            "--domain",
            str(pair.domain),
            "--trace",
            str(tmp_path / "t"),
        ]
    )
    err = capsys.readouterr().err
    assert status == 2
    assert re.search(r"action '[\w-]+' has no :units: nothing can execute it", err), err


def test_the_executor_binds_arguments_by_parameter_name():
    """The same action with its parameters declared in the other order runs the same units on
    the same item: arguments are bound by name, not by position."""
    swapped = _edit(
        ":parameters (?o - item ?w - waypoint)\n    :stratum 1\n    :probability 0.95",
        ":parameters (?w - waypoint ?o - item)\n    :stratum 1\n    :probability 0.95",
    )
    case3 = load(project_file("problems/case3.toml"))
    belief = Belief(case3, RoomMap(case3))
    snap = write(belief, belief.facts(), [], [], "t")
    ctx = Context(None, belief, lambda d, w, why="": [])
    executor = MonitoredExecutor(None, domain=parse(swapped, "swapped.pddl"))
    units = executor.units(Step("take_object", ("wp-entrance", "cup"), False, 1, 0.95, 1.0), snap, ctx)
    assert [type(u) for u in units] == [AdjustBase, Grasp]
    assert [u.item for u in units] == ["cup", "cup"]


def test_a_step_goes_to_a_waypoint_where_the_belief_has_it_now():
    """A waypoint the belief has moved since the plan (a grasp pose chosen anew, the plan's no
    longer usable) is where the monitor checked the plan against: the navigate unit drives
    there, not to the point the plan's snapshot holds."""
    case3 = load(project_file("problems/case3.toml"))
    belief = Belief(case3, RoomMap(case3))
    facts = belief.facts()
    now = belief.poses().points
    to = next(n for n in sorted(now) if n.startswith("vp-"))
    then = {to: (now[to][0] + 0.4, now[to][1]), "wp-entrance": (now["wp-entrance"][0] + 0.2, 0.0)}
    snap = write(belief, replace(facts, points={**facts.points, **then}), [], [], "t")
    assert all(snap.facts.points[n] == q for n, q in then.items())
    ctx = Context(None, belief, lambda d, w, why="": [])
    executor = MonitoredExecutor(None, domain=parse(TIDY, "tidy.pddl"))
    (navigate,) = executor.units(Step("move", ("wp-entrance", to), False, 1, 1.0, 1.0), snap, ctx)
    assert navigate.goal == now[to] != then[to]
    # where the step starts (a way found blocked is blocked from there) is the belief's too
    assert ctx.start == now["wp-entrance"] == belief.robot != then["wp-entrance"]
