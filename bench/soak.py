"""Long runs stay well: memory, open files and processes over a long mission and a long sweep.

    python bench/soak.py mission ROOM.toml [--seed 0] [--every 1] [--out DIR]
    python bench/soak.py sweep SCENARIO... [--seeds 0-199] [--jobs 2] [--faults K=V,...]
                         [--every 2] [--out DIR]

``mission``: ``tidyplan run ROOM --world symbolic`` as a child (a 96-object room: ``python
bench/wrs.py --layout two --rooms 1 --per-room 12 --out DIR``). Every ``--every`` seconds the
child's RSS (``/proc/PID/status`` VmRSS), its open file descriptors (``/proc/PID/fd``) and the
processes under it (its tree, from ``/proc/*/stat``: Fast Downward's searches) are sampled; the
trace it writes is followed, so each sample knows how many plans had been made. Printed: the
time series, then RSS after the first replan (the first sample once a ``plan`` event with
``replan`` 1 is in the trace) against RSS at the end, fds and children first / last / max.

``sweep``: ``tidyplan sweep ... --world symbolic --jobs N`` as a child (heavy faults by
default), sampling the driver (RSS, fds, children) and the missions under it (how many, their
RSS summed); at the end the table's rows by status, the crashed ones listed.

The figures are the kernel's, for processes this benchmark started; nothing else is looked at.
Traces and the table go under DIR (default: a new temporary folder).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

from tidyplan.sweep.missions import descendants

HEAVY = "grasp_drop=0.2,perception_miss=0.2,perception_false=0.05,path_blocked=0.1"


# ------------------------------------------------------------------ /proc
def _rss_kb(pid: int) -> int:
    """VmRSS of a process in kB (0 once it is gone or a zombie)."""
    with contextlib.suppress(OSError):
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def _fds(pid: int) -> int:
    try:
        return len(os.listdir(f"/proc/{pid}/fd"))
    except OSError:
        return 0


def _direct(pid: int, tree: list[int]) -> list[int]:
    found = []
    for child in tree:
        with contextlib.suppress(OSError, ValueError, IndexError):
            with open(f"/proc/{child}/stat") as f:
                if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                    found.append(child)
    return found


def sample(pid: int) -> dict:
    tree = descendants(pid)
    missions = _direct(pid, tree)
    return {
        "rss_kb": _rss_kb(pid),
        "fds": _fds(pid),
        "children": len(tree),
        "direct": len(missions),
        "tree_rss_kb": sum(_rss_kb(p) for p in tree),
        "max_child_rss_kb": max((_rss_kb(p) for p in missions), default=0),
        "max_child_fds": max((_fds(p) for p in missions), default=0),
    }


# ------------------------------------------------------------------ following a trace
class Follow:
    """The whole lines appended to a file so far, read as they come (the writer flushes each)."""

    def __init__(self, path: Path) -> None:
        self.path, self.offset, self.plans, self.replans, self.actions = path, 0, 0, 0, 0

    def poll(self) -> None:
        with contextlib.suppress(OSError):
            with open(self.path, "rb") as f:
                f.seek(self.offset)
                data = f.read()
            whole = data[: data.rfind(b"\n") + 1]
            self.offset += len(whole)
            for line in whole.splitlines():
                with contextlib.suppress(ValueError):
                    e = json.loads(line)
                    if e.get("kind") == "plan":
                        self.plans += 1
                        self.replans = max(self.replans, e.get("replan") or 0)
                    elif e.get("kind") == "action":
                        self.actions += 1


# ------------------------------------------------------------------ mission
def soak_mission(args, out: Path) -> int:
    trace = out / f"soak-mission-s{args.seed}.jsonl"
    cmd = [sys.executable, "-m", "tidyplan", "run", str(args.room), "--world", "symbolic"]
    cmd += ["--seed", str(args.seed), "--trace", str(trace), "--quiet", "--json"]
    print("$ " + " ".join(cmd[2:]).replace("-m tidyplan", "tidyplan"), flush=True)
    follow = Follow(trace)
    t0 = time.monotonic()
    with open(out / "mission.out", "w+b") as output:
        child = subprocess.Popen(cmd, stdout=output, stderr=subprocess.STDOUT)
        rows = _watch(child, args.every, t0, follow)
        output.seek(0)
        text = output.read().decode("utf-8", "replace").strip()
    follow.poll()
    last = text.splitlines()[-1] if text else ""
    summary = {}
    with contextlib.suppress(ValueError):
        summary = json.loads(last)
    print(f"\n{'t_s':>7} {'plans':>5} {'replan':>6} {'actions':>7} {'rss_MB':>7} {'fds':>4} {'children':>8}")
    for r in rows:
        print(
            f"{r['t']:7.1f} {r['plans']:5d} {r['replan']:6d} {r['actions']:7d} "
            f"{r['rss_kb'] / 1024:7.1f} {r['fds']:4d} {r['children']:8d}"
        )
    print(f"\nexit status {child.returncode}, {time.monotonic() - t0:.0f} s wall")
    if summary:
        print(
            f"mission: {summary.get('reason')}; delivered {summary.get('delivered')}/"
            f"{summary.get('objects')}, {summary.get('replans')} replans, {summary.get('actions')} actions"
        )
    else:
        print("mission output: " + " | ".join(text.splitlines()[-3:]))
    alive = [r for r in rows if r["rss_kb"]]
    after = next((r for r in alive if r["replan"] >= 1), None)
    if alive and after:
        end = alive[-1]
        ratio = end["rss_kb"] / after["rss_kb"]
        print(
            f"RSS after the first replan {after['rss_kb'] / 1024:.1f} MB (t {after['t']:.1f} s), "
            f"at the end {end['rss_kb'] / 1024:.1f} MB (t {end['t']:.1f} s): ratio {ratio:.3f}, "
            f"max {max(r['rss_kb'] for r in alive) / 1024:.1f} MB"
        )
    # "first": once the first plan is made (the planner stack loaded), not the interpreter's start
    _firsts([r for r in alive if r["plans"]], ("fds", "children"))
    return 0 if child.returncode in (0, 1) else 1


def _watch(child: subprocess.Popen, every: float, t0: float, follow: Follow | None) -> list[dict]:
    rows = []
    while True:
        s = sample(child.pid)
        ended = child.poll() is not None
        if follow is not None:
            follow.poll()
            s |= {"plans": follow.plans, "replan": follow.replans, "actions": follow.actions}
        s["t"] = time.monotonic() - t0
        if not ended:
            rows.append(s)
        else:
            return rows
        with contextlib.suppress(subprocess.TimeoutExpired):
            child.wait(timeout=every)  # wakes at once when it ends, else samples again


def _firsts(rows: list[dict], keys) -> None:
    for key in keys:
        values = [r[key] for r in rows]
        if values:
            print(f"{key}: first {values[0]}, last {values[-1]}, max {max(values)}")


# ------------------------------------------------------------------ sweep
def soak_sweep(args, out: Path) -> int:
    table = out / "sweep"
    cmd = [sys.executable, "-m", "tidyplan", "sweep", *args.scenarios, "--seeds", args.seeds]
    cmd += ["--world", "symbolic", "--faults", args.faults, "--jobs", str(args.jobs)]
    cmd += ["--out", str(table), "--quiet"]
    print("$ " + " ".join(cmd[2:]).replace("-m tidyplan", "tidyplan"), flush=True)
    t0 = time.monotonic()
    with open(out / "sweep.out", "w+b") as output:
        child = subprocess.Popen(cmd, stdout=output, stderr=subprocess.STDOUT)
        rows = []
        while child.poll() is None:
            s = sample(child.pid) | {"t": time.monotonic() - t0, "rows": _count(table / "results.jsonl")}
            rows.append(s)
            with contextlib.suppress(subprocess.TimeoutExpired):
                child.wait(timeout=args.every)
        output.seek(0)
        text = output.read().decode("utf-8", "replace").strip()
    wall = time.monotonic() - t0
    step = max(1, len(rows) // 40)  # about 40 lines of the series, and the last
    print(
        f"\n{'t_s':>7} {'rows':>5} {'drv_MB':>7} {'drv_fds':>7} {'children':>8} {'missions':>8} "
        f"{'tree_MB':>8} {'max_mission_MB':>14} {'max_mission_fds':>15}"
    )
    for r in [*rows[::step], *rows[-1:]] if rows else []:
        print(
            f"{r['t']:7.1f} {r['rows']:5d} {r['rss_kb'] / 1024:7.1f} {r['fds']:7d} {r['children']:8d} "
            f"{r['direct']:8d} {r['tree_rss_kb'] / 1024:8.1f} {r['max_child_rss_kb'] / 1024:14.1f} "
            f"{r['max_child_fds']:15d}"
        )
    print(f"\nexit status {child.returncode}, {wall:.0f} s wall")
    if child.returncode:
        print("sweep output: " + " | ".join(text.splitlines()[-5:]))
    results = []
    with contextlib.suppress(OSError):
        results = [json.loads(line) for line in (table / "results.jsonl").read_text().splitlines() if line]
    statuses = Counter(r.get("status") for r in results)
    print(f"rows {len(results)}: " + ", ".join(f"{k} {v}" for k, v in sorted(statuses.items())))
    done = [r for r in results if r.get("status") == "done"]
    if done:
        print(
            f"missions done: {sum(bool(r.get('success')) for r in done)} succeeded; "
            f"wall per mission median {sorted(r.get('wall_time_s', 0) for r in done)[len(done) // 2]:.1f} s"
        )
    for r in results:
        if r.get("status") == "crashed":
            print(f"  crashed: {r.get('scenario_file')} seed {r.get('seed')}: {r.get('error')}")
    if rows:
        first_rss = next((r["rss_kb"] for r in rows if r["rows"] >= 1), rows[0]["rss_kb"])
        print(
            f"driver RSS after the first row {first_rss / 1024:.1f} MB, at the end "
            f"{rows[-1]['rss_kb'] / 1024:.1f} MB (ratio {rows[-1]['rss_kb'] / first_rss:.3f}), "
            f"max {max(r['rss_kb'] for r in rows) / 1024:.1f} MB; a mission's RSS at most "
            f"{max(r['max_child_rss_kb'] for r in rows) / 1024:.1f} MB"
        )
        # "first": once the first mission has ended (the pool is full and one row written)
        _firsts([r for r in rows if r["rows"]], ("fds", "children", "direct", "max_child_fds"))
    return 0 if child.returncode == 0 and not statuses.get("crashed") else 1


def _count(path: Path) -> int:
    try:
        with open(path, "rb") as f:
            return f.read().count(b"\n")
    except OSError:
        return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, help="folder for traces and the table (default: a new temporary one)")
    ap.add_argument("--every", type=float, default=1.0, metavar="SECONDS", help="sampling interval")
    sub = ap.add_subparsers(dest="what", required=True)
    mi = sub.add_parser("mission", help="one long symbolic mission")
    mi.add_argument("room", type=Path)
    mi.add_argument("--seed", type=int, default=0)
    sw = sub.add_parser("sweep", help="a long symbolic sweep with faults")
    sw.add_argument("scenarios", nargs="+")
    sw.add_argument("--seeds", default="0-199")
    sw.add_argument("--jobs", type=int, default=2)
    sw.add_argument("--faults", default=HEAVY)
    args = ap.parse_args(argv)
    out = args.out or Path(tempfile.mkdtemp(prefix="tidyplan-soak-"))
    out.mkdir(parents=True, exist_ok=True)
    print(f"soak: output under {out}")
    return soak_mission(args, out) if args.what == "mission" else soak_sweep(args, out)


if __name__ == "__main__":
    sys.exit(main())
