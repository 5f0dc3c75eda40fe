"""`tidyplan sweep`: the grid, the resumable table, crashing and hanging missions, the summary.

Most tests inject stand-in missions (``module:function`` in a file under tmp_path, found through
PYTHONPATH by each mission's process) so they take no planner time; the slow ones run real
symbolic missions of case I with the deterministic ``lama-first``.
"""

from __future__ import annotations

import json
import os
import textwrap
from dataclasses import asdict, replace
from pathlib import Path

import pytest
from processes import descendants, still_running_after

from tidyplan.cli.main import main
from tidyplan.errors import InputError
from tidyplan.loop.scenarios import project_file
from tidyplan.sweep import report as sweep_report
from tidyplan.sweep.grid import RESULTS, MissionConfig, Table, canonical_faults, grid, parse_seeds, run_sweep

CASE1 = str(project_file("problems/case1.toml"))

FAKES = """
import os, time

def ok(config, trace):
    with open(os.environ["SWEEP_LOG"], "a") as f:
        f.write(f"{config['seed']}\\n")
    return {"success": config["seed"] % 2 == 0, "sim_time_s": 10.0 + config["seed"], "distance_m": 1.0,
            "replans": 1, "recoveries": 0, "wrs_score": 290.0, "trace": trace}

def crash_on_1(config, trace):
    if config["seed"] == 1:
        raise RuntimeError("the world fell over")
    return ok(config, trace)

def die(config, trace):
    print("segfault, say")
    os._exit(3)

def hang(config, trace):
    with open(os.environ["SWEEP_PIDS"], "a") as f:
        f.write(f"{os.getpid()}\\n")
    time.sleep(3600)
"""


@pytest.fixture
def fakes(tmp_path, monkeypatch):
    folder = tmp_path / "fakes"
    folder.mkdir()
    (folder / "sweep_fakes.py").write_text(textwrap.dedent(FAKES))
    path = [str(folder), os.environ.get("PYTHONPATH")]
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, path)))
    monkeypatch.setenv("SWEEP_LOG", str(tmp_path / "ran.txt"))
    monkeypatch.setenv("SWEEP_PIDS", str(tmp_path / "pids.txt"))
    return tmp_path


def _ran(tmp_path: Path) -> list[int]:
    log = tmp_path / "ran.txt"
    return sorted(int(s) for s in log.read_text().split()) if log.exists() else []


def _configs(seeds=range(4)) -> list[MissionConfig]:
    return grid([CASE1], list(seeds), ["ofsm"], [""], ["lama-first"], "symbolic")


def _hangers_left() -> set[int]:
    """Processes of the hanging stand-in this test started that are still running (a mission
    killed before it wrote its pid, on a loaded machine, is found too: tests/processes.py)."""
    return still_running_after(descendants(b"sweep_fakes:hang"))


# ------------------------------------------------------------------ the grid
def test_seeds_are_a_range_both_ends_included():
    assert parse_seeds("0-3") == [0, 1, 2, 3]
    assert parse_seeds("5") == [5]
    assert parse_seeds("0-1,4") == [0, 1, 4]
    with pytest.raises(InputError):
        parse_seeds("3-1")


def test_fault_conditions_are_keyed_sorted_and_checked():
    assert canonical_faults("perception_miss=0.2, grasp_drop=0.1") == "grasp_drop=0.1,perception_miss=0.2"
    assert canonical_faults("none") == ""
    with pytest.raises(InputError):
        canonical_faults("gremlins=0.5")


def test_grid_is_every_combination():
    configs = grid([CASE1], [0, 1], ["ofsm", "greedy"], ["", "grasp_drop=0.1"], ["lama"], "symbolic")
    assert len(configs) == 8 and len({c.key for c in configs}) == 8
    assert len({c.condition for c in configs}) == 4


def test_wilson_interval_stays_in_0_1_and_matches_the_formula():
    assert sweep_report.wilson(10, 10)[1] == pytest.approx(1.0) and sweep_report.wilson(0, 10)[0] == 0.0
    lo, hi = sweep_report.wilson(5, 10)
    assert lo == pytest.approx(0.2366, abs=1e-4) and hi == pytest.approx(0.7634, abs=1e-4)


