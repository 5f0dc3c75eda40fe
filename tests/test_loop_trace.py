"""The loop's trace: the files each plan event names, and the same trace for the same seed."""

from __future__ import annotations

from tests.test_loop import _events, _plans, _run, _scenario
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.worlds.rates import Rates


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
        run(
            scenario,
            trace,
            Settings(world="symbolic", seed=7, rates=rates, planner="lama-first", time_budget=5.0),
        )
        runs.append([_stable(e) for e in _events(trace)])
    assert runs[0] == runs[1]


def _stable(e: dict) -> dict:
    drop = {
        "wall_s",
        "planning_time_s",
        "phases",  # seconds
        "wall_time_s",
        "replan_time_s",
        "trace",
        "problem",
        "domain",
        "plain_domain",
        "plain_problem",
    }
    out = {k: v for k, v in e.items() if k not in drop}
    if "attempts" in out:  # [stratum, outcome, wall seconds]
        out["attempts"] = [a[:2] for a in out["attempts"]]
    return out
