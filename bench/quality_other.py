"""Plan cost against the optimum on 12-object tidy-ups in an encoding nobody tuned on (tidy-rooms.pddl).

    python bench/quality_other.py [--seeds 10] [--first-seed 0] [--items 12]
                                  [--planner lama-optimal] [--time-budget 1] [--optimum-limit 300]

Why: bench/plan_quality.py measures the planner on domains/tidy.pddl, the encoding the default
planner was chosen and tuned on (docs/planner.md). This bench asks whether that quality carries
over to another encoding of the same task: domains/tidy-rooms.pddl (other predicates, bins
instead of categories, every move open), on the same seeded rooms (bench/tidygen_rooms.py,
translated from bench/tidygen.py's).

Per seed: the optimum, by Fast Downward's uniform-cost search (``eager(single(g()))``, cost-
optimal) on the compiled task, the optimal plan's cost taken in the file's units (c(pi), the
same units as ``plan()``'s ``score.cost``); a seed whose optimal search does not end within
``--optimum-limit`` seconds is reported and left out of the ratio. Beside it tidygen's Held-Karp
optimum of the same room (the same cost model), as a check that shares no code with the planner.
Then ``plan()`` with ``--planner`` and ``--time-budget`` (the improvement time after the first
plan): its cost, cost / optimum and the planning time (the whole call). A summary ends the run.
Bad options exit 2 with one line.
"""

from __future__ import annotations

import argparse
import math
import statistics
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

import tidygen_rooms  # noqa: E402

from tidyplan.errors import PlannerError  # noqa: E402
from tidyplan.generate import tasks as tidygen  # noqa: E402
from tidyplan.pddl.compile import compile_task  # noqa: E402
from tidyplan.pddl.reader import read  # noqa: E402
from tidyplan.pddl.writer import domain_text, problem_text  # noqa: E402
from tidyplan.planning import fastdownward as fd  # noqa: E402
from tidyplan.planning.engines import OPTIMAL_RACER, check_name  # noqa: E402
from tidyplan.planning.planner import Status, plan  # noqa: E402

DOMAIN = ROOT / "domains" / "tidy-rooms.pddl"
GOOD = 1.05  # the bound on cost / optimum


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line, exit 2 (argparse's own prints the usage too)
        self.exit(2, f"{self.prog}: error: {message}\n")


def _count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, not {text!r}")
    return n


def _seconds(text: str) -> float:
    try:
        s = float(text)
    except ValueError:
        s = math.nan
    if not math.isfinite(s) or s < 0:
        raise argparse.ArgumentTypeError(f"must be a number of seconds >= 0, not {text!r}")
    return s


def optimum(domain, problem, limit: float) -> tuple[float | None, float, str]:
    """The optimal plan's c(pi) (None if the search did not end), the seconds it took (compile,
    translate, search), and how the search ended."""
    start = time.perf_counter()
    task = compile_task(domain, problem)
    sas = fd.sas_text(fd.translate(domain_text(task.domain), problem_text(task.problem)))
    search = fd.Search(("--search", OPTIMAL_RACER), anytime=False)
    result = fd.search(sas, [search], start + limit, 0.0)
    seconds = time.perf_counter() - start
    if result.ending is not fd.Ending.SOLVED or result.plan is None:
        return None, seconds, result.ending.value
    names = {n.lower(): n for n in task.info}
    cost = sum(task.step_cost(names[a[0]], a[1:]) for a in result.plan.actions)
    return cost, seconds, result.ending.value


def main() -> None:
    ap = _Parser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=_count, default=10, help="how many seeds (default 10)")
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--items", type=_count, default=12)
    ap.add_argument("--planner", default="lama-optimal", help="plan()'s planner (default lama-optimal)")
    ap.add_argument("--time-budget", type=_seconds, default=1.0, help="seconds of improvement (default 1)")
    ap.add_argument(
        "--optimum-limit", type=_seconds, default=300.0, help="seconds for the optimal search (default 300)"
    )
    args = ap.parse_args()
    try:
        check_name(args.planner)
    except PlannerError as e:
        ap.error(str(e))

    ratios: dict[int, float] = {}
    times, opt_times, skipped = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            path = Path(tmp) / f"tidy-rooms-{seed}.pddl"
            path.write_text(tidygen_rooms.generate(seed, args.items), encoding="utf-8")
            domain, problem = read(DOMAIN, path)
            best, best_s, ending = optimum(domain, problem, args.optimum_limit)
            held_karp = tidygen.optimum(seed, args.items, seconds=False)
            result = plan(domain, problem, planner=args.planner, time_budget=args.time_budget)
            times.append(result.planning_time_s)
            got = (
                f"{args.planner} {result.score.cost:7.2f}"
                if result.status is Status.SOLVED
                else f"{args.planner} {result.status.value}"
            )
            first = result.phases.get("first_plan", 0.0)
            timing = f"planning {result.planning_time_s:.2f}s (first plan {first:.2f}s)"
            if best is None:
                skipped.append(seed)
                print(
                    f"seed {seed:3d}: optimum unknown (optimal search {ending} after {best_s:.1f}s, "
                    f"limit {args.optimum_limit:g}s; Held-Karp {held_karp:.2f})  {got}  {timing}  "
                    "(not in the ratio)"
                )
                continue
            opt_times.append(best_s)
            check = "" if abs(best - held_karp) < 0.005 else f" DIFFERS from Held-Karp {held_karp:.2f}"
            if result.status is not Status.SOLVED:
                skipped.append(seed)
                print(
                    f"seed {seed:3d}: optimum {best:7.2f} ({best_s:.2f}s){check}  {got}  {timing}  (no plan)"
                )
                continue
            ratio = result.score.cost / best
            ratios[seed] = ratio
            print(
                f"seed {seed:3d}: optimum {best:7.2f} (optimal search {best_s:5.2f}s, Held-Karp "
                f"{held_karp:.2f}){check}  {got}  ratio {ratio:.4f}  {timing}  steps {len(result.steps)}"
            )
    head = f"{args.planner}, budget {args.time_budget:g}s, tidy-rooms.pddl, {args.items} objects"
    if not ratios:
        print(f"{head}: no seed with both an optimum and a plan (skipped: {skipped})")
        return
    worst = max(ratios, key=ratios.get)
    good = sum(r <= GOOD + 1e-9 for r in ratios.values())
    print(
        f"{head}, {len(ratios)} problems in the ratio"
        + (f" (skipped seeds {', '.join(map(str, skipped))})" if skipped else "")
        + f": cost ratio mean {statistics.mean(ratios.values()):.4f}, "
        f"max {ratios[worst]:.4f} (seed {worst}); "
        f"{good}/{len(ratios)} <= {GOOD}; planning time median {statistics.median(times):.2f}s, "
        f"max {max(times):.2f}s; optimal search median {statistics.median(opt_times):.2f}s, "
        f"max {max(opt_times):.2f}s"
    )


if __name__ == "__main__":
    main()
