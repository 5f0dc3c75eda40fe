"""The loop's own time per action, at 12, 48 and 96 objects: what monitoring costs as rooms grow.

    python bench/loop_time.py [--sizes 12,48,96] [--actions 0] [--seed 0] [--out DIR]

For each size, a symbolic mission (12: problems/case3.toml; 48 and 96: bench/wrs.py's two-room
layout, as bench/replan.py makes them) runs to its end, or for its first ``--actions`` actions
when that is given (then it is stopped: its trace stays readable). Between one ``action`` event
and the next, the wall time is the loop's turn: the world's motion (symbolic: bookkeeping), the
look and the belief's update, the map's facts, the assumptions' check, the plan's simulation,
and any replan. The replans' own seconds (their ``plan`` events' ``planning_time_s``: the map's
facts for the problem, writing it, the planner, the commitment check) are taken out, so what is
left is the monitoring of one action. Printed per size: its median, 90th percentile and mean,
and the replans' median beside it. (12 objects are case III, a room of its own; ``--sizes
16,48,96`` compares sizes in one layout.)

Traces go under DIR (default: a new temporary folder), never over an existing file.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from replan import _scenario  # noqa: E402  (the same rooms as the replan benchmark)


class _Enough(Exception):
    """Raised from the trace listener once the mission has run its actions."""


def turns(scenario: Path, trace: Path, seed: int, actions: int) -> tuple[list[float], list[float]]:
    """(the loop's own wall seconds of each turn, each replan's seconds) of a symbolic mission's
    first ``actions`` actions (0: all of them)."""
    from tidyplan.loop.mission import run
    from tidyplan.loop.options import Settings

    own, replans = [], []
    state = {"last": None, "planning": 0.0, "n": 0}

    def listen(event: dict) -> None:
        kind = event.get("kind")
        if kind == "plan":
            state["planning"] += event.get("planning_time_s") or 0.0
            replans.append(event.get("planning_time_s") or 0.0)
        elif kind == "action":
            if state["last"] is not None:
                own.append(event["wall_s"] - state["last"] - state["planning"])
            state["last"], state["planning"] = event["wall_s"], 0.0
            state["n"] += 1
            if actions and state["n"] >= actions:
                raise _Enough

    try:
        run(str(scenario), trace, Settings(seed=seed, world="symbolic"), on_event=listen)
    except _Enough:
        pass
    return own, replans


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="12,48,96")
    ap.add_argument("--actions", type=int, default=0, help="stop after this many (0: the whole mission)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, metavar="DIR")
    args = ap.parse_args()
    try:
        sizes = [int(x) for x in args.sizes.split(",")]
    except ValueError:
        ap.exit(2, f"loop_time.py: --sizes: {args.sizes!r} is not a list of numbers\n")
    if args.actions < 0 or args.actions == 1:
        ap.exit(2, "loop_time.py: --actions must be 0 (the whole mission) or at least 2\n")
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="tidyplan-loop-time-"))
    out.mkdir(parents=True, exist_ok=True)
    which = f"the first {args.actions} actions" if args.actions else "every action"
    print(f"traces under {out}; {which} of each mission, seed {args.seed}")
    print(
        "\n| objects | turns | loop per action: median (s) | 90th percentile (s) | mean (s) | replans ",
        end="",
    )
    print("| replan median (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for size in sizes:
        scenario = _scenario(size, out)
        trace = out / f"n{size}-s{args.seed}.jsonl"
        if trace.exists():
            ap.exit(2, f"loop_time.py: {trace} exists; choose another --out\n")
        own, replans = turns(scenario, trace, args.seed, args.actions)
        if not own:
            print(f"| {size} | 0 | - | - | - | {len(replans)} | - |")
            continue
        p90 = statistics.quantiles(own, n=10)[-1] if len(own) >= 2 else own[0]
        rep = statistics.median(replans) if replans else float("nan")
        print(
            f"| {size} | {len(own)} | {statistics.median(own):.3f} | {p90:.3f} | {statistics.fmean(own):.3f} "
            f"| {len(replans)} | {rep:.3f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
