"""The continual loop's rules (Goebelbecker et al.; Brenner & Nebel), one test each, in small
symbolic rooms with real planning (Fast Downward through unified-planning).

Each room is a scenario file written here; the world is made exact where a test needs it
(no false detections, no failed grasps), so each run shows the one rule under test.
"""

from __future__ import annotations

import json
import subprocess
from dataclasses import replace

import pytest

from sim.scenario_file import loads
from tidyplan.exec.bindings import DirectExecutor, Report
from tidyplan.exec.symbolic import Outcome, Rates, SymbolicWorld
from tidyplan.mission import Settings, run

# A toy in the far corner behind a crate as tall as a table: no look finds it and no grasp
# reaches it until the crate (a toy too) is put away.
HIDDEN = ("hidden", 2.93, 2.93, (0.06, 0.06, 0.08))
CRATE = ("crate", 2.6, 2.6, (0.5, 0.5, 0.8))
EXACT = Rates(take=1.0, deliver=1.0, drop=1.0, false_negative=0.0, false_positive=0.0)

ROOM = """
schema = 1
name = "{name}"
title = "a test room"
[room]
bounds = [0.0, 3.0, 0.0, 3.0]
entrance = [2.6, 0.4]
[[furniture]]
name = "shelf"
center = [0.2, 1.5]
size = [0.3, 1.0]
height = 0.9
kind = "table"
[[deposit]]
name = "box"
category = "toy"
position = [0.2, 1.5, 0.9]
approach = [0.75, 1.5]
"""


def _scenario(name: str, items: list[tuple], extra: str = ""):
    text = ROOM.format(name=name) + extra
    for item, x, y, *size in items:
        text += f'[[item]]\nname = "{item}"\ncategory = "toy"\nposition = [{x}, {y}]\n'
        if size:
            text += f"size = {list(size[0])}\n"
    return loads(text, f"{name}.toml")


def _events(path) -> list[dict]:
    return [json.loads(line) for line in open(path, encoding="utf-8")]


def _run(tmp_path, scenario, rates=EXACT, **kw):
    trace = tmp_path / "trace.jsonl"
    summary = run(scenario, trace, Settings(rates=rates, time_budget=0.5, **kw))
    return summary, _events(trace)


def _plans(events):
    return [e for e in events if e["kind"] == "plan"]


def test_a_plan_that_stays_valid_is_kept_to_the_end(tmp_path):
    # Two toys in plain view, nothing fails: one plan, executed to the goal, no replan.
    scenario = _scenario("plain", [("t1", 1.8, 1.0), ("t2", 1.8, 2.2)])
    summary, events = _run(tmp_path, scenario)
    assert summary["success"] and summary["delivered"] == 2
    assert summary["replans"] == 0
    assert [p["cause"] for p in _plans(events)] == ["initial"]
    assert events[-2]["kind"] == "end" and events[-2]["reason"] == "goal reached"


def test_failed_grasp_leaves_the_rest_of_the_plan_invalid_and_replans(tmp_path):
    # take_object fails (seeded): the carry move can still run, the delivery after it cannot:
    # the rest of the plan no longer reaches the goal (ii).
    scenario = _scenario("grasp", [("t1", 1.8, 1.0)])
    summary, events = _run(tmp_path, scenario, rates=replace(EXACT, take=0.5), seed=2)
    assert summary["success"]
    failed = [e for e in events if e["kind"] == "action" and e["failure"] == "grasp_fail"]
    assert failed, "seed 2 must make a grasp fail"
    assert summary["replan_causes"] == {"plan_invalid": len(failed)}
    assert "(deliver_it t1" not in _plans(events)[1]["why"] and "deliver_it" in _plans(events)[1]["why"]


def test_blocked_move_makes_the_next_precondition_false_and_replans(tmp_path, monkeypatch):
    # The first move finds its way blocked: the robot is not where take_object needs it (i).
    real = SymbolicWorld.move
    calls = {"n": 0}

    def blocked_once(self, to, *, adjust=False):
        calls["n"] += 1
        return Outcome(False, "path_blocked", 2.0) if calls["n"] == 1 else real(self, to, adjust=adjust)

    monkeypatch.setattr(SymbolicWorld, "move", blocked_once)
    summary, events = _run(tmp_path, _scenario("blocked", [("t1", 1.8, 1.0)]))
    assert summary["success"]
    assert summary["replan_causes"] == {"precondition_failed": 1}
    assert _plans(events)[1]["why"].startswith("(take_object toy-1")


def test_unseen_toy_is_assumed_and_the_contradiction_replans(tmp_path):
    # One toy hidden behind a tall crate; two viewpoints. The plan assumes it near a viewpoint
    # (a virtual object); looking from there without seeing it contradicts the assumption.
    scenario = _scenario(
        "unseen",
        [("seen", 1.8, 1.0), HIDDEN, CRATE],
        '[[viewpoint]]\nname = "vp-a"\nposition = [1.2, 0.5]\n'
        '[[viewpoint]]\nname = "vp-b"\nposition = [1.2, 2.5]\n',
    )
    summary, events = _run(tmp_path, scenario)
    first = _plans(events)[0]
    assert any(s.startswith("(assume-item-near unseen-toy-") for s in first["plan"])
    assert first["assumptions"] >= 1
    checks = [e for e in events if e["kind"] == "assumption"]
    assert any(not c["holds"] for c in checks)
    assert summary["replan_causes"].get("assumption_contradicted", 0) >= 1


