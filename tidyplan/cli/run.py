"""`tidyplan run` and `tidyplan reproduce`: missions from scenario files, and the papers' tables.

Kept apart from cli.py (check/plan/compile) so each stays small; cli.py registers both.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

from tidyplan.errors import InternalError, TidyplanError
from tidyplan.loop.options import AFTER_LIMIT, DEFAULTS  # plain values: no planner stack
from tidyplan.loop.scenarios import DEFAULT_SCENARIO, load_scenario, project_file
from tidyplan.planning.strata import STRATEGIES
from tidyplan.trace.events import delivers
from tidyplan.trace.score import TIME_LIMIT_S
from tidyplan.worlds.rates import FAULTS
from tidyplan.worlds.registry import WORLDS

CASES = {"I": "case1.toml", "II": "case2.toml", "III": "case3.toml"}
# Yan et al., Table II: uses of P1, P2, P3 and total actions per case (O-FSM scenario planning)
TABLE2 = {"I": (12, 0, 0, 36), "II": (10, 1, 1, 45), "III": (11, 0, 1, 52)}
# Yan et al., Table III: simulation time (s) and distance (m) per case; greedy fails II and III
TABLE3 = {"I": (661, 56.87), "II": (822, 80.69), "III": (919, 91.36)}
TABLE3_GREEDY = {"I": (661, 56.87), "II": None, "III": None}


def add_parsers(sub, positive) -> None:
    r = sub.add_parser("run", help="run a monitored tidy-up mission and write its trace")
    r.add_argument(
        "scenario",
        nargs="?",
        help=f"scenario file or a shipped one's name, e.g. case1 (default: {DEFAULT_SCENARIO})",
    )
    r.add_argument(
        "--world",
        choices=tuple(WORLDS),
        default=DEFAULTS.world,
        help="pybullet (default): the HSR in the physics world, headless unless --gui; "
        "symbolic: the fast world with a hidden truth",
    )
    r.add_argument(
        "--strategy",
        choices=sorted(STRATEGIES),
        default=DEFAULTS.strategy,
        help="ofsm: strata P1, P2, P3; greedy: P1 only",
    )
    r.add_argument("--seed", type=int, default=DEFAULTS.seed)
    r.add_argument(
        "--domain",
        metavar="FILE",
        help="the domain to plan and act with (default: the shipped tidy.pddl); every action must "
        "name its behaviour units (:units), checked before the world starts",
    )
    r.add_argument(
        "--planner",
        default=DEFAULTS.planner,
        help="engine: lama (default, anytime), lama-optimal (LAMA beside a cost-optimal search), "
        "lama-first or optimal (deterministic), or any unified-planning engine name",
    )
    r.add_argument("--faults", default="", metavar="K=V,...", help="fault rates: " + ", ".join(FAULTS))
    r.add_argument("--trace", metavar="FILE", help="trace file to write (default: runs/<scenario>-...)")
    r.add_argument(
        "--time-budget",
        type=positive,
        default=DEFAULTS.time_budget,
        metavar="SECONDS",
        help="seconds the anytime planner improves each (re)plan's first plan, at most "
        f"(default {DEFAULTS.time_budget:g})",
    )
    r.add_argument(
        "--patience",
        type=_seconds,
        default=DEFAULTS.patience,
        metavar="SECONDS",
        help="end the improvement once no cheaper plan came for this long "
        f"(default {DEFAULTS.patience:g}; 0: improve for the whole budget; docs/planner.md)",
    )
    r.add_argument(
        "--first-plan-limit",
        type=positive,
        default=DEFAULTS.first_plan_limit,
        metavar="SECONDS",
        help="seconds to find a first plan, per (re)plan; past it the replan is 'not found in time' "
        f"(default {DEFAULTS.first_plan_limit:g})",
    )
    r.add_argument(
        "--min-probability",
        type=positive,
        default=DEFAULTS.min_probability,
        metavar="P",
        help="adopt a plan only when what it commits to next (its steps up to the first delivery) "
        "succeeds with probability P or more; under it the goal is narrowed "
        f"(default {DEFAULTS.min_probability:g})",
    )
    r.add_argument(
        "--max-recovery",
        type=int,
        default=DEFAULTS.max_recovery,
        metavar="N",
        help="recovery iterations for one failing behaviour unit before the planner replans "
        f"(default {DEFAULTS.max_recovery})",
    )
    r.add_argument(
        "--time-limit",
        type=positive,
        default=None,
        metavar="SECONDS",
        help="simulated seconds the WRS referee allows: the score counts what is put away within "
        "them and the robot plans for the most score in them (default: the scenario's time_limit_s, "
        f"900 for wrs-task1; where it gives none, {TIME_LIMIT_S:g} for the score alone)",
    )
    r.add_argument(
        "--after-limit",
        choices=AFTER_LIMIT,
        default=DEFAULTS.after_limit,
        help="once the time limit has passed: go on tidying everything, or stop the mission "
        f"(default {DEFAULTS.after_limit})",
    )
    r.add_argument("--gui", action="store_true", help="open the pybullet window (pybullet world only)")
    r.add_argument("--json", action="store_true", help="print the summary as one JSON object, last")
    r.add_argument("--quiet", action="store_true", help="no progress lines")

    rp = sub.add_parser("reproduce", help="regenerate a table of the O-FSM paper from our own runs")
    rp.add_argument(
        "table",
        choices=("table2", "table3"),
        help="table2: plan uses per case (symbolic world); table3: time and distance (pybullet)",
    )
    rp.add_argument("--seed", type=int, default=DEFAULTS.seed)
    rp.add_argument("--time-budget", type=positive, default=DEFAULTS.time_budget, metavar="SECONDS")
    rp.add_argument("--out", default="runs", metavar="DIR", help="folder for the traces (default runs/)")
    rp.add_argument("--json", action="store_true")


def _seconds(text: str) -> float:
    """A number of seconds, 0 allowed (`--patience 0`: improve for the whole budget)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0 <= value < math.inf:
        raise argparse.ArgumentTypeError(f"must be a number of seconds >= 0: {text!r}")
    return value


