"""How much faster than real time a headless pybullet mission runs.

    python bench/speed.py [--scenario problems/case3.toml] [--seeds 1] [--planner lama] [--patience S]

Runs O-FSM in the pybullet world (DIRECT mode, no window) and prints, per run, the simulated
seconds, the wall seconds, their ratio (the goal: at least 100x for case III), and how
the wall time splits between the planner (the `plan` events' planning_time_s) and everything
else (physics, perception, the loop). Traces go to a temporary folder. The missions run one at
a time through ``tidyplan sweep``'s engine (each in a process of its own).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default=str(ROOT / "problems" / "case3.toml"))
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--planner", default="lama")
    ap.add_argument("--time-budget", type=float, default=1.0)
    from tidyplan.planning.engines import MISSION_PATIENCE
    from tidyplan.sweep.grid import grid, run_sweep

    ap.add_argument(
        "--patience", type=float, default=MISSION_PATIENCE, help="tidyplan run's --patience (0: off)"
    )
    args = ap.parse_args()

    out = Path(tempfile.mkdtemp(prefix="tidyplan-speed-"))
    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    configs = grid(
        [args.scenario],
        seeds,
        ["ofsm"],
        [""],
        [args.planner],
        "pybullet",
        time_budget=args.time_budget,
        patience=args.patience,
    )
    ratios = []

    def show(s: dict) -> None:
        if s["status"] != "done":
            raise SystemExit(f"speed.py: seed {s['seed']}: the mission {s['status']}: {s['error']}")
        planning = sum(
            e.get("planning_time_s", 0.0)
            for e in map(json.loads, Path(s["trace"]).read_text().splitlines())
            if e["kind"] == "plan"
        )
        ratio = s["sim_time_s"] / s["wall_time_s"]
        ratios.append(ratio)
        print(
            f"{s['scenario']} seed {s['seed']}: {'tidied' if s['success'] else 'FAILED'} "
            f"{s['delivered']}/{s['objects']}, sim {s['sim_time_s']:.0f} s, wall {s['wall_time_s']:.1f} s "
            f"(planner {planning:.1f} s, the rest {s['wall_time_s'] - planning:.1f} s): "
            f"{ratio:.0f}x real time",
            flush=True,
        )

    # tidyplan sweep's engine, one mission at a time (a wall time measured beside another
    # mission is no speed), each in a process of its own; the wall time is the mission's own
    # (tidyplan.loop.mission.run's clock), not the process's start-up
    run_sweep(configs, out, jobs=1, on_row=show)
    print(f"mean {sum(ratios) / len(ratios):.0f}x real time over {len(ratios)} run(s); goal >= 100x")
    return 0 if min(ratios) >= 50 else 1


if __name__ == "__main__":
    sys.exit(main())
