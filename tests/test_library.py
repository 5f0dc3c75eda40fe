"""The library (tidyplan.library): ``tidyplan.run`` does what ``tidyplan run`` does and returns a
typed summary; a trace only when asked for; the shipped domains and scenarios found from the
package."""

from __future__ import annotations

import json
import os
from dataclasses import fields

import pytest

import tidyplan
from tidyplan.loop.scenarios import project_file


def test_the_shipped_domain_and_scenarios_are_found_from_the_package():
    for name in ("domains/tidy.pddl", "problems/case1.toml", "problems/case2.toml", "problems/case3.toml"):
        assert project_file(name).is_file(), name


@pytest.mark.parametrize(
    "options, message",
    [
        ({"world": "mars"}, "world: 'mars' is not one of pybullet, symbolic"),
        ({"strategy": "random"}, "strategy: 'random' is not one of"),
        ({"gui": True, "world": "symbolic"}, "gui: only the pybullet world has a window"),
        ({"max_recovery": -1}, "max_recovery: -1 is negative"),
        ({"first_plan_limit": 0}, "first_plan_limit: 0 is not a positive number of seconds"),
        ({"time_budget": float("nan")}, "time_budget: nan is not a positive number of seconds"),
        ({"patience": -1.0}, "patience: -1.0 is not a number of seconds >= 0"),
        ({"faults": "grasp_drop=2"}, "faults: grasp_drop=2: the rate must be in [0, 1]"),
        ({"planner": "no-such-planner"}, "no-such-planner"),
    ],
)
def test_bad_options_raise_input_error_before_anything_runs(options, message):
    with pytest.raises(tidyplan.InputError) as err:
        tidyplan.run("case1", **options)
    assert message in str(err.value)
    assert "--" not in str(err.value), "a Python caller is told the keyword, not the command-line option"


def test_a_scenario_that_is_neither_shipped_nor_a_file_is_input_error(tmp_path):
    with pytest.raises(tidyplan.InputError, match="no such file"):
        tidyplan.run(str(tmp_path / "nowhere.toml"), world="symbolic")
    with pytest.raises(tidyplan.InputError, match="no such file"):
        tidyplan.run("case9", world="symbolic")


def test_a_bad_domain_is_refused_with_its_place(tmp_path):
    bad = tmp_path / "bad.pddl"
    bad.write_text("(define (domain d)\n  (:action a :parameters (?x) :effect (p ?x)))\n")
    with pytest.raises(tidyplan.InputError) as err:
        tidyplan.run("case1", world="symbolic", domain=bad)
    assert f"{bad}:2:" in str(err.value)


def test_an_existing_trace_is_never_overwritten(tmp_path):
    trace = tmp_path / "mine.jsonl"
    trace.write_text("someone's run\n")
    with pytest.raises(tidyplan.InputError, match="exists"):
        tidyplan.run("case1", world="symbolic", trace=trace)
    assert trace.read_text() == "someone's run\n"


@pytest.mark.slow
def test_run_returns_the_json_summary_typed_and_writes_no_trace_unless_asked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    events = []
    s = tidyplan.run("case1", world="symbolic", seed=0, planner="lama-first", on_event=events.append)
    assert isinstance(s, tidyplan.Summary)
    assert s.success and s.delivered == s.objects == 12 and s.lost_objects == 0
    assert s.trace is None
    assert os.listdir(tmp_path) == []  # nothing written: no trace, no runs/ folder
    assert events[-1]["kind"] == "summary"
    # the summary's fields are the --json fields, exactly
    assert {f.name for f in fields(tidyplan.Summary)} == set(events[-1]) - {
        "v",
        "seq",
        "kind",
        "wall_s",
        "sim_s",
    }
    assert s.as_dict() == {k: events[-1][k] for k in s.as_dict()}

    # asked for, the trace is written and ends with the same summary
    traced = tidyplan.run("case1", world="symbolic", seed=0, planner="lama-first", trace=tmp_path / "t.jsonl")
    last = json.loads((tmp_path / "t.jsonl").read_text().splitlines()[-1])
    assert traced.trace == str(tmp_path / "t.jsonl") and last["kind"] == "summary"
    assert traced.as_dict() == {k: last[k] for k in traced.as_dict()}
    assert (tmp_path / "t.pddl").is_dir()
