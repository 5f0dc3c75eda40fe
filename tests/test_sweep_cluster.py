"""`tidyplan sweep --ray ADDRESS` on a cluster that loses a node, and a driver that is killed.

A Ray cluster of a head (no CPU) and three worker nodes of one CPU each runs on this machine
(``ray.cluster_utils.Cluster``); the sweep's driver runs in a process of its own against the
cluster's address, as `tidyplan sweep --ray ADDRESS` would. Its missions are a stand-in that logs
each attempt (seed, pid, the raylet of its node) and then blocks until the test opens its gate (a
file), so the test decides when a node goes and what is running on it, with no guessing of timing.

The rules held (docs/sweep.md, "When a node or the driver is lost"): the table has each mission of
the grid once, none lost or doubled; a mission whose node died is rerun on another node by Ray
(``max_retries``) and is one row; a driver killed mid-sweep loses at most the missions then running,
and the same sweep again runs only those.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from processes import descendants, still_running_after

ray_cluster_utils = pytest.importorskip(
    "ray.cluster_utils", reason="Ray is an optional extra: pip install '.[ray]'"
)

pytestmark = pytest.mark.slow

SEEDS = list(range(6))

GATED = """
import json, os, time
from pathlib import Path

def gated(config, trace):
    gate = Path(trace).parents[1] / "gate"  # the table's folder: DIR/traces/<mission>.jsonl
    seed = config["seed"]
    attempt = {"seed": seed, "pid": os.getpid(), "raylet": int(os.environ["RAY_RAYLET_PID"]), "trace": trace}
    with open(trace, "x") as f:  # as tidyplan's trace writer opens it: never over an existing trace
        f.write(json.dumps({"event": "start", **attempt}) + "\\n")
    with open(gate / "started", "a") as f:
        f.write(json.dumps(attempt) + "\\n")
    while not (gate / "open").exists() and not (gate / f"open-{seed}").exists():
        time.sleep(0.01)
    with open(gate / "ended", "a") as f:
        f.write(json.dumps(attempt) + "\\n")
    return {"success": True, "sim_time_s": 10.0 + seed, "distance_m": 1.0, "replans": 1,
            "recoveries": 0, "wrs_score": 290.0, "trace": trace}
"""

DRIVER = """
import json, sys
from tidyplan.loop.scenarios import project_file
from tidyplan.sweep.grid import grid, run_sweep

