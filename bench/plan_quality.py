"""Plan cost against the exact optimum on 12-object tidy-up problems.

    python bench/plan_quality.py [--seeds 10] [--planner lama-optimal] [--time-budget 1]

Each seed makes a problem for domains/tidy.pddl in the WRS room with
path-length move costs (bench/tidygen.py); its optimum comes from an
independent dynamic programme (`tidygen.optimum`), not from a planner. Prints,
per seed and overall, the cost ratio to the optimum and the planning time
(the whole `plan()` call: compilation, Fast Downward's translator and search; the budget is the
improvement time after the first plan). A problem without a plan is reported and left out.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

from tidyplan.generate import tasks as tidygen  # noqa: E402
from tidyplan.pddl.reader import read  # noqa: E402
from tidyplan.planning.planner import plan  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--items", type=int, default=12)
    ap.add_argument("--planner", default="lama-optimal")
    ap.add_argument("--time-budget", type=float, default=1.0)
    ap.add_argument("--domain", default=str(ROOT / "domains" / "tidy.pddl"))
    ap.add_argument(
        "--no-shortest-paths",
        action="store_true",
        help="leave (shortest-paths) out of the problems: every move is open, to any waypoint",
    )
    args = ap.parse_args()
    ratios, times, missed = [], [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            path = Path(tmp) / f"tidy-{seed}.pddl"
            text = tidygen.generate(seed, args.items)
            if args.no_shortest_paths:
                text = text.replace("    (shortest-paths)\n", "")
            path.write_text(text)
            domain, problem = read(args.domain, path)
            result = plan(domain, problem, planner=args.planner, time_budget=args.time_budget)
            best = tidygen.optimum(seed, args.items)
            if result.score is None:
                print(f"seed {seed:3d}: {result.status.value}: {result.message}")
                missed += 1
                continue
            ratio = result.score.cost / best
            ratios.append(ratio)
            times.append(result.planning_time_s)
            print(
                f"seed {seed:3d}: cost {result.score.cost:7.2f}  optimum {best:7.2f}  "
                f"ratio {ratio:.4f}  planning {result.planning_time_s:.2f}s  steps {len(result.steps)}"
            )
    if not ratios:
        print(f"{args.planner}: no plan on any of {missed} problems")
        return
    print(
        f"{args.planner}, budget {args.time_budget:g}s, {len(ratios)} problems of {args.items} objects"
        f"{f' ({missed} without a plan)' if missed else ''}: "
        f"cost ratio mean {statistics.mean(ratios):.4f}, max {max(ratios):.4f}; "
        f"{sum(r <= 1.05 for r in ratios)} within 1.05; "
        f"planning time median {statistics.median(times):.2f}s, max {max(times):.2f}s"
    )


if __name__ == "__main__":
    main()
