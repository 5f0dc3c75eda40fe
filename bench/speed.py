"""How much faster than real time a headless pybullet mission runs.

    python bench/speed.py [--scenario problems/case3.toml] [--seeds 1] [--planner lama] [--patience S]

Runs O-FSM in the pybullet world (DIRECT mode, no window) and prints, per run, the simulated
seconds, the wall seconds, their ratio (the goal: at least 100x for case III), and how
the wall time splits between the planner (the `plan` events' planning_time_s) and everything
else (physics, perception, the loop). Traces go to a temporary folder.
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
    from tidyplan.engines import MISSION_PATIENCE
    from tidyplan.mission import Settings, run

    ap.add_argument(
        "--patience", type=float, default=MISSION_PATIENCE, help="tidyplan run's --patience (0: off)"
    )
    args = ap.parse_args()

    out = Path(tempfile.mkdtemp(prefix="tidyplan-speed-"))
    ratios = []
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        trace = out / f"speed-s{seed}.jsonl"
        settings = Settings(
            "ofsm",
            seed,
            planner=args.planner,
            time_budget=args.time_budget,
            patience=args.patience or None,
            world="pybullet",
        )
        s = run(args.scenario, trace, settings)
        planning = sum(
            e.get("planning_time_s", 0.0)
            for e in map(json.loads, trace.read_text().splitlines())
            if e["kind"] == "plan"
        )
        ratio = s["sim_time_s"] / s["wall_time_s"]
        ratios.append(ratio)
        print(
            f"{s['scenario']} seed {seed}: {'tidied' if s['success'] else 'FAILED'} "
            f"{s['delivered']}/{s['objects']}, sim {s['sim_time_s']:.0f} s, wall {s['wall_time_s']:.1f} s "
            f"(planner {planning:.1f} s, the rest {s['wall_time_s'] - planning:.1f} s): "
            f"{ratio:.0f}x real time",
            flush=True,
        )
    print(f"mean {sum(ratios) / len(ratios):.0f}x real time over {len(ratios)} run(s); goal >= 100x")
    return 0 if min(ratios) >= 50 else 1


if __name__ == "__main__":
    sys.exit(main())
