"""`tidyplan trace FILE --html OUT`: the replay page, its data held to the trace, and the page in
a real browser.

The fast tests read a tiny trace written here by hand (a toy driven east, taken, driven north and
delivered), so every figure the page embeds is known exactly. The slow ones run a seeded mission
in the symbolic world (case I with faults: replans, recoveries, a contradicted assumption) and
render its page in headless Chromium (Debian's ``chromium``): the page's own script moves the
slider to the times asked for in the URL, reads back where it drew the robot, opens a replan's
diff and writes what it found into ``<pre id="selftest">``, which the test reads from the dumped
DOM. Chromium runs in a session of its own and the whole session is ended when the call returns.
"""

from __future__ import annotations

import contextlib
import html
import json
import math
import os
import re
import signal
import subprocess
from pathlib import Path

import pytest

from tidyplan.cli.main import main
from tidyplan.loop.mission import run
from tidyplan.loop.options import Settings
from tidyplan.loop.scenarios import project_file
from tidyplan.trace.diff import replan_diff
from tidyplan.trace.html import keyframes, page, page_data, pose_at
from tidyplan.trace.read import adopted, read_trace, summarise
from tidyplan.worlds.rates import Rates

CHROMIUM = Path("/usr/bin/chromium")
NEEDS_CHROMIUM = pytest.mark.skipif(
    not CHROMIUM.exists(),
    reason=f"{CHROMIUM} is absent (Debian: apt-get install chromium): the page is not rendered in a browser",
)


# ------------------------------------------------------------------ a tiny trace, by hand
def _e(kind: str, sim_s: float, **fields) -> dict:
    return {"v": 1, "seq": 0, "kind": kind, "wall_s": 0.0, "sim_s": sim_s, **fields}


def _units(action: str, *runs: tuple[str, float, float]) -> list[dict]:
    """Each (unit, start, end) as check and plan at its start and do at its end, all ok."""
    out = []
    for unit, a, b in runs:
        for step, t in (("check", a), ("plan", a), ("do", b)):
            out.append(_e("unit", t, action=action, unit=unit, step=step, ok=True, depth=0))
    return out


def _action(step: str, sim_s: float, seconds: float, path: list, robot: list, units: list, **more) -> dict:
    metres = sum(math.dist(a, b) for a, b in zip(path, path[1:], strict=False))
    fields = dict(action=step, ok=True, seconds=seconds, path=path, robot=robot, units=units, metres=metres)
    return _e("action", sim_s, **fields, **more)


PLAN = ["(move wp-entrance wp-toy-1)", "(take_object toy-1 wp-toy-1)", "(move wp-toy-1 wp-box)"]
PLAN.append("(deliver_it toy-1 box wp-box toy)")


def _tiny() -> list[dict]:
    """Drive 2 m east in 10 s (2-12 s), look; take the toy (grasp 16-28 s); drive 2 m north
    (30-40 s), look; put it into the box (42-52 s), look; the end at 54 s."""
    events = [
        _e("start", 0.0, strategy="ofsm", scenario="tiny", expected={"toy": 1}, robot=[0.0, 0.0]),
        _e("observe", 2.0, waypoint="wp-entrance", seen=1, new=["toy-1"], confirmed=[], forgotten=[]),
        _e("plan", 2.0, replan=0, cause="initial", why="", goal_kind="all", goal=["toy-1"], status="solved")
        | {"stratum": 1, "cost": 6.0, "probability": 0.9, "plan": PLAN, "adopted": True},
        *_units(PLAN[0], ("navigate", 2.0, 12.0), ("look", 12.0, 14.0)),
        _action(PLAN[0], 14.0, 12.0, [[1.0, 0.0], [2.0, 0.0]], [2.0, 0.0], ["navigate"]),
        *_units(PLAN[1], ("adjust_base", 15.0, 15.0), ("grasp", 16.0, 28.0), ("look", 28.0, 30.0)),
        _action(PLAN[1], 30.0, 16.0, [], [2.0, 0.0], ["adjust_base", "grasp"]),
        *_units(PLAN[2], ("navigate", 30.0, 40.0), ("look", 40.0, 42.0)),
        _action(PLAN[2], 42.0, 12.0, [[2.0, 1.0], [2.0, 2.0]], [2.0, 2.0], ["navigate"]),
        *_units(PLAN[3], ("approach_deposit", 42.0, 42.0), ("place", 42.0, 52.0), ("look", 52.0, 54.0)),
        _action(PLAN[3], 54.0, 12.0, [], [2.0, 2.0], ["approach_deposit", "place"], delivered="toy-1"),
        _e("end", 54.0, success=True, reason="goal reached", items={"toy": ["tidied:box", 2.0, 2.1]}),
    ]
    return [e | {"seq": i} for i, e in enumerate(events)]


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.jsonl"
    path.write_text("".join(json.dumps(e) + "\n" for e in _tiny()))
    return path