def _trace_path(folder: Path, stem: str) -> Path:
    """A fresh file name: runs are never overwritten. The folder is made with the trace (not
    here: input refused before the mission must leave nothing behind)."""
    base = f"{stem}-{time.strftime('%Y%m%d-%H%M%S')}"
    path, n = folder / f"{base}.jsonl", 1
    while path.exists() or path.with_suffix(".pddl").exists():
        n += 1
        path = folder / f"{base}-{n}.jsonl"
    return path


def cmd_run(args) -> int:
    from tidyplan.library import run  # the planner stack loads only when needed

    scenario = load_scenario(args.scenario or DEFAULT_SCENARIO)
    trace = (
        Path(args.trace)
        if args.trace
        else _trace_path(Path("runs"), f"{scenario.name}-{args.strategy}-s{args.seed}")
    )
    show = None if args.quiet else _progress(len(scenario.items))
    try:
        summary = run(
            scenario,
            world=args.world,
            seed=args.seed,
            strategy=args.strategy,
            planner=args.planner,
            faults=args.faults,
            time_budget=args.time_budget,
            patience=args.patience,
            first_plan_limit=args.first_plan_limit,
            min_probability=args.min_probability,
            max_recovery=args.max_recovery,
            time_limit=args.time_limit,
            after_limit=args.after_limit,
            domain=args.domain,
            trace=trace,
            gui=args.gui,
            on_event=show,
            options="cli",
        ).as_dict()
    except TidyplanError:
        raise
    except Exception as e:  # a bug of ours: one line naming the trace (kept), the traceback beside it
        what = f"{type(e).__name__}: {e}".splitlines()[0][:300]
        kept = str(trace) if trace.exists() else None
        raise InternalError(what, kept, _save_traceback(trace) if kept else None) from e
    if args.json:
        print(json.dumps(summary))
    else:
        _print_summary(summary)
    return 0 if summary["success"] else 1


