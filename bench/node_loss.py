"""A sweep on a 3-node Ray cluster that loses a node mid-sweep: is every mission in the table once?

    python bench/node_loss.py [--seeds 0-3] [--nodes 3] [--remove-after 3] [--out DIR]

Starts a Ray cluster on this machine (``ray.cluster_utils.Cluster``: a head with no CPU, ``--nodes``
worker nodes of one CPU each), runs ``tidyplan sweep problems/case1.toml problems/case2.toml
problems/case3.toml --seeds A-B --world symbolic --planner lama-first --ray ADDRESS`` against it
(12 missions by default), and once ``--remove-after`` rows are in the table removes the worker node
that runs the oldest running mission (``cluster.remove_node``). Meanwhile it watches the mission
processes (``python -m tidyplan.sweep.missions``) under the cluster's raylets: which node each
attempt ran on and which mission it was (the trace it has open). Prints the table: missions of the
grid, rows, duplicates, lost, reruns (missions with more than one attempt), and per node the
attempts started, ended in a row, and killed. Exit status 0 when the table holds each mission
once, all ``done``, 1 otherwise. Needs the ray extra (``pip install '.[ray]'``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = [ROOT / "problems" / f"case{n}.toml" for n in (1, 2, 3)]


def _children() -> dict[int, list[int]]:
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                ppid = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            children.setdefault(ppid, []).append(int(entry.name))
    return children


def _under(root: int, children) -> list[tuple[int, int]]:
    """(pid, parent) of every process under ``root``."""
    out, todo = [], [root]
    while todo:
        parent = todo.pop()
        for child in children.get(parent, []):
            out.append((child, parent))
            todo.append(child)
    return out


def _is_mission(pid: int) -> bool:
    try:
        return b"tidyplan.sweep.missions" in Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return False


def _mission_of(pid: int, parent: int) -> str | None:
    """The mission a process runs: the trace it has open, without a retry's ``-N``. A process the
    mission forks (to start Fast Downward's search) looks the same until it execs: not an attempt."""
    if not _is_mission(pid) or _is_mission(parent):
        return None
    try:
        for fd in Path(f"/proc/{pid}/fd").iterdir():
            target = os.readlink(fd)
            if "/traces/" in target and target.endswith(".jsonl"):
                return re.sub(r"-\d+$", "", Path(target).stem)
    except OSError:
        pass
    return None


class Watch(threading.Thread):
    """Every 50 ms, the mission processes under each node's raylet: pid -> (node, mission)."""

    def __init__(self, raylets: dict[int, str]) -> None:
        super().__init__(daemon=True)
        self.raylets, self.attempts, self.alive, self.stop = raylets, {}, set(), threading.Event()

    def run(self) -> None:
        while not self.stop.is_set():
            children, alive = _children(), set()
            for raylet, node in self.raylets.items():
                for pid, parent in _under(raylet, children):
                    if pid not in self.attempts and (mission := _mission_of(pid, parent)):
                        self.attempts[pid] = (node, mission, time.monotonic())
                    if pid in self.attempts:
                        alive.add(pid)
            self.alive = alive
            time.sleep(0.05)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", default="0-3")
    ap.add_argument("--nodes", type=int, default=3)
    ap.add_argument("--remove-after", type=int, default=3, help="rows in the table before a node goes")
    ap.add_argument("--out", help="the sweep's folder (default: a temporary one)")
    args = ap.parse_args()
    try:
        from ray.cluster_utils import Cluster
    except ImportError:
        print("bench/node_loss.py: needs Ray: pip install '.[ray]'", file=sys.stderr)
        return 2

    out = Path(args.out or tempfile.mkdtemp(prefix="node-loss-"))
    started = time.monotonic()
    cluster = Cluster(
        initialize_head=True, connect=False, head_node_args={"num_cpus": 0, "include_dashboard": False}
    )
    try:
        nodes = [cluster.add_node(num_cpus=1) for _ in range(args.nodes)]
        raylets = {
            node.all_processes["raylet"][0].process.pid: f"node{i + 1}" for i, node in enumerate(nodes)
        }
        by_name = {name: node for node, name in zip(nodes, raylets.values(), strict=True)}
        print(
            f"cluster: head (0 CPU) + {args.nodes} nodes of 1 CPU at {cluster.address}, up in "
            f"{time.monotonic() - started:.1f} s"
        )
        watch = Watch(raylets)
        watch.start()
        command = [
            sys.executable,
            "-m",
            "tidyplan.cli.main",
            "sweep",
            *map(str, CASES),
            "--seeds",
            args.seeds,
            "--world",
            "symbolic",
            "--planner",
            "lama-first",
            "--ray",
            cluster.address,
            "--out",
            str(out),
            "--quiet",
        ]
        print("+", " ".join(command[2:]))
        t0 = time.monotonic()
        sweep = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        removed, killed = None, set()
        while sweep.poll() is None:
            rows = _rows(out)
            if removed is None and len(rows) >= args.remove_after and watch.alive:
                pid = min(watch.alive, key=lambda p: watch.attempts[p][2])
                removed = watch.attempts[pid][0]
                running = {p for p in watch.alive if watch.attempts[p][0] == removed}
                cluster.remove_node(by_name[removed])
                killed = set(running)
                print(
                    f"removed {removed} at {time.monotonic() - t0:.1f} s, with {len(rows)} rows in the "
                    f"table, running {', '.join(watch.attempts[p][1] for p in sorted(running))}"
                )
            time.sleep(0.1)
        output = sweep.stdout.read()
        wall = time.monotonic() - t0
        time.sleep(0.2)  # one more look for the watcher
        watch.stop.set()
        watch.join()
    finally:
        cluster.shutdown()

    rows = _rows(out)
    keys = Counter(_key(r) for r in rows)
    missions = 3 * len(range(*_span(args.seeds)))
    attempts_of = Counter(m for _, m, _ in watch.attempts.values())
    final = {re.sub(r"-\d+$", "", Path(r["trace"]).stem): Path(r["trace"]) for r in rows if r.get("trace")}
    print(f"sweep: exit {sweep.returncode}, {wall:.1f} s wall")
    print(*[line for line in output.splitlines() if line.startswith("table:")] or ["(no table line)"])
    print()
    print("| missions | rows | duplicates | lost | crashed or timeout | reruns | attempts seen |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    bad = sum(r["status"] != "done" for r in rows)
    reruns = sorted(m for m, n in attempts_of.items() if n > 1)
    print(
        f"| {missions} | {len(rows)} | {sum(n - 1 for n in keys.values())} | {missions - len(keys)} "
        f"| {bad} | {len(reruns)} | {len(watch.attempts)} |"
    )
    print()
    print("| node | attempts started | killed with the node | missions it ended |")
    print("| --- | --- | --- | --- |")
    for name in raylets.values():
        mine = [p for p, (n, _, _) in watch.attempts.items() if n == name]
        dead = [p for p in mine if p in killed]
        print(
            f"| {name}{' (removed)' if name == removed else ''} | {len(mine)} | {len(dead)} "
            f"| {len(mine) - len(dead)} |"
        )
    for m in reruns:
        nodes_of = [n for _, (n, mm, t) in sorted(watch.attempts.items(), key=lambda kv: kv[1][2]) if mm == m]
        print(
            f"rerun: {m}: attempts on {' then '.join(nodes_of)}; "
            f"its row's trace {final.get(m, Path('?')).name}"
        )
    ok = len(rows) == missions == len(keys) and bad == 0
    return 0 if ok else 1


def _span(text: str) -> tuple[int, int]:
    a, _, b = text.partition("-")
    return int(a), int(b or a) + 1


def _key(row: dict) -> tuple:
    return (row["scenario_file"], row["seed"], row["strategy"], row["faults"], row["planner"], row["world"])


def _rows(out: Path) -> list[dict]:
    path = out / "results.jsonl"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip().endswith("}")]


if __name__ == "__main__":
    sys.exit(main())
