"""The O-FSM paper's test cases I-III (Yan et al., Fig. 5), as scenario files: they hide and
block what the paper says, O-FSM tidies all 12 objects in each, greedy (P1 alone) fails in II
and III (Table III). The missions are real runs: symbolic world, Fast Downward."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from sim.scenario.read import load
from sim.visibility import visible_items
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import ENTRANCE, Placed, deposit_waypoint
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.worlds.rates import Rates

PROBLEMS = Path(__file__).resolve().parent.parent / "problems"
CASES = ["case1", "case2", "case3"]


def _start(name):
    scenario = load(PROBLEMS / f"{name}.toml")
    room = RoomMap(scenario)
    items = [Placed(i.name, i.category, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items]
    return scenario, room.facts(items)


@pytest.mark.parametrize("name", CASES)
def test_case_has_12_objects_in_4_categories_of_3(name):
    scenario = load(PROBLEMS / f"{name}.toml")
    cats = [i.category for i in scenario.items]
    assert len(cats) == 12 and sorted(set(cats)) == ["food", "kitchen", "task", "tool"]
    assert all(cats.count(c) == 3 for c in set(cats))
    assert {i.on for i in scenario.items} >= {"floor", "long-table"}  # on the floor and a table


@pytest.mark.parametrize("name", CASES)
def test_what_the_case_hides_no_reachable_waypoint_sees(name):
    scenario, facts = _start(name)
    reachable = [n for n in facts.points if n == ENTRANCE or (ENTRANCE, n) in facts.path]
    seen = set().union(*(visible_items(scenario, facts.points[n]) for n in reachable))
    hidden = set(scenario.expect.unobservable_items)
    assert hidden and hidden.isdisjoint(seen) if name != "case2" else not hidden
    for d in scenario.expect.unobservable_deposits:  # the deposit's place is out of sight too
        assert (ENTRANCE, deposit_waypoint(d)) not in facts.path


@pytest.mark.parametrize("name", CASES)
def test_what_the_case_blocks_no_path_reaches(name):
    scenario, facts = _start(name)
    for item in scenario.expect.unreachable_items:
        wp = facts.grasp.get(item)
        assert wp is None or (ENTRANCE, wp) not in facts.path, item
    for d in scenario.expect.unreachable_deposits:
        assert (ENTRANCE, deposit_waypoint(d)) in facts.blocked
    assert bool(scenario.expect.unreachable_deposits) == (name != "case1")


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_ofsm_tidies_all_12_objects(name, tmp_path):
    # lama-first: its first plan, whatever the machine's speed (with LAMA's anytime search and a
    # 0.5 s budget, case II once ended in a fresh clone's full run with "no plan" for nine items)
    settings = Settings("ofsm", seed=1, planner="lama-first", time_budget=30.0, world="symbolic")
    summary = run(PROBLEMS / f"{name}.toml", tmp_path / "t.jsonl", settings)
    assert summary["success"], summary["reason"]
    assert summary["delivered"] == 12 and summary["lost_objects"] == 0
    assert sum(summary["strata"].values()) == 12
    if name != "case1":
        assert summary["strata"]["P3"] >= 1  # the blocked deposit needs an object put aside


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_with_faults_on_nothing_is_lost(name, tmp_path):
    # The fault set: items fall while carried, the camera misses and imagines things.
    # LAMA's first plan, not the anytime default: how far the anytime search improves its plans
    # in its second, and so the run, depends on how loaded the machine is
    # Seeds from 2 on until one drops something in transit (which seed does depends on the
    # plans, and so on the planner): every run loses nothing and tidies all.
    rates = Rates.parse("grasp_drop=0.2,perception_miss=0.2,perception_false=0.05")
    for seed in range(2, 7):
        trace = tmp_path / f"t{seed}.jsonl"
        settings = Settings(
            "ofsm", seed=seed, rates=rates, planner="lama-first", time_budget=30.0, world="symbolic"
        )
        summary = run(PROBLEMS / f"{name}.toml", trace, settings)
        assert summary["lost_objects"] == 0, seed
        assert summary["success"], (seed, summary["reason"])
        events = [json.loads(line) for line in open(trace, encoding="utf-8")]
        drops = [e for e in events if e["kind"] == "unit" and e["failure"] == "grasp_drop"]
        if drops:
            assert summary["recoveries"] >= len(drops)
            break
    assert drops, "no seed of 2-6 dropped anything in transit"


@pytest.mark.slow
@pytest.mark.parametrize("name", ["case2", "case3"])
def test_greedy_fails_where_p1_cannot_go_on(name, tmp_path):
    summary = run(
        PROBLEMS / f"{name}.toml",
        tmp_path / "t.jsonl",
        Settings("greedy", seed=1, planner="lama-first", time_budget=0.5, world="symbolic"),
    )
    assert not summary["success"]
    assert summary["delivered"] < 12
    assert summary["strata"]["P2"] == summary["strata"]["P3"] == 0


@pytest.mark.slow
def test_run_case3_json_from_the_command_line(tidyplan_cmd, tmp_path):
    trace = tmp_path / "case3.jsonl"
    done = subprocess.run(
        [
            *tidyplan_cmd,
            "run",
            str(PROBLEMS / "case3.toml"),
            "--world",
            "symbolic",
            "--json",
            "--trace",
            str(trace),
            "--planner",
            "lama-first",
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    summary = json.loads(done.stdout.strip().splitlines()[-1])
    keys = {
        "scenario",
        "strategy",
        "success",
        "objects",
        "delivered",
        "lost_objects",
        "actions",
        "strata",
        "replans",
        "distance_m",
        "sim_time_s",
        "wall_time_s",
        "replan_time_s",
        "trace",
    }
    assert keys <= summary.keys()
    assert summary["delivered"] == 12 and summary["trace"] == str(trace)
    last = json.loads(trace.read_text().splitlines()[-1])
    assert last["kind"] == "summary" and last["delivered"] == 12


def test_bad_scenario_is_one_message_and_exit_2(tidyplan_cmd, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('schema = 1\nname = "x"\ntitle = "t"\n[room]\nbounds = [0, 1, 0]\nentrance = [0.5, 0.5]\n')
    done = subprocess.run([*tidyplan_cmd, "run", str(bad), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.startswith(f"{bad}: ") and "bounds" in done.stderr
    assert "Traceback" not in done.stderr