# ------------------------------------------------------------------ the table
def test_rows_go_to_jsonl_and_csv_and_a_second_run_redoes_nothing(fakes):
    out = fakes / "sweep"
    rows = run_sweep(_configs(), out, jobs=2, limit=60, target="sweep_fakes:ok")
    assert sorted(r["seed"] for r in rows) == [0, 1, 2, 3] and {r["status"] for r in rows} == {"done"}
    csv_lines = (out / "results.csv").read_text().splitlines()
    assert len(csv_lines) == 5 and csv_lines[0].startswith("scenario_file,seed,")
    again = run_sweep(_configs(), out, jobs=2, limit=60, target="sweep_fakes:ok")
    assert _ran(fakes) == [0, 1, 2, 3] and again == rows


def test_resume_after_a_kill_runs_only_the_missing_rows_and_drops_a_row_cut_short(fakes):
    out = fakes / "sweep"
    run_sweep(_configs(range(2)), out, jobs=1, limit=60, target="sweep_fakes:ok")
    with open(out / RESULTS, "a") as f:
        f.write('{"scenario_file": "cut mid-wa')  # what kill -9 during a write leaves
    warnings = []
    assert len(Table(out, warnings.append).rows) == 2 and "cut short" in warnings[0]
    rows = run_sweep(_configs(), out, jobs=2, limit=60, target="sweep_fakes:ok", warn=warnings.append)
    assert _ran(fakes) == [0, 1, 2, 3] and len(rows) == 4
    assert len(Table(out).rows) == 4  # the cut line is gone, every row reads


def test_an_interrupted_sweep_stops_its_missions_and_a_rerun_completes_the_table(fakes):
    out = fakes / "sweep"

    def interrupt(row):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(_configs(), out, jobs=1, limit=60, target="sweep_fakes:ok", on_row=interrupt)
    assert len(Table(out).rows) == 1
    rows = run_sweep(_configs(), out, jobs=2, limit=60, target="sweep_fakes:ok")
    assert len(rows) == 4 and _ran(fakes) == [0, 1, 2, 3]


def test_a_crashing_mission_is_a_row_and_the_sweep_goes_on(fakes):
    rows = run_sweep(_configs(range(3)), fakes / "sweep", jobs=2, limit=60, target="sweep_fakes:crash_on_1")
    by_seed = {r["seed"]: r for r in rows}
    assert by_seed[1]["status"] == "crashed" and "the world fell over" in by_seed[1]["error"]
    assert by_seed[0]["status"] == by_seed[2]["status"] == "done"


def test_a_mission_whose_process_dies_is_a_crashed_row_with_its_last_output(fakes):
    (row,) = run_sweep(_configs(range(1)), fakes / "sweep", jobs=1, limit=60, target="sweep_fakes:die")
    assert row["status"] == "crashed" and "status 3" in row["error"] and "segfault, say" in row["error"]


def test_a_hanging_mission_is_killed_at_the_limit_and_recorded_as_a_timeout(fakes):
    rows = run_sweep(_configs(range(1)), fakes / "sweep", jobs=1, limit=1.0, target="sweep_fakes:hang")
    assert rows[0]["status"] == "timeout" and "killed" in rows[0]["error"]
    assert _hangers_left() == set()
    pids = fakes / "pids.txt"  # written only if the mission got that far within the limit
    assert not still_running_after({int(p) for p in (pids.read_text().split() if pids.exists() else [])})


def test_report_pools_seeds_by_condition_and_counts_crashes_as_failures(fakes):
    rows = run_sweep(_configs(range(3)), fakes / "sweep", jobs=2, limit=60, target="sweep_fakes:crash_on_1")
    (entry,) = sweep_report.conditions(rows)
    assert entry["missions"] == 3 and entry["success"] == 2 and entry["crashed"] == 1
    assert entry["sim_time_s"][0] == pytest.approx(11.0)  # seeds 0 and 2: the crash has no time
    lines = sweep_report.report_lines(rows)
    assert "case1 ofsm lama-first baseline symbolic" in lines[1]