out, address, seeds = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
configs = grid([str(project_file("problems/case1.toml"))], seeds, ["ofsm"], [""], ["lama-first"], "symbolic")
rows = run_sweep(configs, out, ray=True, address=address, limit=120, target="sweep_fakes:gated")
print(json.dumps([r["seed"] for r in rows]))
"""


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """The cluster, its stand-in missions on every node's PYTHONPATH; shut down at the end, and no
    process it started left."""
    folder = tmp_path_factory.mktemp("cluster")
    (folder / "sweep_fakes.py").write_text(textwrap.dedent(GATED))
    (folder / "driver.py").write_text(textwrap.dedent(DRIVER))
    before = descendants()
    with pytest.MonkeyPatch.context() as mp:
        # the raylets, their workers and the missions under them inherit this environment
        mp.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(folder), os.environ.get("PYTHONPATH")])))
        mp.setenv("PYTHONUNBUFFERED", "1")
        # Ray's session (sockets, logs) under the test's folder too, not /tmp/ray
        head = {"num_cpus": 0, "include_dashboard": False, "temp_dir": str(tmp_path_factory.mktemp("ray"))}
        c = ray_cluster_utils.Cluster(initialize_head=True, connect=False, head_node_args=head)
        try:
            for _ in range(3):
                c.add_node(num_cpus=1)
            c.folder = folder
            yield c
        finally:
            c.shutdown()
    assert still_running_after(descendants() - before) == set()


def _driver(cluster, out: Path) -> subprocess.Popen:
    (out / "gate").mkdir(parents=True, exist_ok=True)
    return subprocess.Popen(
        [sys.executable, str(cluster.folder / "driver.py"), str(out), cluster.address, json.dumps(SEEDS)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _lines(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []


def _rows(out: Path) -> list[dict]:
    return _lines(out / "results.jsonl")


def _wait_for(condition, what: str, driver: subprocess.Popen, timeout: float = 120.0):
    """Poll the files the sweep writes until ``condition()`` holds; the limit only turns a hang into
    a failure (it bounds nothing the test asserts)."""
    deadline = time.monotonic() + timeout
    while not (found := condition()):
        if driver.poll() is not None:
            pytest.fail(
                f"the driver ended ({driver.returncode}) before {what}: {driver.stderr.read()[-2000:]}"
            )
        if time.monotonic() > deadline:
            driver.kill()
            pytest.fail(f"no {what} within {timeout:g} s")
        time.sleep(0.02)
    return found


def _finish(driver: subprocess.Popen) -> list[int]:
    stdout, stderr = driver.communicate(timeout=300)
    assert driver.returncode == 0, stderr[-2000:]
    return json.loads(stdout.splitlines()[-1])


def test_a_node_lost_mid_sweep_has_its_mission_rerun_elsewhere_and_counted_once(cluster, tmp_path):
    out = tmp_path / "sweep"
    gate = out / "gate"
    driver = _driver(cluster, out)
    # every worker node busy with one mission, each blocked at its gate
    first = _wait_for(
        lambda: len(_lines(gate / "started")) >= 3 and _lines(gate / "started"), "3 missions", driver
    )
    raylets = {node.all_processes["raylet"][0].process.pid: node for node in cluster.worker_nodes}
    assert sorted(a["raylet"] for a in first) == sorted(raylets)  # one a node (1 CPU each)
    victim = first[0]
    cluster.remove_node(raylets[victim["raylet"]])
    assert still_running_after({victim["pid"]}) == set()  # the mission went with its node's worker
    (gate / "open").touch()
    assert _finish(driver) == SEEDS

    rows = _rows(out)
    assert sorted(r["seed"] for r in rows) == SEEDS  # each mission once: none lost, none doubled
    assert {r["status"] for r in rows} == {"done"}
    started, ended = _lines(gate / "started"), _lines(gate / "ended")
    assert sorted(a["seed"] for a in ended) == SEEDS  # each mission finished once
    reruns = [a for a in started if a["seed"] == victim["seed"]]
    assert len(reruns) == 2 and reruns[1]["raylet"] != victim["raylet"]  # Ray's retry, on another node
    assert sorted(a["seed"] for a in started) == sorted([*SEEDS, victim["seed"]])  # no other rerun
    # the rerun's trace is its own (a trace is never overwritten, and the first attempt left one):
    # with the first attempt's path the rerun would crash, a `crashed` row for a mission that ran
    (row,) = [r for r in rows if r["seed"] == victim["seed"]]
    assert reruns[1]["trace"] != reruns[0]["trace"] and row["trace"] == reruns[1]["trace"]


def test_a_driver_killed_mid_sweep_loses_only_its_running_missions_and_a_rerun_completes(cluster, tmp_path):
    out = tmp_path / "sweep"
    gate = out / "gate"
    driver = _driver(cluster, out)
    nodes = len(cluster.worker_nodes)  # after the first test, two; alone, three
    first = _wait_for(lambda: (s := _lines(gate / "started")) and len(s) >= nodes and s, "a wave", driver)
    for attempt in first:  # the first wave ends, and its rows are written
        (gate / f"open-{attempt['seed']}").touch()
    _wait_for(lambda: len(_rows(out)) == nodes, f"{nodes} rows", driver)
    running = _wait_for(
        lambda: (s := _lines(gate / "started")) and len(s) >= 2 * nodes and s[nodes:], "a second wave", driver
    )
    driver.send_signal(signal.SIGKILL)
    driver.wait()
    # the cluster ends a dead driver's tasks: its missions end with their workers
    assert still_running_after({a["pid"] for a in running}) == set()
    kept = sorted(r["seed"] for r in _rows(out))
    assert kept == sorted(a["seed"] for a in first)

    (gate / "open").touch()
    rerun = _driver(cluster, out)
    assert _finish(rerun) == SEEDS
    rows = _rows(out)
    assert sorted(r["seed"] for r in rows) == SEEDS  # the rows kept, and the rest: none doubled
    started = _lines(gate / "started")[2 * nodes :]
    assert sorted(a["seed"] for a in started) == sorted(set(SEEDS) - set(kept))  # only the missing ran