def _embedded(text: str) -> dict:
    found = re.search(r'<script type="application/json" id="data">(.*?)</script>', text, re.S)
    assert found, "the page embeds its data"
    return json.loads(found.group(1))


# ------------------------------------------------------------------ the data the page draws
def test_the_robot_drives_its_recorded_path_during_its_motions_and_stands_still_otherwise(tiny):
    keys = keyframes(read_trace(tiny))
    assert [k[0] for k in keys] == sorted(k[0] for k in keys)
    expected = {
        0.0: (0.0, 0.0),  # the start
        2.0: (0.0, 0.0),  # navigate's do begins
        4.5: (0.5, 0.0),  # 2 m in 10 s
        7.0: (1.0, 0.0),  # the path's first point
        12.0: (2.0, 0.0),  # arrived: the look follows
        13.0: (2.0, 0.0),
        22.0: (2.0, 0.0),  # grasping
        35.0: (2.0, 1.0),  # north, half-way
        41.0: (2.0, 2.0),
        60.0: (2.0, 2.0),  # after the end
    }
    for t, xy in expected.items():
        x, y, _ = pose_at(keys, t)
        assert (x, y) == pytest.approx(xy, abs=1e-9), t
    assert pose_at(keys, 4.5)[2] == pytest.approx(0.0)  # heading east
    assert pose_at(keys, 35.0)[2] == pytest.approx(90.0)  # heading north
    assert pose_at(keys, 45.0)[2] == pytest.approx(90.0)  # still: the last heading


def test_the_belief_holds_the_toy_from_its_grasp_and_tidies_it_at_its_place(tiny):
    data = page_data(read_trace(tiny), None, [])
    assert data["belief"]["toy-1"]["keys"] == [
        [2.0, "seen", None, None],  # no problem file: its place is not recorded
        [28.0, "held", None, None],  # the grasp's do
        [52.0, "tidied", 2.0, 2.0],  # the place's do, where the robot stood (no room to find the box in)
    ]


def test_each_plan_step_is_passed_when_its_action_ends(tiny):
    (plan,) = page_data(read_trace(tiny), None, [])["plans"]
    assert plan["steps"] == PLAN and plan["until"] is None
    assert plan["began"] == [2.0, 14.0, 30.0, 42.0]
    assert plan["passed"] == [14.0, 30.0, 42.0, 54.0]


def test_the_page_is_one_file_that_fetches_nothing(tiny):
    warned = []
    text = page(read_trace(tiny), warn=warned.append)
    assert warned == [
        "the trace does not name its scenario file (give --scenario): the room is not drawn",
        "the plan events name no problem file: the believed places of the items are not drawn",
    ]
    for fetch in ("<link", "src=", "@import", "fetch(", "XMLHttpRequest", "import(", "<iframe", "<img"):
        assert fetch not in text, fetch
    assert re.findall(r"url\((?!#)", text) == []  # only references inside the page (a clip path)
    assert set(re.findall(r"https?://[^\s\"'<>]*", text)) == {"http://www.w3.org/2000/svg"}  # a name
    assert "default-src 'none'" in text  # and the browser is told to fetch nothing
    data = _embedded(text)
    assert data["summary"] == json.loads(json.dumps(summarise(read_trace(tiny))))
    assert data["notes"] == warned