def test_a_new_toy_that_matches_a_virtual_object_is_bound_without_replanning(tmp_path):
    # The third toy is out of the camera's range (2 m here) from the entrance; the plan uses a
    # virtual toy for it, assumed near the one viewpoint; the toy seen on the way is bound to it.
    scenario = _scenario(
        "bind",
        [("a", 2.2, 1.0), ("b", 2.2, 1.5), ("far", 0.8, 2.7)],
        '[sensing]\nrange_max = 2.0\n[[viewpoint]]\nname = "vp-w"\nposition = [1.0, 2.0]\n',
    )
    summary, events = _run(tmp_path, scenario)
    assert summary["success"] and summary["delivered"] == 3
    binds = [e for e in events if e["kind"] == "bind"]
    assert binds and binds[0]["virtual"].startswith("unseen-toy-")
    after = events[events.index(binds[0]) + 1]
    assert after["kind"] != "plan" or after["cause"] != "new_object"  # binding is not trigger (v)


def test_a_new_toy_the_plan_cannot_bind_replans(tmp_path):
    # No viewpoint can reveal the hidden toy, so the goal is narrowed to the toys seen; when the
    # crate is taken away the toy appears, binds to nothing in the plan, and the loop replans (v).
    scenario = _scenario(
        "newobj",
        [CRATE, HIDDEN],
    )
    summary, events = _run(tmp_path, scenario)
    assert summary["success"] and summary["delivered"] == 2
    assert summary["replan_causes"].get("new_object", 0) >= 1
    assert any(p["goal_kind"] != "all" or p["cause"] == "new_object" for p in _plans(events))


def test_recovery_exhausted_replans(tmp_path, monkeypatch):
    # The execution layer (the monitor's error layer, next issue) gives up once: cause (iv).
    real = DirectExecutor.execute
    calls = {"n": 0}

    def flaky(self, step, snapshot, belief):
        report = real(self, step, snapshot, belief)
        calls["n"] += 1
        if calls["n"] == 1:
            return Report(
                report.ok,
                "grasp_fail",
                report.seconds,
                report.metres,
                report.detections,
                True,
                report.waypoint,
            )
        return report

    monkeypatch.setattr(DirectExecutor, "execute", flaky)
    summary, _ = _run(tmp_path, _scenario("recovery", [("t1", 1.8, 1.0)]))
    assert summary["replan_causes"] == {"recovery_exhausted": 1}
    assert summary["success"]


def test_gives_up_when_the_best_plan_is_too_unlikely(tmp_path):
    scenario = _scenario("unlikely", [("t1", 1.8, 1.0)])
    summary, events = _run(tmp_path, scenario, min_probability=0.99)
    assert not summary["success"]
    assert "below 0.99" in summary["reason"]
    assert events[-2]["kind"] == "end"


def test_gives_up_when_no_plan_exists(tmp_path):
    # A toy walled in by furniture: no grasp pose, no plan, and the loop says which toy.
    walls = "".join(
        f'[[furniture]]\nname = "w{k}"\ncenter = [{x}, {y}]\nsize = [{sx}, {sy}]\n'
        'height = 0.3\nkind = "wall"\n'
        for k, (x, y, sx, sy) in enumerate([(2.0, 2.6, 0.1, 0.8), (2.5, 2.15, 1.0, 0.1)])
    )
    scenario = _scenario("walled", [("t1", 2.6, 2.6)], walls)
    summary, events = _run(tmp_path, scenario)
    assert not summary["success"]
    assert summary["reason"].startswith("no plan for")


def test_every_plan_event_names_its_saved_pddl(tmp_path):
    scenario = _scenario("files", [("t1", 1.8, 1.0)])
    _, events = _run(tmp_path, scenario)
    for p in _plans(events):
        for key in ("domain", "problem", "plain_domain", "plain_problem"):
            assert (tmp_path / p[key]).is_file(), key
        assert {"planning_time_s", "stratum", "cost", "probability", "plan", "cause"} <= p.keys()


def test_same_seed_same_trace(tmp_path):
    # lama-first is deterministic; the anytime default may improve a plan sooner or later.
    scenario = _scenario("seeded", [("t1", 1.8, 1.0), ("t2", 1.8, 2.2)])
    rates = Rates(take=0.7, false_negative=0.2, false_positive=0.05)
    runs = []
    for k in range(2):
        trace = tmp_path / f"t{k}.jsonl"
        run(scenario, trace, Settings(seed=7, rates=rates, planner="lama-first", time_budget=5.0))
        runs.append([_stable(e) for e in _events(trace)])
    assert runs[0] == runs[1]


def _stable(e: dict) -> dict:
    drop = {
        "wall_s",
        "planning_time_s",
        "wall_time_s",
        "replan_time_s",
        "trace",
        "problem",
        "domain",
        "plain_domain",
        "plain_problem",
    }
    return {k: v for k, v in e.items() if k not in drop}


@pytest.mark.parametrize("bad", ["grasp_fail=2", "nonsense=0.1", "grasp_fail"])
def test_bad_fault_option_is_exit_2(tidyplan_cmd, bad):
    done = subprocess.run([*tidyplan_cmd, "run", "--faults", bad, "--quiet"], capture_output=True, text=True)
    assert done.returncode == 2
    assert "--faults" in done.stderr and "Traceback" not in done.stderr


def test_unknown_planner_is_exit_2_before_any_trace_is_written(tidyplan_cmd, tmp_path):
    trace = tmp_path / "t.jsonl"
    done = subprocess.run(
        [*tidyplan_cmd, "run", "--planner", "nosuch", "--trace", str(trace), "--quiet"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "planner 'nosuch'" in done.stderr and "Traceback" not in done.stderr
    assert not trace.exists() and not trace.with_suffix(".pddl").exists()
