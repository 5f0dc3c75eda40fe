"""`tidyplan sweep`: a grid of missions on this machine's cores or on Ray, one resumable table,
a summary by condition (docs/sweep.md). The grid and table are in ``tidyplan.sweep.grid``, the
engines in ``tidyplan.sweep.missions``, the summary in ``tidyplan.sweep.report``."""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

from tidyplan.errors import InputError
from tidyplan.loop.options import AFTER_LIMIT, DEFAULTS, OptionError, cli_spelling
from tidyplan.loop.scenarios import load_scenario, scenario_path
from tidyplan.worlds.registry import WORLDS


def add_parser(sub, positive) -> None:
    s = sub.add_parser(
        "sweep",
        help="run a grid of missions (scenarios x seeds x strategies x faults x planners) into one table",
    )
    s.add_argument("scenarios", nargs="*", metavar="SCENARIO", help="scenario files (or case1, case2, ...)")
    s.add_argument("--seeds", metavar="A-B", help="seeds, A-B inclusive (or N, or a comma list)")
    s.add_argument(
        "--strategy",
        default=DEFAULTS.strategy,
        metavar="NAME,...",
        help=f"ofsm, greedy (default {DEFAULTS.strategy})",
    )
    s.add_argument(
        "--faults",
        default="",
        metavar="K=V,...;K=V,...",
        help="fault conditions, ';' between them (tidyplan run's --faults each; '' or none: the baseline)",
    )
    s.add_argument(
        "--planner",
        default=DEFAULTS.planner,
        metavar="NAME,...",
        help=f"planners (default {DEFAULTS.planner})",
    )
    s.add_argument("--world", choices=tuple(WORLDS), default=DEFAULTS.world)
    s.add_argument(
        "--time-limit",
        type=positive,
        default=DEFAULTS.time_limit,
        metavar="SECONDS",
        help="simulated seconds the WRS referee allows, for the score and the robot's plans "
        "(default: each scenario's time_limit_s; tidyplan run --time-limit)",
    )
    s.add_argument("--after-limit", choices=AFTER_LIMIT, default=DEFAULTS.after_limit)
    s.add_argument("--time-budget", type=positive, default=DEFAULTS.time_budget, metavar="SECONDS")
    s.add_argument(
        "--patience",
        type=float,
        default=DEFAULTS.patience,
        metavar="SECONDS",
        help=f"tidyplan run's --patience (default {DEFAULTS.patience:g}; 0: the whole budget)",
    )
    s.add_argument(
        "--mission-limit",
        type=positive,
        default=600.0,
        metavar="SECONDS",
        help="wall seconds one mission may take before it is killed and recorded as a timeout (default 600)",
    )
    s.add_argument("--out", metavar="DIR", help="the table's folder: results.jsonl, results.csv, traces/")
    s.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="missions at once (default: cores)")
    s.add_argument(
        "--ray",
        nargs="?",
        const="",
        default=None,
        metavar="ADDRESS",
        help="run on Ray: no ADDRESS, a Ray started on this machine; ADDRESS, an existing cluster",
    )
    s.add_argument("--report", metavar="DIR", help="print the summary of the table in DIR; run nothing")
    s.add_argument("--plot", metavar="FILE.png", help="draw the summary by condition")
    s.add_argument(
        "--by",
        metavar="FIELD,...",
        help="the fields that make a condition in the summary, the rest pooled (e.g. strategy,faults: "
        "over every scenario); default every one but the seed",
    )
    s.add_argument("--quiet", action="store_true", help="no progress bar")


def _scenario_file(text: str) -> str:
    load_scenario(text)  # InputError, with the file's messages, if it does not load
    return str(scenario_path(text).resolve())


def configs_from(args) -> list:
    from tidyplan.sweep.grid import canonical_faults, grid, parse_seeds

    if not args.scenarios:
        raise InputError("tidyplan sweep: give SCENARIO files (or --report DIR)")
    if args.seeds is None:
        raise InputError("--seeds: required (A-B)")
    if args.out is None:
        raise InputError("--out: required (the table's folder)")
    if args.jobs < 1:
        raise InputError(f"--jobs: {args.jobs} is not at least 1")
    strategies = _names(args.strategy, "--strategy")
    planners = _names(args.planner, "--planner")
    faults = list(dict.fromkeys(canonical_faults(f) for f in args.faults.split(";")))
    configs = grid(
        [_scenario_file(s) for s in args.scenarios],
        parse_seeds(args.seeds),
        strategies,
        faults,
        planners,
        args.world,
        time_limit=args.time_limit,
        after_limit=args.after_limit,
        time_budget=args.time_budget,
        patience=args.patience,
    )
    checked = set()
    for config in configs:  # each condition's options checked once, as a mission would
        if config.condition not in checked:
            checked.add(config.condition)
            try:
                config.settings()
            except OptionError as err:
                raise err.spelled(cli_spelling) from None
    return configs


def _names(text: str, option: str) -> list[str]:
    names = list(dict.fromkeys(n.strip() for n in text.split(",") if n.strip()))
    if not names:
        raise InputError(f"{option}: no name given")
    return names


def ray_missing() -> bool:
    return importlib.util.find_spec("ray") is None


def cmd_sweep(args) -> int:
    from tidyplan.sweep.grid import RESULTS, RESULTS_CSV, Table, run_sweep
    from tidyplan.sweep.missions import RAY_INSTALL
    from tidyplan.sweep.report import parse_by, plot, report_lines

    def warn(message: str) -> None:
        print(f"tidyplan: warning: {message}", file=sys.stderr)

    by = parse_by(args.by)  # checked before anything runs
    if args.report is not None:
        if args.scenarios:
            raise InputError("--report DIR: summarises a table; give no SCENARIO with it")
        if not (Path(args.report) / RESULTS).exists():
            raise InputError(f"--report: {Path(args.report) / RESULTS}: no such table")
        rows = Table(args.report, warn).rows
    else:
        configs = configs_from(args)
        if args.ray is not None and ray_missing():
            raise InputError(f"--ray: Ray is not installed; install the extra: {RAY_INSTALL}")
        rows = run_sweep(
            configs,
            args.out,
            jobs=args.jobs,
            ray=args.ray is not None,
            address=args.ray or None,
            limit=args.mission_limit,
            warn=warn,
            progress=not args.quiet,
        )
        print(f"table: {Path(args.out) / RESULTS} and {RESULTS_CSV}: {len(rows)} missions of this sweep")
    for line in report_lines(rows, by):
        print(line)
    if args.plot:
        plot(rows, args.plot, by)
        print(f"plot: {args.plot}")
    return 0 if all(r.get("status") == "done" for r in rows) else 1