def test_report_by_named_fields_pools_the_rest(fakes, capsys):
    case2 = str(project_file("problems/case2.toml"))
    configs = grid([CASE1, case2], [0, 1], ["ofsm"], [""], ["lama-first"], "symbolic")
    rows = run_sweep(configs, fakes / "sweep", jobs=2, limit=60, target="sweep_fakes:ok")
    assert [e["missions"] for e in sweep_report.conditions(rows)] == [2, 2]  # a line per scenario
    (pooled,) = sweep_report.conditions(rows, ("strategy", "faults"))
    assert pooled["missions"] == 4 and pooled["success"] == 2 and pooled["label"] == "ofsm baseline"
    assert main(["sweep", "--report", str(fakes / "sweep"), "--by", "strategy,faults"]) == 0
    assert "ofsm baseline   4   2  50%" in capsys.readouterr().out
    assert main(["sweep", "--report", str(fakes / "sweep"), "--by", "seed"]) == 2
    assert "--by: 'seed' is not one of" in capsys.readouterr().err


# ------------------------------------------------------------------ the command line
def test_sweep_without_ray_installed_exits_2_naming_the_extra(monkeypatch, capsys, tmp_path):
    from tidyplan.cli import sweep as cli_sweep

    monkeypatch.setattr(cli_sweep, "ray_missing", lambda: True)
    args = [CASE1, "--seeds", "0-1", "--world", "symbolic", "--out", str(tmp_path / "s")]
    assert main(["sweep", *args, "--ray"]) == 2
    assert "pip install '.[ray]'" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


def test_sweep_refuses_bad_input_with_exit_2(capsys, tmp_path):
    assert main(["sweep", CASE1, "--seeds", "0-1", "--out", str(tmp_path), "--faults", "x=1"]) == 2
    assert main(["sweep", "--report", str(tmp_path / "none")]) == 2
    assert main(["sweep", CASE1, "--out", str(tmp_path)]) == 2


@pytest.mark.slow
def test_sweep_of_real_missions_matches_single_runs_and_reports(capsys, tmp_path):
    from tidyplan.loop.mission import run
    from tidyplan.loop.options import Settings

    out = tmp_path / "sweep"
    args = ["sweep", CASE1, "--seeds", "0-1", "--world", "symbolic", "--planner", "lama-first"]
    assert main([*args, "--out", str(out), "--jobs", "2", "--quiet", "--plot", str(tmp_path / "s.png")]) == 0
    rows = {r["seed"]: r for r in Table(out).rows}
    alone = run(CASE1, tmp_path / "alone.jsonl", Settings("ofsm", 1, planner="lama-first", world="symbolic"))
    for key in ("success", "delivered", "actions", "replans", "recoveries", "distance_m", "wrs_score"):
        assert rows[1][key] == alone[key], key
    assert Path(rows[0]["trace"]).exists() and (tmp_path / "s.png").exists()
    capsys.readouterr()
    assert main(["sweep", "--report", str(out)]) == 0
    assert "case1 ofsm lama-first baseline symbolic   2   2 100%" in capsys.readouterr().out


@pytest.mark.slow
def test_ray_gives_the_local_pools_rows(tmp_path):
    pytest.importorskip("ray", reason="Ray is an optional extra: pip install '.[ray]'")
    configs = _configs(range(2))
    local = run_sweep(configs, tmp_path / "local", jobs=2, limit=300)
    on_ray = run_sweep(configs, tmp_path / "ray", jobs=2, ray=True, limit=300)
    assert [_same(r) for r in local] == [_same(r) for r in on_ray]


@pytest.mark.slow
def test_on_ray_a_hanging_mission_is_a_timeout_row_and_leaves_no_process(fakes):
    pytest.importorskip("ray", reason="Ray is an optional extra: pip install '.[ray]'")
    (row,) = run_sweep(
        _configs(range(1)), fakes / "ray", jobs=1, ray=True, limit=1.0, target="sweep_fakes:hang"
    )
    assert row["status"] == "timeout"
    assert _hangers_left() == set()
    pids = fakes / "pids.txt"  # written only if the mission got that far within the limit
    assert not still_running_after({int(p) for p in (pids.read_text().split() if pids.exists() else [])})


def _same(row: dict) -> dict:
    """A row without what differs from run to run of a deterministic mission: wall times, paths."""
    return {k: v for k, v in row.items() if k not in ("wall_time_s", "replan_time_s", "trace")}


def test_config_round_trips_through_a_row():
    c = _configs(range(1))[0]
    row = json.loads(json.dumps({**asdict(c), "status": "done", "success": True}))
    assert MissionConfig.from_row(row) == c and replace(c, seed=5).condition == c.condition