def _save_traceback(trace: Path) -> str | None:
    """The traceback of the exception being handled, in a file beside the trace (never over one)."""
    import traceback

    path = trace.with_suffix(".traceback.txt")
    try:
        with open(path, "x", encoding="utf-8") as f:
            f.write(traceback.format_exc())
    except OSError:
        return None
    return str(path)


def _progress(total: int):
    tidied = [0]

    def show(e: dict) -> None:
        if e["kind"] == "plan":
            p = e["probability"]
            print(
                f"[{e['sim_s']:7.1f} s] plan {e['replan']} ({e['cause']}): {e['status']}"
                + (f", P{e['stratum']}, {len(e['plan'])} steps, p {p:.3g}" if p is not None else "")
                + f", {e['planning_time_s']:.2f} s",
                file=sys.stderr,
            )
        elif e["kind"] == "action" and delivers(e):
            tidied[0] += 1
            print(f"[{e['sim_s']:7.1f} s] tidied {tidied[0]}/{total}: {e['action']}", file=sys.stderr)
        elif e["kind"] == "recovery":
            then = ", ".join(e["then"] or [])
            print(
                f"[{e['sim_s']:7.1f} s]   recovery {e['attempt']}: {e['unit']} {e['failure']} "
                f"({e['failure_class']}) -> {e['layer']}" + (f": {then}" if then else ""),
                file=sys.stderr,
            )
        elif e["kind"] == "end":
            print(f"[{e['sim_s']:7.1f} s] end: {e['reason']}", file=sys.stderr)

    return show


def _print_summary(s: dict) -> None:
    strata = ", ".join(f"{k} {v}" for k, v in s["strata"].items())
    if s.get("strata_unproven"):
        strata += f" ({s['strata_unproven']} with a lower stratum out of time, not proven empty)"
    causes = ", ".join(f"{k} {v}" for k, v in s["replan_causes"].items()) or "none"
    print(
        f"{s['scenario']} ({s['strategy']}, seed {s['seed']}): "
        f"{'success' if s['success'] else 'FAILED'}: {s['reason']}"
    )
    print(
        f"delivered {s['delivered']}/{s['objects']}, lost {s['lost_objects']}; "
        f"{s['actions']} actions ({s['paper_actions']} counted as Yan et al. do); plans by stratum: {strata}"
    )
    if s.get("given_up"):  # the belief's account beside the room's: a mismatch is said, not scored
        left = len(s.get("untidied") or [])
        print(f"the belief gave up on {' '.join(s['given_up'])}; the room has {left} objects untidied")
    print(f"replans {s['replans']} ({causes}); kept {s['replans_avoided']} plans that stayed valid")
    print(
        f"distance {s['distance_m']} m, simulated time {s['sim_time_s']} s, wall time {s['wall_time_s']} s, "
        f"replanning median {s['replan_time_s']['median']} s, max {s['replan_time_s']['max']} s"
    )
    print(f"WRS score {s['wrs_score']:g} (time limit {s['time_limit_s']:g} s simulated)")
    print(f"trace {s['trace']}")


