"""Missions under faults: how many tidy everything, lose nothing, and do not crash.

    python bench/recovery.py [--seeds 20] [--faults grasp_drop=0.2,perception_miss=0.2,perception_false=0.05]
                             [--cases case1,case2,case3] [--jobs 2] [--out DIR]

Runs O-FSM in the symbolic world on each case for each seed, with the faults given (the
issue's default set), each mission in its own process (``--jobs`` at a time). Prints one line
per mission, then per case and overall: share of missions that tidied all objects, missions
that lost an object (``lost_objects`` > 0), crashes (a mission that raised), and the means of
replans, recoveries, simulated time and distance. Traces go to ``--out`` (a temporary folder by
default). Exit status 0 when every figure meets the goal (>= 95 % tidied, 0 lost, 0 crashes).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import traceback
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_FAULTS = "grasp_drop=0.2,perception_miss=0.2,perception_false=0.05"


def mission(job: tuple[str, int, str, str, float]) -> dict:
    case, seed, faults, out, budget = job
    from tidyplan.cli_run import parse_faults
    from tidyplan.mission import Settings, run

    trace = Path(out) / f"{case}-s{seed}.jsonl"
    try:
        settings = Settings("ofsm", seed, rates=parse_faults(faults), time_budget=budget)
        s = run(ROOT / "problems" / f"{case}.toml", trace, settings)
        return {"case": case, "seed": seed, "crash": None, **s}
    except Exception:  # noqa: BLE001 - a crash is a figure this benchmark reports
        return {"case": case, "seed": seed, "crash": traceback.format_exc(limit=3)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--faults", default=DEFAULT_FAULTS)
    ap.add_argument("--cases", default="case1,case2,case3")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--time-budget", type=float, default=1.0)
    ap.add_argument("--out", default=None, help="folder for the traces (default: a temporary one)")
    args = ap.parse_args()
    out = Path(args.out or tempfile.mkdtemp(prefix="tidyplan-recovery-"))
    out.mkdir(parents=True, exist_ok=True)
    cases = args.cases.split(",")
    jobs = [
        (c, s, args.faults, str(out), args.time_budget)
        for c in cases
        for s in range(args.first_seed, args.first_seed + args.seeds)
    ]
    print(f"faults {args.faults}; {len(jobs)} missions; traces in {out}", flush=True)
    results = []
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        for r in pool.map(mission, jobs):
            results.append(r)
            if r["crash"]:
                print(
                    f"{r['case']} seed {r['seed']:2d}: CRASH {r['crash'].strip().splitlines()[-1]}",
                    flush=True,
                )
            else:
                print(
                    f"{r['case']} seed {r['seed']:2d}: {'tidied' if r['success'] else 'FAILED'} "
                    f"{r['delivered']}/{r['objects']}, lost {r['lost_objects']}, replans {r['replans']}, "
                    f"recoveries {r['recoveries']}, {r['sim_time_s']:.0f} s, {r['distance_m']:.1f} m"
                    + ("" if r["success"] else f" ({r['reason']})"),
                    flush=True,
                )
    print()
    print(
        f"{'case':8} {'missions':>8} {'tidied all':>11} {'lost':>5} {'crashes':>8} "
        f"{'replans':>8} {'recoveries':>11} {'sim time':>9} {'distance':>9}"
    )
    ok = True
    for case in cases + ["all"]:
        rs = [r for r in results if case == "all" or r["case"] == case]
        done = [r for r in rs if not r["crash"]]
        tidied = sum(r["success"] for r in done)
        lost = sum(r["lost_objects"] > 0 for r in done)
        crashes = len(rs) - len(done)
        share = tidied / len(rs)
        ok &= case != "all" or (share >= 0.95 and lost == 0 and crashes == 0)

        def mean(key, done=done):
            return statistics.mean(r[key] for r in done) if done else float("nan")

        print(
            f"{case:8} {len(rs):8d} {tidied:5d} ({share:4.0%}) {lost:5d} {crashes:8d} {mean('replans'):8.1f} "
            f"{mean('recoveries'):11.1f} {mean('sim_time_s'):7.0f} s {mean('distance_m'):7.1f} m"
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
