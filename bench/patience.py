"""What `--patience` costs in plan quality, on the loop's own problems.

    python bench/patience.py [--scenarios problems/case1.toml,...] [--seeds 2] [--replans 6]
                             [--patience 0.25,0.5] [--time-budget 1]

Symbolic missions (O-FSM, `lama-first`, so the problems do not depend on the machine's speed)
save the problems they plan from the belief (`replan-NNN.pddl`, beside the domain the trace
copied). Each problem is then planned as a mission plans it (LAMA anytime, every move open,
`--time-budget` seconds of improvement) once without patience and once per `--patience`, and the
criterion of each plan and the time each call took are printed, then per setting: how many plans
were as good as the full budget's, the median and worst criterion ratio (patience / full budget)
and the median time. LAMA's improvement depends on the machine's speed, so the full budget's own
plans differ between two calls too: `--repeat 2` plans the full budget twice to show that spread.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _problems(scenario: str, seed: int, replans: int, out: Path) -> list[tuple[Path, Path]]:
    from replan import first_plans  # bench/replan.py: a mission stopped after its first plans

    trace = out / f"{Path(scenario).stem}-s{seed}.jsonl"
    made = first_plans(Path(scenario), trace, "lama-first", seed, replans, 1.0)
    folder = trace.with_suffix(".pddl")
    return [
        (folder / "domain.pddl", trace.parent / e["problem"])
        for e in made
        if e["status"] == "solved" and e.get("problem")
    ]


def _plan(domain: Path, problem: Path, budget: float, patience: float | None) -> tuple[float, float]:
    from tidyplan.pddl.reader import read
    from tidyplan.planning.planner import plan

    d, p = read(domain, problem)
    result = plan(d, p, planner="lama", time_budget=budget, reduce_moves=False, patience=patience)
    return (result.score.criterion if result.score else float("nan")), result.planning_time_s


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    cases = ",".join(str(ROOT / "problems" / f"case{i}.toml") for i in (1, 2, 3))
    ap.add_argument("--scenarios", default=cases)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--replans", type=int, default=6)
    ap.add_argument("--patience", default="0.25,0.5")
    ap.add_argument("--time-budget", type=float, default=1.0)
    ap.add_argument("--repeat", type=int, default=1, help="plans with the full budget per problem")
    args = ap.parse_args()
    try:
        waits = [float(x) for x in args.patience.split(",")]
    except ValueError:
        ap.exit(2, f"patience.py: --patience: {args.patience!r} is not a list of seconds\n")
    if not all(w > 0 for w in waits) or args.time_budget <= 0 or args.seeds < 1 or args.repeat < 1:
        ap.exit(2, "patience.py: --patience, --time-budget, --seeds and --repeat must be positive\n")
    out = Path(tempfile.mkdtemp(prefix="tidyplan-patience-"))
    print(f"problems under {out}; LAMA, budget {args.time_budget:g} s")
    pairs = [
        pair
        for scenario in args.scenarios.split(",")
        for seed in range(args.seeds)
        for pair in _problems(scenario, seed, args.replans, out)
    ]
    settings = [("full", None)] * args.repeat + [(f"patience {w:g}", w) for w in waits]
    rows = []
    print(f"{'problem':40s} " + " ".join(f"{name:>18s}" for name, _ in settings))
    for domain, problem in pairs:
        row = [_plan(domain, problem, args.time_budget, w) for _, w in settings]
        rows.append(row)
        cells = " ".join(f"{c:10.2f} {t:6.2f} s" for c, t in row)
        print(f"{problem.parent.name + '/' + problem.name:40s} {cells}", flush=True)
    print(f"\n{len(rows)} problems; criterion against the first full-budget plan:")
    for i, (name, _) in enumerate(settings):
        ratios = [r[i][0] / r[0][0] for r in rows]
        same = sum(abs(x - 1) < 1e-9 for x in ratios)
        print(
            f"  {name:14s} as good {sum(x <= 1 + 1e-9 for x in ratios):3d}/{len(rows)} (equal {same}), "
            f"ratio median {statistics.median(ratios):.4f} mean {statistics.mean(ratios):.4f} "
            f"max {max(ratios):.4f}; time median {statistics.median(r[i][1] for r in rows):.2f} s"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
