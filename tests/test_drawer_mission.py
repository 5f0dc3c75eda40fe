"""The WRS drawer end to end through the declared path: problems/wrs-drawer.toml (case I's room,
the tools' deposit a drawer closed at the start) planned with tidy.pddl's open_drawer (stratum 1)
and run by its units, approach_handle and pull_handle, with their failure classes: a slipped
handle (B) pulled again, a jammed drawer (C) pushed closed first."""

from __future__ import annotations

import json

import pytest

from tidyplan.cli.main import main
from tidyplan.loop.scenarios import project_file

pytestmark = pytest.mark.slow


def _run(tmp_path, capsys, *extra: str) -> tuple[dict, list[dict]]:
    trace = tmp_path / "drawer.jsonl"
    scenario = str(project_file("problems/wrs-drawer.toml"))
    args = ["run", scenario, "--world", "symbolic", "--planner", "lama-first", "--trace", str(trace)]
    status = main([*args, "--json", "--quiet", *extra])
    out = capsys.readouterr()
    assert status in (0, 1), out.err
    return json.loads(out.out.strip().splitlines()[-1]), [json.loads(line) for line in trace.open()]


def test_the_drawer_is_opened_before_the_first_tool_goes_in(tmp_path, capsys):
    summary, events = _run(tmp_path, capsys, "--seed", "0")
    assert summary["success"] and summary["delivered"] == 12
    actions = [e for e in events if e["kind"] == "action" and e["ok"]]
    opened = next(i for i, e in enumerate(actions) if e["action"].startswith("(open_drawer drawer"))
    into_drawer = [
        i
        for i, e in enumerate(actions)
        if e["action"].startswith("(deliver_it") and " drawer " in e["action"]
    ]
    assert len(into_drawer) == 3 and opened < min(into_drawer)
    assert actions[opened]["units"] == ["approach_handle", "pull_handle"] and actions[opened]["stratum"] == 1
    assert summary["strata"]["P3"] == 0  # opening a drawer escalates nothing


def test_a_slipped_handle_is_pulled_again_and_a_jammed_drawer_pushed_closed_first(tmp_path, capsys):
    summary, events = _run(tmp_path, capsys, "--seed", "2", "--faults", "handle_slip=0.5,drawer_jam=0.5")
    assert summary["success"] and summary["delivered"] == 12
    pulls = [e for e in events if e["kind"] == "recovery" and e["unit"] == "pull_handle"]
    slipped = [e for e in pulls if e["failure"] == "handle_slip" and e["layer"] == "same_unit"]
    jammed = [e for e in pulls if e["failure"] == "drawer_jammed" and e["layer"] == "insert_unit"]
    assert slipped and all(e["failure_class"] == "B" for e in slipped)
    assert jammed and all(e["failure_class"] == "C" and e["then"] == ["push_drawer"] for e in jammed)