def test_text_from_the_trace_cannot_end_the_pages_script(tmp_path):
    events = _tiny()
    events[-1]["reason"] = "goal reached </script><!-- <script>alert(1)</script>"
    path = tmp_path / "odd.jsonl"
    path.write_text("".join(json.dumps(e) + "\n" for e in events))
    text = page(read_trace(path))
    assert "alert(1)</script>" not in text
    assert _embedded(text)["summary"]["reason"] == events[-1]["reason"]


def test_a_trace_cut_off_mid_line_opens_up_to_its_last_whole_event_with_a_note(tiny, tmp_path):
    lines = tiny.read_text().splitlines(keepends=True)
    cut = tmp_path / "killed.jsonl"
    cut.write_text("".join(lines[:20]) + lines[20][:30])
    data = _embedded(page(read_trace(cut)))
    assert data["t_end"] == _tiny()[19]["sim_s"]
    assert data["notes"][0] == (
        f"{cut}: warning: cut off mid-line (a killed run?): read up to its last whole event, "
        f"seq 19 ({_tiny()[19]['kind']})"
    )
    assert not data["summary"]["complete"]


# ------------------------------------------------------------------ the command
def _trace(capsys, *args) -> tuple[int, str, str]:
    status = main(["trace", *map(str, args)])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_html_writes_the_page_and_never_replaces_a_file_unless_forced(tiny, tmp_path, capsys):
    out = tmp_path / "run.html"
    status, story, err = _trace(capsys, tiny, "--html", out)
    assert status == 0 and "tidied in order: toy-1" in story  # the story too, as with --plot
    assert err.splitlines()[-1] == f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB): open it in a browser"
    out.write_text("mine")
    status, story, err = _trace(capsys, tiny, "--html", out)
    assert (status, story, err) == (2, "", f"{out}: exists; --force replaces it\n")
    assert out.read_text() == "mine"
    status, _, _ = _trace(capsys, tiny, "--html", out, "--force")
    assert status == 0 and out.read_text().startswith("<!doctype html>")
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temporary left


@pytest.mark.parametrize(
    "target, why",
    [
        ("{tiny}", "is the trace itself; choose another --html file"),
        ("{tmp}", "is a directory; --html names the page's file"),
        ("{tmp}/no/such/folder/x.html", "cannot write the page: no such folder"),
    ],
)
def test_html_where_it_cannot_be_written_is_one_line_and_exit_2(target, why, tiny, tmp_path, capsys):
    out = target.format(tiny=tiny, tmp=tmp_path)
    status, story, err = _trace(capsys, tiny, "--html", out, "--force")
    assert (status, story, err) == (2, "", f"{out}: {why}\n")


def test_html_takes_one_trace(tiny, tmp_path, capsys):
    status, _, err = _trace(capsys, tiny, tiny, "--html", tmp_path / "x.html")
    assert (
        status == 2
        and err == "--plot, --html and --replan: give one trace (several are compared side by side)\n"
    )


# ------------------------------------------------------------------ a real mission
@pytest.fixture(scope="module")
def mission(tmp_path_factory) -> Path:
    """Case I, O-FSM, seed 1, items dropped while carried and missed by the camera."""
    trace = tmp_path_factory.mktemp("html") / "ofsm.jsonl"
    rates = Rates.parse("grasp_drop=0.2,perception_miss=0.2")
    run(
        project_file("problems/case1.toml"),
        trace,
        Settings(world="symbolic", planner="lama-first", time_budget=0.5, seed=1, rates=rates),
    )
    return trace


def _drives(trace) -> list[tuple[dict, float, float, list]]:
    """Actions driven by one navigate, no recovery: (action, do's start, do's end, polyline)."""
    out, before, at, units = [], 0.0, trace.start["robot"], []
    for e in trace.events:
        if e["kind"] == "unit" and e["step"] == "do" and e["unit"] == "navigate":
            units.append((before, e["sim_s"]))
        if e["kind"] == "action":
            if len(units) == 1 and e["metres"] > 1.0 and not e["recoveries"]:
                out.append((e, *units[0], [at, *e["path"]]))
            at, units = e["robot"], []
        if e["kind"] != "observe":
            before = e["sim_s"]
    return out