def cmd_reproduce(args) -> int:
    from tidyplan.sweep.grid import grid, run_sweep

    world = "pybullet" if args.table == "table3" else "symbolic"
    files = {case: str(project_file(f"problems/{file}")) for case, file in CASES.items()}
    for path in files.values():
        load_scenario(path)  # one message for a scenario that does not load
    configs = grid(list(files.values()), [args.seed], ["ofsm", "greedy"], [""], [DEFAULTS.planner], world)
    configs = [replace(c, time_budget=args.time_budget) for c in configs]
    case_of = {str(Path(f).resolve()): case for case, f in files.items()}

    def show(row: dict) -> None:
        print(
            f"case {case_of[row['scenario_file']]}, {row['strategy']} ({world}): {row['status']}",
            file=sys.stderr,
        )

    # tidyplan sweep's engine, one mission at a time (Table III prints wall times), each in a
    # process of its own; a fresh sweep folder per call: a reproduction runs every mission anew
    folder = _trace_path(Path(args.out), f"{args.table}-s{args.seed}").with_suffix("")
    found = run_sweep(configs, folder, jobs=1, on_row=show)
    failed = [r for r in found if r["status"] != "done"]
    for r in failed:
        what = f"{Path(r['scenario_file']).stem} {r['strategy']}: the mission {r['status']}"
        print(f"tidyplan: {what}: {r['error']}", file=sys.stderr)
    if failed:
        return 1
    by = {(case_of[r["scenario_file"]], r["strategy"]): r for r in found}
    rows = [(case, {s: by[case, s] for s in ("ofsm", "greedy")}) for case in CASES]
    if args.json:
        print(json.dumps([{"case": c, **o} for c, o in rows]))
    elif args.table == "table3":
        _print_table3(rows, args.seed)
    else:
        _print_table2(rows, args.seed)
    return 0 if all(o["ofsm"]["success"] for _, o in rows) else 1


def _print_table2(rows, seed: int) -> None:
    print(f"Table II (Yan et al.), O-FSM scenario planning: paper | ours (symbolic world, seed {seed})")
    print(
        f"{'case':5} {'P1':>9} {'P2':>9} {'P3':>9} {'actions':>11} {'ours: all actions':>18} "
        f"{'replans':>8} {'tidied':>7} {'greedy':>12}"
    )
    for case, o in rows:
        s, g = o["ofsm"], o["greedy"]
        p1, p2, p3, total = TABLE2[case]
        st = s["strata"]
        greedy = "tidies all" if g["success"] else f"fails {g['delivered']}/{g['objects']}"
        print(
            f"{case:5} {p1:>4} | {st['P1']:<2} {p2:>4} | {st['P2']:<2} {p3:>4} | {st['P3']:<2} "
            f"{total:>5} | {s['paper_actions']:<3} {s['actions']:>18} {s['replans']:>8} "
            f"{s['delivered']:>4}/{s['objects']:<2} {greedy:>12}"
        )
    unproven = {case: o["ofsm"].get("strata_unproven", 0) for case, o in rows}
    if any(unproven.values()):
        print(
            "deliveries whose stratum was reached with a lower one out of time (not proven to have "
            "no plan), counted above too: " + ", ".join(f"{c} {n}" for c, n in unproven.items() if n)
        )
    print(
        "actions: Yan et al.'s count (take_object includes the approach; P1 = 3, P2 = 4, P3 = 4 per "
        "object moved aside + 3); 'all actions' counts every executed action, moves to objects included."
    )


def _print_table3(rows, seed: int) -> None:
    print(f"Table III (Yan et al.), simulation: paper | ours (pybullet HSR, seed {seed})")
    print(
        f"{'case':5} {'method':7} {'time (s)':>17} {'distance (m)':>19} {'tidied':>8} {'lost':>5} "
        f"{'replans':>8} {'wall (s)':>9}"
    )
    for case, o in rows:
        for strategy, paper in (("ofsm", TABLE3[case]), ("greedy", TABLE3_GREEDY[case])):
            r = o[strategy]
            if paper is None:
                t_paper, d_paper = "fails", "fails"
            else:
                t_paper, d_paper = f"{paper[0]}", f"{paper[1]:.2f}"
            ours_t = f"{r['sim_time_s']:.0f}" if r["success"] else "fails"
            ours_d = f"{r['distance_m']:.2f}" if r["success"] else "fails"
            print(
                f"{case:5} {strategy:7} {t_paper:>7} | {ours_t:<7} {d_paper:>8} | {ours_d:<8} "
                f"{r['delivered']:>5}/{r['objects']:<2} {r['lost_objects']:>5} {r['replans']:>8} "
                f"{r['wall_time_s']:>9.1f}"
            )
    print("ours: simulated time and distance of the run; 'fails' where not every object was tidied.")
