"""How far the −ln p compilation's plans are from the exact criterion optimum.

    python bench/criterion_gap.py [--time-budget 1]

For each example task: the criterion c + R(1 − p) of (a) the default planner's
plan, (b) the optimal plan of the compiled costs (the compilation's own error,
without search error), and (c) the exact optimum (`tidyplan.planning.exact`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tidyplan.pddl.reader import read
from tidyplan.planning.exact import exact_optimum
from tidyplan.planning.planner import DEFAULT_ENGINE, plan

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = [
    ("domains/tidy.pddl", "problems/tidy-p1.pddl"),
    ("domains/tidy.pddl", "problems/tidy-p2.pddl"),
    ("domains/tidy.pddl", "problems/tidy-p3.pddl"),
    ("domains/tidy.pddl", "problems/tidy-strata-cheap.pddl"),
    ("domains/avs.pddl", "problems/avs-indirect.pddl"),
    ("domains/avs.pddl", "problems/avs-direct.pddl"),
    ("tests/data/routes-domain.pddl", "tests/data/routes-r1000.pddl"),
    ("tests/data/routes-domain.pddl", "tests/data/routes-r1.pddl"),
    ("tests/data/gap-domain.pddl", "tests/data/gap-problem.pddl"),
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time-budget", type=float, default=1.0)
    args = ap.parse_args()
    print(f"{'problem':28s} {'default':>10s} {'compiled-opt':>12s} {'exact':>10s} {'default/exact':>13s}")
    worst = 1.0
    for domain_path, problem_path in EXAMPLES:
        domain, problem = read(ROOT / domain_path, ROOT / problem_path)
        default = plan(domain, problem, planner=DEFAULT_ENGINE, time_budget=args.time_budget)
        compiled_opt = plan(domain, problem, planner="optimal", time_budget=60)
        exact = exact_optimum(domain, problem)
        ratio = default.score.criterion / exact.score.criterion
        worst = max(worst, ratio)
        print(
            f"{Path(problem_path).stem:28s} {default.score.criterion:10.2f} "
            f"{compiled_opt.score.criterion:12.2f} {exact.score.criterion:10.2f} {ratio:13.4f}"
        )
    print(f"worst default/exact ratio: {worst:.4f}")


if __name__ == "__main__":
    main()