def _off_path(xy, polyline) -> float:
    def seg(p, a, b):
        ab = (b[0] - a[0], b[1] - a[1])
        n = ab[0] ** 2 + ab[1] ** 2
        f = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / n))
        return math.dist(p, (a[0] + f * ab[0], a[1] + f * ab[1]))

    return min(seg(xy, a, b) for a, b in zip(polyline, polyline[1:], strict=False))


@pytest.mark.slow
def test_the_track_passes_through_every_action_end_and_the_diffs_are_the_commands(mission):
    trace = read_trace(mission)
    data = page_data(trace, None, [])
    for a in trace.of("action"):
        assert pose_at(data["track"], a["sim_s"])[:2] == pytest.approx(tuple(a["robot"]), abs=1e-3)
    for r in data["replans"]:
        d = replan_diff(trace, r["replan"])
        assert r["diff"] == d["diff"] and r["kept"] == len(d["kept"]) and r["cause"] == d["cause"]
    assert [p["replan"] for p in data["plans"]] == [p["replan"] for p in adopted(trace)]
    assert len(page(trace).encode()) < 2_000_000


def _chromium(tmp_path: Path, url: str, *options: str) -> str:
    """Run headless Chromium on ``url``, its files under ``tmp_path``, in a session of its own;
    that session, and the crash handlers it starts in sessions of their own, end with the call."""
    command = [
        str(CHROMIUM),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
        f"--user-data-dir={tmp_path / 'chromium-profile'}",
        "--virtual-time-budget=5000",
        *options,
        url,
    ]
    env = os.environ | {
        "XDG_CONFIG_HOME": str(tmp_path / "xdg-config"),
        "XDG_CACHE_HOME": str(tmp_path / "xdg-cache"),
    }
    proc = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env, start_new_session=True
    )
    try:
        out, _ = proc.communicate(timeout=120)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)  # its renderers and helpers too
        proc.wait()
        _end_those_naming(tmp_path)
    return out


def _end_those_naming(folder: Path) -> None:
    """End the processes whose command line names ``folder``: Chromium's crash handlers, which
    keep their database under XDG_CONFIG_HOME (set inside ``folder`` above)."""
    mark = str(folder).encode()
    for entry in Path("/proc").iterdir():
        with contextlib.suppress(OSError):
            if entry.name.isdigit() and mark in (entry / "cmdline").read_bytes():
                os.kill(int(entry.name), signal.SIGKILL)


def _selftest(tmp_path: Path, page_file: Path, times: list[float], **more) -> dict:
    """What the page's self-test found at ``times`` (and with ``more``: replan=N, play=SPEED)."""
    query = "selftest=" + ",".join(f"{t:.3f}" for t in times) + "".join(f"&{k}={v}" for k, v in more.items())
    dom = _chromium(tmp_path, f"{page_file.as_uri()}#{query}", "--dump-dom")
    found = re.search(r'<pre id="selftest"[^>]*>(.*?)</pre>', dom, re.S)
    assert found and found.group(1), "the page's self-test wrote nothing"
    result = json.loads(html.unescape(found.group(1)))
    assert result["errors"] == []
    # the header's figures as drawn: label -> text
    result["figures"] = {
        html.unescape(k).strip(): html.unescape(v)
        for k, v in re.findall(r'<span class="fig"><b>(.*?)</b><span[^>]*>(.*?)</span></span>', dom)
    }
    return result


