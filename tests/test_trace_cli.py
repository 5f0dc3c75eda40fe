"""`tidyplan trace`: the story of a run read back from its trace, held to the run's own summary.

Two seeded missions in the symbolic world (case I with faults under O-FSM, and case I under
greedy) are run once for the module; every test reads their traces, or copies of them damaged
on purpose (cut off mid-line, rewritten as a newer schema, their PDDL folder gone).
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from collections import Counter
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from tidyplan.cli.main import main
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.loop.scenarios import project_file
from tidyplan.trace.plot import CLASS_COLOURS, PLAN_COLOURS
from tidyplan.trace.read import adopted, read_trace, summarise
from tidyplan.worlds.rates import Rates

CONTRACT = (
    "replans replan_causes actions strata recoveries distance_m sim_time_s wall_time_s success "
    "objects delivered lost_objects"
).split()
COUNTS = (
    "replans replan_causes actions strata recoveries replans_avoided delivered objects success wrs_score"
).split()


def _mission(folder: Path, name: str, **settings) -> tuple[Path, dict]:
    trace = folder / f"{name}.jsonl"
    summary = run(
        project_file("problems/case1.toml"),
        trace,
        Settings(**{"world": "symbolic", "planner": "lama-first", "time_budget": 0.5, **settings}),
    )
    return trace, summary


@pytest.fixture(scope="module")
def faulty(tmp_path_factory) -> tuple[Path, dict]:
    """Case I, O-FSM, seed 1, items dropped while carried and missed by the camera."""
    folder = tmp_path_factory.mktemp("ofsm")
    return _mission(folder, "ofsm", seed=1, rates=Rates.parse("grasp_drop=0.2,perception_miss=0.2"))


@pytest.fixture(scope="module")
def greedy(tmp_path_factory) -> tuple[Path, dict]:
    return _mission(tmp_path_factory.mktemp("greedy"), "greedy", strategy="greedy", seed=0)


def _trace(capsys, *args) -> tuple[int, str, str]:
    status = main(["trace", *map(str, args)])
    out = capsys.readouterr()
    return status, out.out, out.err


def _events(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()]


# ------------------------------------------------------------------ the story
@pytest.mark.slow
def test_json_summary_has_the_runs_own_counts(faulty, capsys):
    trace, summary = faulty
    assert summary["recoveries"] > 0 and summary["replans"] > 0  # a run with faults and replans
    status, out, err = _trace(capsys, trace, "--json")
    assert status == 0 and err == ""
    s = json.loads(out)
    for key in CONTRACT:
        assert s[key] == summary[key], key
    assert s["strata"].keys() == {"P1", "P2", "P3"}
    assert s["complete"] and s["ended"] == summary["reason"]
    assert len(s["plans"]) == len([e for e in _events(trace) if e["kind"] == "plan"])


@pytest.mark.slow
@pytest.mark.parametrize("run_name", ["faulty", "greedy"])
def test_a_trace_without_summary_is_summarised_from_its_events_alike(run_name, request):
    """The figures the reader computes from the events are the ones the run itself counted."""
    trace_path, summary = request.getfixturevalue(run_name)
    trace = read_trace(trace_path)
    killed = replace(trace, events=trace.events[:-1])
    assert trace.events[-1]["kind"] == "summary"
    s = summarise(killed)
    for key in COUNTS:
        assert s[key] == summary[key], key
    assert s["distance_m"] == pytest.approx(summary["distance_m"], abs=0.005 * summary["actions"] + 0.01)
    # the events' clock is rounded to 0.01 s and the summary's to 0.1 s: rounded again, one tenth apart
    assert s["sim_time_s"] == pytest.approx(summary["sim_time_s"], abs=0.1 + 1e-9)
    assert not s["complete"] and s["ended"].startswith("without a summary")


@pytest.mark.slow
def test_story_says_how_many_replans_and_why(faulty, capsys):
    trace, summary = faulty
    status, out, _ = _trace(capsys, trace)
    assert status == 0
    assert f"replans: {summary['replans']} (" in out
    for cause, n in summary["replan_causes"].items():
        assert f"{cause} (" in out and f") {n}" in out
    assert f"ended: {summary['reason']}: success, {summary['delivered']}/{summary['objects']} tidied" in out
    assert f"actions: {summary['actions']} executed" in out
    assert f"recoveries: {summary['recoveries']} steps" in out
    assert f"distance {summary['distance_m']:.2f} m" in out
    from tidyplan.trace.read import read_trace
    from tidyplan.trace.score import wrs_score

    at_end = wrs_score(read_trace(trace).events, math.inf)
    assert f"WRS score {summary['wrs_score']:g} within 900 s simulated ({at_end:g} at the end" in out


@pytest.mark.slow
def test_trace_carries_what_the_plot_needs(faulty):
    trace, summary = faulty
    events = _events(trace)
    start, end = events[0], events[-2]
    assert Path(start["scenario_file"]) == project_file("problems/case1.toml").resolve()
    assert len(start["robot"]) == 2
    assert len(end["items"]) == summary["objects"]
    assert sum(state.startswith("tidied:") for state, _, _ in end["items"].values()) == summary["delivered"]
    moves = [e for e in events if e["kind"] == "action" and e["metres"] > 0]
    assert moves and all(e["path"] and e["path"][-1] == e["robot"] for e in moves if e["ok"])


# ------------------------------------------------------------------ the plot
def _pixels(image: np.ndarray, colour: str, tolerance: float = 0.03) -> int:
    rgb = np.array([int(colour[i : i + 2], 16) / 255 for i in (1, 3, 5)])
    return int((np.abs(image[..., :3] - rgb).max(axis=-1) < tolerance).sum())


@pytest.mark.slow
def test_plot_draws_the_path_by_plan_and_the_recoveries(faulty, tmp_path, capsys):
    trace, summary = faulty
    png = tmp_path / "run.png"
    status, _, err = _trace(capsys, trace, "--plot", png)
    assert status == 0 and f"wrote {png}" in err
    assert png.stat().st_size > 50_000
    image = imread(png)
    height = image.shape[0]
    room, timeline = image[: int(height * 0.6)], image[int(height * 0.65) :]
    plans = len(adopted(read_trace(trace)))
    used = PLAN_COLOURS[: min(plans, len(PLAN_COLOURS))]
    counts = [_pixels(room, c) for c in used]
    assert sum(counts) > 3000, counts  # metres of path, not a legend swatch
    assert sum(n > 100 for n in counts) >= min(plans, 3), counts
    classes = summarise(read_trace(trace))["recovery_steps"]["by_class"]
    for k in classes:
        assert _pixels(timeline, CLASS_COLOURS[k]) > 20, k


# ------------------------------------------------------------------ damaged traces
@pytest.mark.slow
def test_a_trace_cut_off_mid_line_is_read_to_its_last_whole_event(faulty, tmp_path, capsys):
    trace, _ = faulty
    lines = trace.read_text().splitlines(keepends=True)
    cut = tmp_path / "killed.jsonl"
    cut.write_text("".join(lines[:120]) + lines[120][: len(lines[120]) // 2])
    status, out, err = _trace(capsys, cut, "--json")
    assert status == 0
    assert err.splitlines() == [
        f"{cut}: warning: cut off mid-line (a killed run?): read up to its last whole event, "
        f"seq 119 ({json.loads(lines[119])['kind']})"
    ]
    s = json.loads(out)
    whole = [json.loads(line) for line in lines[:120]]
    assert s["actions"] == sum(e["kind"] == "action" for e in whole)
    assert not s["complete"] and s["ended"].startswith("without a summary") and not s["success"]


@pytest.mark.slow
def test_a_newer_schema_with_an_unknown_kind_is_read_with_one_warning(faulty, tmp_path, capsys):
    trace, summary = faulty
    events = _events(trace)
    for e in events:
        e["v"] = 2
        e["battery"] = 0.5  # a field this reader does not know
    events.insert(3, {"v": 2, "seq": 3, "kind": "battery_low", "wall_s": 0.0, "sim_s": 2.0, "level": 0.1})
    newer = tmp_path / "newer.jsonl"
    newer.write_text("".join(json.dumps(e) + "\n" for e in events))
    status, out, err = _trace(capsys, newer, "--json")
    assert status == 0
    assert err.splitlines() == [
        f"{newer}: warning: written with trace schema v2, this tidyplan reads v1: "
        "read as v1, 1 event of unknown kinds skipped"
    ]
    s = json.loads(out)
    assert s["schema"] == 2
    for key in COUNTS:
        assert s[key] == summary[key], key


@pytest.mark.parametrize(
    "name, content, why",
    [
        ("missing.jsonl", None, "no such file"),
        ("empty.jsonl", b"", "not a tidyplan trace: the file is empty"),
        ("binary.jsonl", b"\x89PNG\r\n\x1a\n\x00\x00", "not a tidyplan trace: it is a binary file"),
        ("notes.txt", b"a plan\nand more\n", "not a tidyplan trace: line 1 is not JSON (Expecting value)"),
        ("list.jsonl", b"[1, 2]\n", 'not a tidyplan trace: line 1 is not a trace event (no "kind")'),
        (
            "headless.jsonl",
            b'{"v": 1, "seq": 0, "kind": "plan"}\n',
            "not a tidyplan trace: it has no start event (the first is 'plan')",
        ),
        (
            "garbled.jsonl",
            b'{"v": 1, "seq": 0, "kind": "start", "wall_s": 0, "sim_s": 0}\n'
            b'{"v": 1, "seq": 1, "kind": "plan", "wall_s": 0, "sim_s": 0, "replan": "one"}\n',
            'not a tidyplan trace: line 2: a plan event whose "replan" is missing or not a whole number',
        ),
    ],
)
def test_a_file_that_is_not_a_trace_is_one_line_and_exit_2(name, content, why, tmp_path, capsys):
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    status, out, err = _trace(capsys, path)
    assert status == 2 and out == ""
    assert err == f"{path}: {why}\n"


def test_a_directory_is_not_a_trace_and_the_process_shows_no_traceback(tmp_path, tidyplan_cmd):
    done = subprocess.run(
        [*tidyplan_cmd, "trace", str(tmp_path)], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 2
    assert done.stderr == f"{tmp_path}: not a tidyplan trace: it is a directory\n"


# ------------------------------------------------------------------ one replan
def _contradicted(trace: Path) -> dict:
    plans = [e for e in _events(trace) if e["kind"] == "plan" and e["cause"] == "assumption_contradicted"]
    assert plans, "the seeded run no longer contradicts an assumption: choose another seed"
    return plans[0]


@pytest.mark.slow
def test_replan_diff_after_a_contradicted_assumption(faulty, capsys):
    trace, _ = faulty
    plan = _contradicted(trace)
    status, out, err = _trace(capsys, trace, "--replan", plan["replan"], "--json")
    assert status == 0 and err == ""
    d = json.loads(out)
    assert d["cause"] == "assumption_contradicted" and d["plan"] == plan["plan"]
    # the diff is a partition of the old rest and of the new plan, in their orders
    assert [s for m, s in d["diff"] if m in " -"] == d["rest"]
    assert [s for m, s in d["diff"] if m in " +"] == d["plan"]
    assert Counter(d["kept"]) + Counter(d["dropped"]) == Counter(d["rest"])
    assert Counter(d["kept"]) + Counter(d["added"]) == Counter(d["plan"])
    assert d["kept"] and d["dropped"] and d["added"]
    # what the assumption said is dropped; where the look found the item is added
    assumption, _, finding = plan["why"].partition(": ")
    _, item, waypoint = assumption.strip("()").split()
    assert f"(take_object {item} {waypoint})" in d["dropped"]
    assert not any(f"(take_object {item} {waypoint})" == s for s in d["kept"] + d["added"])
    if " is at " in finding:
        found_at = finding.split(" is at ")[1]
        assert f"(take_object {item} {found_at})" in d["added"]
        assert f"(item-at {item} {found_at})" in d["facts"]["added"]
    assert d["previous"]["replan"] < plan["replan"]
    assert d["executed"]  # the action whose look contradicted it


@pytest.mark.slow
def test_replan_diff_in_text_and_without_the_pddl_folder(faulty, tmp_path, capsys):
    trace, _ = faulty
    plan = _contradicted(trace)
    status, out, _ = _trace(capsys, trace, "--replan", plan["replan"])
    assert status == 0
    assert f"replan {plan['replan']} of {trace}" in out and "assumption_contradicted (iii)" in out
    assert "kept," in out and "dropped," in out and "belief (" in out
    alone = tmp_path / "alone.jsonl"
    shutil.copy(trace, alone)  # the trace without its PDDL folder
    status, out, _ = _trace(capsys, alone, "--replan", plan["replan"])
    assert status == 0
    gone = [line for line in out.splitlines() if "belief facts not compared" in line]
    folder = tmp_path / trace.with_suffix(".pddl").name  # the events name the original's folder
    assert gone == [f"{folder}: gone (the trace's PDDL folder): belief facts not compared"]
    assert "kept," in out and "  - " in out


@pytest.mark.slow
def test_a_replan_the_trace_does_not_have_is_bad_input(faulty, capsys):
    trace, summary = faulty
    status, out, err = _trace(capsys, trace, "--replan", 999)
    assert status == 2 and out == ""
    assert err == f"{trace}: --replan 999: no such replan (it has 0..{summary['replans']})\n"


# ------------------------------------------------------------------ runs side by side
@pytest.mark.slow
def test_two_runs_side_by_side(faulty, greedy, capsys):
    (a, sa), (b, sb) = faulty, greedy
    status, out, _ = _trace(capsys, a, b, "--json")
    assert status == 0
    runs = json.loads(out)["runs"]
    assert [r["strategy"] for r in runs] == ["ofsm", "greedy"]
    for r, s in zip(runs, (sa, sb), strict=True):
        for key in CONTRACT:
            assert r[key] == s[key], key
    status, out, _ = _trace(capsys, a, b)
    assert status == 0
    rows = {line.split("│")[0].strip(): line for line in out.splitlines() if "│" in line}
    assert rows["tidied"].split("│")[1:] and f"{sa['delivered']}/{sa['objects']}" in rows["tidied"]
    assert f"{sb['delivered']}/{sb['objects']}" in rows["tidied"]
    assert str(sa["replans"]) in rows["replans"] and str(sb["replans"]) in rows["replans"]
    assert "ofsm" in rows["strategy"] and "greedy" in rows["strategy"]
    assert f"{sa['wrs_score']:g} (" in rows["WRS score (at the end)"]
    status, _, err = _trace(capsys, a, b, "--plot", "x.png")
    assert status == 2 and "give one trace" in err
