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
in a fresh process of its own (``--jobs`` at a time; ``tidyplan sweep``'s engine): a pybullet
server, a crash or a hang stays there. ``--out`` holds the sweep's table: run again, it skips
the missions already there.
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
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_FAULTS = "grasp_drop=0.2,perception_miss=0.2,perception_false=0.05"


def _row(r: dict) -> dict:
    """A sweep row as this benchmark reads it: its label, and a crash (a raise, a death or a
    hang past the sweep's mission limit) as the error's first line."""
    crash = None if r["status"] == "done" else f"{r['status']}: {r['error']}".split(" (")[0]
    return {**r, "case": Path(r["scenario_file"]).name.removesuffix(".toml"), "crash": crash}


def scenarios(ap: argparse.ArgumentParser, args: argparse.Namespace) -> dict[str, str]:
    """Label -> scenario file, each checked to load here, so a bad file is one message, not a
    crash per seed."""
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load

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
    from tidyplan.errors import InputError
    from tidyplan.sweep.grid import MissionConfig, canonical_faults

    try:
        canonical_faults(faults)
    except InputError as e:
        ap.error(str(e))
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs must be at least 1")
    files = scenarios(ap, args)
    out = Path(args.out or tempfile.mkdtemp(prefix="tidyplan-recovery-"))
    from tidyplan.planning.engines import MISSION_ENGINE
    from tidyplan.sweep.grid import grid, run_sweep

    configs = grid(
        list(files.values()),
        list(range(args.first_seed, args.first_seed + args.seeds)),
        ["ofsm"],
        [canonical_faults(faults)],
        [MISSION_ENGINE],
        args.world,
        time_budget=args.time_budget,
    )
    print(f"faults {faults or 'none'}; {len(configs)} missions; traces in {out}", flush=True)
    # tidyplan sweep's engine: a fresh process per mission; the table in --out, resumable.
    # Lines in the missions' order, each as soon as it and those before it have ended.
    order = {c.key: i for i, c in enumerate(configs)}
    ended: dict[int, dict] = {}
    shown = [0]

    def show(row: dict) -> None:
        ended[order[MissionConfig.from_row(row).key]] = _row(row)
        while shown[0] in ended:
            print(line(ended[shown[0]]), flush=True)
            shown[0] += 1

    rows = run_sweep(configs, out, jobs=args.jobs, on_row=show)
    results = [_row(r) for r in rows]
    for r in results[shown[0] :]:  # rows an earlier run of the same --out had already
        print(line(r), flush=True)
    print()
    return 0 if report(results, list(files)) else 1


if __name__ == "__main__":
    sys.exit(main())
