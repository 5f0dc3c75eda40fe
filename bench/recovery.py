"""Missions under faults: how many tidy everything, lose nothing, and do not crash.

    python bench/recovery.py [--seeds 20] [--faults grasp_drop=0.2,perception_miss=0.2,perception_false=0.05]
                             [--cases case1,case2,case3 | --scenarios FILE ...]
                             [--world symbolic|pybullet] [--jobs 2] [--out DIR]

Runs O-FSM on each scenario for each seed, in the symbolic world (default) or the pybullet one,
with the faults given (the issue's default set; ``--faults ""`` or ``none``: none injected, only
the world's baseline, as ``tidyplan run`` without ``--faults``: a grasp fails 5 %, a placement 2 %,
perception errs at the scenario's rates). The scenarios are the cases of
problems/ named by ``--cases``, or any scenario files given to ``--scenarios`` (the rooms
bench/wrs.py generates, say), each labelled by its file name without ``.toml``. Each mission runs
in a fresh process of its own (``--jobs`` at a time): a pybullet server or a crash stays there.
Prints one line per mission, then per scenario and overall: share of missions that tidied all
objects, missions that lost an object (``lost_objects`` > 0), crashes (a mission that raised),
and the means of replans, recoveries, simulated time and distance. Traces go to ``--out`` (a
temporary folder by default). Exit status 0 when every figure meets the goal (>= 95 % tidied,
0 lost, 0 crashes), 1 when one does not, 2 for bad options or a scenario that does not load.
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


def mission(job: tuple[str, str, int, str, str, str, float]) -> dict:
    label, path, seed, faults, world, out, budget = job
    from tidyplan.cli_run import parse_faults
    from tidyplan.mission import Settings, run

    trace = Path(out) / f"{label}-s{seed}.jsonl"
    try:
        settings = Settings("ofsm", seed, rates=parse_faults(faults), time_budget=budget, world=world)
        s = run(path, trace, settings)
        return {"case": label, "seed": seed, "crash": None, **s}
    except Exception:  # noqa: BLE001 - a crash is a figure this benchmark reports
        return {"case": label, "seed": seed, "crash": traceback.format_exc(limit=3)}


def scenarios(ap: argparse.ArgumentParser, args: argparse.Namespace) -> dict[str, str]:
    """Label -> scenario file, each checked to load here, so a bad file is one message, not a
    crash per seed."""
    from sim.scenario import ScenarioError
    from sim.scenario_file import load

    if args.scenarios:
        files = {Path(f).name.removesuffix(".toml"): str(Path(f).resolve()) for f in args.scenarios}
        if len(files) < len(args.scenarios):
            ap.error("--scenarios: two files have the same name; their traces would clash")
    else:
        files = {c: str(ROOT / "problems" / f"{c}.toml") for c in args.cases.split(",")}
    for path in files.values():
        try:
            load(path)
        except ScenarioError as e:
            ap.error(f"scenario does not load: {e.messages[0]}")
    return files


def report(results: list[dict], labels: list[str]) -> bool:
    """The table per scenario and overall; True when the overall figures meet the goal."""
    width = max([8, *map(len, labels)])
    print(
        f"{'case':{width}} {'missions':>8} {'tidied all':>11} {'lost':>5} {'crashes':>8} "
        f"{'replans':>8} {'recoveries':>11} {'sim time':>9} {'distance':>9}"
    )
    ok = True
    for case in labels + ["all"]:
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
            f"{case:{width}} {len(rs):8d} {tidied:5d} ({share:4.0%}) {lost:5d} {crashes:8d} "
            f"{mean('replans'):8.1f} {mean('recoveries'):11.1f} {mean('sim_time_s'):7.0f} s "
            f"{mean('distance_m'):7.1f} m"
        )
    return ok


def line(r: dict) -> str:
    if r["crash"]:
        return f"{r['case']} seed {r['seed']:2d}: CRASH {r['crash'].strip().splitlines()[-1]}"
    return (
        f"{r['case']} seed {r['seed']:2d}: {'tidied' if r['success'] else 'FAILED'} "
        f"{r['delivered']}/{r['objects']}, lost {r['lost_objects']}, replans {r['replans']}, "
        f"recoveries {r['recoveries']}, {r['sim_time_s']:.0f} s, {r['distance_m']:.1f} m"
        + ("" if r["success"] else f" ({r['reason']})")
    )


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--faults", default=DEFAULT_FAULTS, help='K=V,...; "" or none: no injected faults')
    which = ap.add_mutually_exclusive_group()
    which.add_argument("--cases", default="case1,case2,case3", help="cases of problems/ (the default)")
    which.add_argument("--scenarios", nargs="+", metavar="FILE", help="scenario files, instead of --cases")
    ap.add_argument("--world", choices=("symbolic", "pybullet"), default="symbolic")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--time-budget", type=float, default=1.0)
    ap.add_argument("--out", default=None, help="folder for the traces (default: a temporary one)")
    args = ap.parse_args()
    faults = "" if args.faults.strip().lower() == "none" else args.faults
    from tidyplan.cli_run import parse_faults
    from tidyplan.errors import InputError

    try:
        parse_faults(faults)
    except InputError as e:
        ap.error(str(e))
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs must be at least 1")
    files = scenarios(ap, args)
    out = Path(args.out or tempfile.mkdtemp(prefix="tidyplan-recovery-"))
    out.mkdir(parents=True, exist_ok=True)
    jobs = [
        (label, path, s, faults, args.world, str(out), args.time_budget)
        for label, path in files.items()
        for s in range(args.first_seed, args.first_seed + args.seeds)
    ]
    print(f"faults {faults or 'none'}; {len(jobs)} missions; traces in {out}", flush=True)
    results = []
    # one fresh process per mission (spawned: a worker is never reused, nothing is inherited)
    with ProcessPoolExecutor(max_workers=args.jobs, max_tasks_per_child=1) as pool:
        for r in pool.map(mission, jobs):
            results.append(r)
            print(line(r), flush=True)
    print()
    return 0 if report(results, list(files)) else 1


if __name__ == "__main__":
    sys.exit(main())