@pytest.mark.slow
@NEEDS_CHROMIUM
def test_in_chromium_the_robot_is_drawn_where_the_trace_has_it_and_a_replan_diff_opens(
    mission, tmp_path, capsys
):
    out = tmp_path / "run.html"
    assert _trace(capsys, mission, "--html", out)[0] == 0
    trace = read_trace(mission)
    drives = _drives(trace)[:3]
    assert drives, "the seeded run no longer has a plain drive: choose another seed"
    # at an action's end the robot stands at its `robot` (the glance after it takes no time)
    looks = trace.of("action")[::9]
    times = [0.0] + [(a + b) / 2 for _, a, b, _ in drives] + [a["sim_s"] for a in looks]
    replan = next(p["replan"] for p in trace.of("plan") if p["cause"] == "assumption_contradicted")
    result = _selftest(tmp_path, out, times, replan=replan, play=100)

    poses = result["poses"]
    assert [p["shown"] for p in poses] == pytest.approx(times, abs=1e-3)  # the slider moved there
    s = summarise(trace)
    score = f"{s['wrs_score']:g} within {s['time_limit_s']:g} s ({s['wrs_score_at_end']:g} at the end)"
    assert result["figures"]["WRS score"] == score
    assert (poses[0]["x"], poses[0]["y"]) == pytest.approx(tuple(trace.start["robot"]), abs=0.01)
    keys = keyframes(trace)
    for p, (_, _, _, polyline) in zip(poses[1:], drives, strict=False):  # mid-drive: on its path
        assert _off_path((p["x"], p["y"]), polyline) < 0.01
        assert (p["x"], p["y"]) == pytest.approx(pose_at(keys, p["t"])[:2], abs=0.01)
    for p, a in zip(poses[1 + len(drives) :], looks, strict=True):
        assert (p["x"], p["y"]) == pytest.approx(tuple(a["robot"]), abs=0.01), a["action"]

    d = replan_diff(trace, replan)
    assert result["diff"]["open"] and result["diff"]["replan"] == str(replan)
    assert result["diff"]["title"].startswith(
        f"replan {replan} at {d['sim_s']} s simulated: assumption_contradicted"
    )
    assert result["diff"]["counts"] == (
        f"plan against the rest of replan {d['previous']['replan']} ({len(d['rest'])} steps left): "
        f"{len(d['kept'])} kept, {len(d['dropped'])} dropped, {len(d['added'])} added"
    )
    assert result["diff"]["t"] == pytest.approx(d["sim_s"])  # the click moved the time there too
    # then the play button: a (virtual) second at 100 simulated seconds a second
    assert result["play"]["from"] == pytest.approx(d["sim_s"]) and result["play"]["button"] == "❚❚ pause"
    assert result["play"]["to"] - result["play"]["from"] == pytest.approx(100, abs=10)


@pytest.mark.slow
@NEEDS_CHROMIUM
def test_in_chromium_a_killed_run_opens_with_its_note_and_a_screenshot_is_drawn(mission, tmp_path, capsys):
    lines = mission.read_text().splitlines(keepends=True)
    cut = tmp_path / "killed.jsonl"
    cut.write_text("".join(lines[:150]) + lines[150][:40])
    out = tmp_path / "killed.html"
    status, _, err = _trace(capsys, cut, "--html", out)
    assert status == 0 and "cut off mid-line" in err
    trace = read_trace(cut)
    last = trace.of("action")[-1]
    result = _selftest(tmp_path, out, [last["sim_s"]])  # its end: where the action left the robot
    assert (result["poses"][0]["x"], result["poses"][0]["y"]) == pytest.approx(tuple(last["robot"]), abs=0.01)
    assert result["notes"][0].startswith(f"{cut}: warning: cut off mid-line (a killed run?)")
    assert result["notes"][-1].startswith("unfinished: without a summary")

    from matplotlib.image import imread

    png = tmp_path / "replay.png"
    _chromium(
        tmp_path,
        f"{out.as_uri()}#t={last['sim_s'] / 2:.1f}",
        f"--screenshot={png}",
        "--window-size=1400,1000",
    )
    image = imread(png)
    assert image.shape[:2] == (1000, 1400)
    assert len({tuple(p) for p in (image[::7, ::7, :3] * 255).astype(int).reshape(-1, 3)}) > 50  # not blank
