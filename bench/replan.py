"""A replan in the loop, phase by phase, beside Fast Downward's own driver on the same problem.

    python bench/replan.py [--sizes 12,48,96] [--replans 8] [--seed 0] [--planner lama-first]
                           [--time-budget 1] [--out DIR]

For each size, a symbolic mission (12: problems/case3.toml; 48 and 96: bench/wrs.py's two-room
layout, seed 0, 6 and 12 objects of each category in each room) runs until it has made
`--replans` plans (then it is stopped: its trace stays readable). Each `plan` event carries the
replan's phases (tidyplan/loop/replanning.py): the map's facts, building and checking the
problem, compiling it, grounding it (the SAS task), the search, the commitment check. The same
replan's problem, as the trace saved it in plain PDDL, is then given to Fast Downward's driver
(`fast-downward.py --alias lama-first domain problem`, the whole process timed), and the ratio
in-loop / driver printed per replan and as medians. With `--planner lama-first` both run the same
search, so the ratio is what the loop adds or saves around it.

Traces go under DIR (default: a new temporary folder), never over an existing file.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

PHASES = ("map_facts", "problem", "compile", "ground", "sas", "translate", "search", "commitment")
DRIVER = None  # Fast Downward's driver script, found on first use


class _Enough(Exception):
    """Raised from the trace listener once the mission has made its plans."""


def _scenario(size: int, out: Path) -> Path:
    if size == 12:
        return ROOT / "problems" / "case3.toml"
    import wrs

    if size % 8:
        raise SystemExit(
            f"replan.py: --sizes: {size} is not 12 or a multiple of 8 (two rooms, four categories)"
        )
    path = out / f"wrs-two-n{size}.toml"
    if not path.exists():
        wrs.main(["--layout", "two", "--rooms", "1", "--per-room", str(size // 8), "--out", str(out)])
        made = sorted(out.glob(f"wrs-two-s000*n{size}*.toml")) or sorted(out.glob("wrs-two-s000*.toml"))
        made[-1].rename(path)
    return path


def first_plans(
    scenario: Path, trace: Path, planner: str, seed: int, replans: int, budget: float
) -> list[dict]:
    """The `plan` events of a symbolic mission, stopped once it has made `replans` of them."""
    from tidyplan.loop.mission import run
    from tidyplan.loop.options import Settings

    made = []

    def listen(event: dict) -> None:
        if event.get("kind") == "plan":
            made.append(event)
            if len(made) >= replans:
                raise _Enough

    try:
        settings = Settings(seed=seed, world="symbolic", planner=planner, time_budget=budget)
        run(str(scenario), trace, settings, on_event=listen)
    except _Enough:
        pass
    return made


def _driver(domain: str, problem: str) -> float:
    global DRIVER
    if DRIVER is None:
        import importlib.util

        spec = importlib.util.find_spec("up_fast_downward")
        DRIVER = Path(next(iter(spec.submodule_search_locations))) / "downward" / "fast-downward.py"
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        cmd = [sys.executable, str(DRIVER), "--alias", "lama-first", domain, problem]
        done = subprocess.run(cmd, cwd=tmp, capture_output=True, text=True)
        seconds = time.perf_counter() - start
    if done.returncode != 0:
        return float("nan")
    return seconds


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="12,48,96")
    ap.add_argument("--replans", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--planner", default="lama-first")
    ap.add_argument("--time-budget", type=float, default=1.0, help="improvement seconds (anytime planners)")
    ap.add_argument("--out", default=None, metavar="DIR")
    args = ap.parse_args()
    try:
        sizes = [int(x) for x in args.sizes.split(",")]
    except ValueError:
        ap.exit(2, f"replan.py: --sizes: {args.sizes!r} is not a list of numbers\n")
    if not args.time_budget > 0:
        ap.exit(2, "replan.py: --time-budget must be a positive number of seconds\n")
    if args.replans < 1:
        ap.exit(2, "replan.py: --replans must be at least 1\n")
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="tidyplan-replan-"))
    out.mkdir(parents=True, exist_ok=True)
    print(f"traces under {out}; planner {args.planner} (budget {args.time_budget:g} s), seed {args.seed}")
    header = " ".join(f"{p[:9]:>9s}" for p in PHASES)
    summary = []
    for size in sizes:
        scenario = _scenario(size, out)
        trace = out / f"n{size}-s{args.seed}-{args.planner}.jsonl"
        if trace.exists():
            ap.exit(2, f"replan.py: {trace} exists; choose another --out\n")
        plans = first_plans(scenario, trace, args.planner, args.seed, args.replans, args.time_budget)
        print(f"\n{size} objects ({scenario.name}): {len(plans)} replans")
        print(f"  {'replan':>6s} {header} {'in-loop':>8s} {'driver':>8s} {'ratio':>6s}")
        ratios, loops, drivers = [], [], []
        for e in plans:
            phases = e.get("phases", {})
            loop = e["planning_time_s"]
            plain_domain, plain_problem = e.get("plain_domain"), e.get("plain_problem")
            if not plain_domain or e["status"] != "solved":
                continue
            driver = _driver(str(trace.parent / plain_domain), str(trace.parent / plain_problem))
            ratio = loop / driver
            ratios.append(ratio)
            loops.append(loop)
            drivers.append(driver)
            cells = " ".join(f"{phases.get(p, 0.0):9.3f}" for p in PHASES)
            print(f"  {e['replan']:6d} {cells} {loop:8.3f} {driver:8.3f} {ratio:6.2f}")
        if ratios:
            medians = " ".join(
                f"{statistics.median(e.get('phases', {}).get(p, 0.0) for e in plans):9.3f}" for p in PHASES
            )
            loop, driver = statistics.median(loops), statistics.median(drivers)
            ratio = statistics.median(ratios)
            worst = max(ratios)
            print(
                f"  {'median':>6s} {medians} {loop:8.3f} {driver:8.3f} {ratio:6.2f} (max ratio {worst:.2f})"
            )
            summary.append(
                (size, statistics.median(loops), statistics.median(drivers), statistics.median(ratios))
            )
    print("\nsize  median in-loop  median driver  median ratio")
    for size, loop, driver, ratio in summary:
        print(f"{size:4d}  {loop:14.3f}  {driver:13.3f}  {ratio:12.2f}")
    print(
        json.dumps(
            {"sizes": [{"objects": s, "in_loop_s": x, "driver_s": d, "ratio": r} for s, x, d, r in summary]}
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
