"""The loop's own time per action, at 12, 48 and 96 objects: what monitoring costs as rooms grow.

    python bench/loop_time.py [--sizes 12,16,48,96] [--repeat 3] [--actions 0] [--seeds 0] [--out DIR]

For each size, a symbolic mission (12: problems/case3.toml; other sizes, multiples of 8:
bench/wrs.py's two-room layout, as bench/replan.py makes them) runs to its end, or for its first
``--actions`` actions when that is given (then it is stopped: its trace stays readable). Between
one ``action`` event and the next, the wall time (read as each event is written) is the loop's
turn: the world's simulation (the symbolic world's motion, frames and looks), the belief's update
from what the robot saw, the map's facts, the assumptions' check, the plan's simulation, and any
replan. Two parts are taken out, so what is left is the loop's own work for one action: the
replans' own seconds (their ``plan`` events' ``planning_time_s``: the map's facts for the
problem, writing it, the planner, the commitment check), and the world's, the time inside its
calls (the simulator's, which on the robot is the robot's: the world is run as a registry entry
of its own, the symbolic world with each call clocked). Printed per size, in milliseconds: the
loop's median, 90th percentile and mean per action, the mean over the turns that did not
replan (one that did also pays, past its plan event, what the new plan first asks of the map:
its waypoints' pairs, the problem's copies in the trace), and of those the mean of the turns
that left the map's floor as it was and of those that made the map work out a new one (an item
taken, put down, seen or moved, on the floor or on furniture: what the map's facts are made
from; counted by wrapping ``RoomMap._floor``) with their share: what a turn costs by what it
changed; the world's mean beside it, and the replans' median. 12 objects are case III, a room
of its own (smaller: fewer waypoints, less floor to see); 16, 48 and 96 are one layout, so those
rows compare the number of objects alone (in the same two rooms: more of them lie on the floor,
9 of 16, 73 of 96, and more actions change it). Each size runs ``--repeat`` times, the sizes
taking turns (a process's first mission pays for what it loads once, and a busy second falls on
one run, not on one size). Runs of a size that made the same actions are one mission (one
seed: the same turns, in the same order), so each turn's time is its least over them, the
machine's noise taken out as a timer's best of several is (where the planner's wall-clock budget
made another plan, the run least in mean is taken, and it is said); the spread of the runs' own
means is printed beside it. ``--seeds`` (a list, 0,1,2, or a range, 0-2) runs each size's mission
for each of those seeds (the same rooms, the world's draws anew: which looks miss an item, so
what is seen when, and the plans that follow): a row then pools every seed's turns, and prints
each seed's mean beside it (what one mission's mix of turns makes of it: one mission may make
more of its floor changes in turns that replan, whose map work counts as planning).

Traces go under DIR (default: a new temporary folder), never over an existing file.
"""

from __future__ import annotations

import argparse
import functools
import inspect
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from replan import _scenario  # noqa: E402  (the same rooms as the replan benchmark)


class _Enough(Exception):
    """Raised from the trace listener once the mission has run its actions."""


_SPENT = {"s": 0.0, "depth": 0}  # wall seconds inside the world's calls (the outermost only)


def _clocked(method):
    @functools.wraps(method)
    def call(*args, **kwargs):
        if _SPENT["depth"]:
            return method(*args, **kwargs)
        _SPENT["depth"], start = 1, time.perf_counter()
        try:
            return method(*args, **kwargs)
        finally:
            _SPENT["s"] += time.perf_counter() - start
            _SPENT["depth"] = 0

    return call


def _clocked_world() -> str:
    """The symbolic world with the wall time of every call into it counted (``_SPENT``), as a
    world of the registry: the simulator's own time, which the loop's turn is read without."""
    from tidyplan.worlds.registry import WORLDS, WorldEntry
    from tidyplan.worlds.symbolic import SymbolicWorld

    global ClockedSymbolicWorld
    methods = {
        name: _clocked(value)
        for cls in reversed(SymbolicWorld.__mro__)
        for name, value in vars(cls).items()
        if inspect.isfunction(value) and not name.startswith("_")
    }
    ClockedSymbolicWorld = type("ClockedSymbolicWorld", (SymbolicWorld,), methods)
    WORLDS["symbolic-clocked"] = WorldEntry(f"{__name__}:ClockedSymbolicWorld", WORLDS["symbolic"].skills)
    return "symbolic-clocked"


_FLOORS = {"new": 0}  # floors (placed items) the map worked out that it did not keep


def _counted_floors() -> None:
    """Count each floor the map meets that it does not keep (the placed items changed: one
    taken, put down, seen or moved), by wrapping ``RoomMap._floor``, once."""
    from tidyplan.belief.geometry import RoomMap

    if getattr(RoomMap._floor, "counted", False):
        return
    floor = RoomMap._floor

    def counted(self, key):
        _FLOORS["new"] += key not in self._floors
        return floor(self, key)

    counted.counted = True
    RoomMap._floor = counted


def turns(scenario: Path, trace: Path, seed: int, actions: int) -> tuple[list, ...]:
    """(the loop's own wall seconds of each turn, the world's seconds in each, each replan's
    seconds, each turn's action, whether each turn replanned, whether each made a new floor)
    of a symbolic mission's first ``actions`` actions (0: all)."""
    from tidyplan.loop.mission import run
    from tidyplan.loop.options import Settings

    _counted_floors()
    own, world, replans, acts, replanned, floors = [], [], [], [], [], []
    state = {"last": None, "planning": 0.0, "n": 0, "world": 0.0, "plans": 0, "floors": _FLOORS["new"]}

    def listen(event: dict) -> None:
        kind = event.get("kind")
        if kind == "plan":
            state["planning"] += event.get("planning_time_s") or 0.0
            state["plans"] += 1
            replans.append(event.get("planning_time_s") or 0.0)
        elif kind == "action":
            # the clock read here, not the event's wall_s (rounded to the millisecond)
            now, spent = time.perf_counter(), _SPENT["s"]
            if state["last"] is not None:
                in_world = spent - state["world"]
                own.append(now - state["last"] - state["planning"] - in_world)
                world.append(in_world)
                acts.append(event.get("action"))
                replanned.append(state["plans"] > 0)
                floors.append(_FLOORS["new"] > state["floors"])
            state["last"], state["planning"], state["world"], state["plans"] = now, 0.0, spent, 0
            state["floors"] = _FLOORS["new"]
            state["n"] += 1
            if actions and state["n"] >= actions:
                raise _Enough

    try:
        run(str(scenario), trace, Settings(seed=seed, world=_clocked_world()), on_event=listen)
    except _Enough:
        pass
    return own, world, replans, acts, replanned, floors


def _seeds(spec: str) -> list[int]:
    """``--seeds``: "0,1,2" or "0-2" (empty where it is neither)."""
    try:
        if "-" in spec:
            lo, hi = (int(x) for x in spec.split("-", 1))
            return list(range(lo, hi + 1)) if 0 <= lo <= hi else []
        seeds = [int(x) for x in spec.split(",")]
        return seeds if all(x >= 0 for x in seeds) else []
    except ValueError:
        return []


def _least(mission: list[tuple[list, ...]], size: int, seed: int) -> tuple[list, list, list]:
    """(each turn's least time, whether it replanned, whether it made a new floor) over the runs
    of one size and seed. Runs that made the same actions are one mission (one seed: the same
    turns in the same order), so a turn's least time over them is its time with the least of
    the machine's noise; where the planner's wall-clock budget made another plan in some run,
    the run least in mean is taken (and it is said)."""
    if len({tuple(run[3]) for run in mission}) == 1:
        least = [min(times) for times in zip(*(run[0] for run in mission), strict=True)]
        return least, mission[0][4], mission[0][5]
    print(
        f"({size} objects, seed {seed}: the runs' actions differ;"
        " the turns are those of the run least in mean)"
    )
    least, *_, replanned, new_floor = min(mission, key=lambda run: statistics.fmean(run[0]))
    return least, replanned, new_floor


def _p90(own: list[float]) -> float:
    return statistics.quantiles(own, n=10)[-1] if len(own) >= 2 else own[0]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="12,16,48,96")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each size, taking turns (default 3)")
    ap.add_argument("--actions", type=int, default=0, help="stop after this many (0: the whole mission)")
    ap.add_argument("--seeds", default="0", help="the missions' seeds: a list (0,1,2) or a range (0-2)")
    ap.add_argument("--seed", type=int, default=None, help="one seed (the same as --seeds N)")
    ap.add_argument("--out", default=None, metavar="DIR")
    args = ap.parse_args()
    try:
        sizes = [int(x) for x in args.sizes.split(",")]
    except ValueError:
        ap.exit(2, f"loop_time.py: --sizes: {args.sizes!r} is not a list of numbers\n")
    seeds = _seeds(args.seeds) if args.seed is None else [args.seed]
    if not seeds:
        ap.exit(2, f"loop_time.py: --seeds: {args.seeds!r} is not a list (0,1,2) or a range (0-2) of seeds\n")
    if args.repeat < 1:
        ap.exit(2, "loop_time.py: --repeat must be at least 1\n")
    if args.actions < 0 or args.actions == 1:
        ap.exit(2, "loop_time.py: --actions must be 0 (the whole mission) or at least 2\n")
    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="tidyplan-loop-time-"))
    out.mkdir(parents=True, exist_ok=True)
    which = f"the first {args.actions} actions" if args.actions else "every action"
    named = "seed" if len(seeds) == 1 else "seeds"
    print(
        f"traces under {out}; {which} of each mission, {named} {','.join(map(str, seeds))}, "
        f"{args.repeat} runs of each size and seed"
    )
    runs: dict[tuple[int, int], list[tuple[list, ...]]] = {(size, s): [] for size in sizes for s in seeds}
    for r in range(args.repeat):
        for seed in seeds:
            for size in sizes:
                scenario = _scenario(size, out)
                trace = out / f"n{size}-s{seed}-r{r}.jsonl"
                if trace.exists():
                    ap.exit(2, f"loop_time.py: {trace} exists; choose another --out\n")
                runs[(size, seed)].append(turns(scenario, trace, seed, args.actions))
    print(
        "\n| objects | room | turns | loop per action: median (ms) | 90th percentile (ms) | mean (ms) "
        "| mean, turns without a replan (ms) | of those, floor kept: mean (ms) | new floor: mean (ms), "
        "share | the runs' means (ms) | the world's, mean (ms) | replans | replan median (s) "
        "| each seed's mean (ms) |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for size in sizes:
        room = "case III" if size == 12 else "two rooms"
        done = {seed: [run for run in runs[(size, seed)] if run[0]] for seed in seeds}
        done = {seed: kept for seed, kept in done.items() if kept}
        if not done:
            print(f"| {size} | {room} | 0 | - | - | - | - | - | - | - | - | - | - | - |")
            continue
        least, replanned, new_floor, per_seed = [], [], [], []
        for seed, mission in done.items():
            times, again, floor = _least(mission, size, seed)
            least += times
            replanned += again
            new_floor += floor
            per_seed.append(statistics.fmean(times))
        med, p90 = statistics.median(least), _p90(least)
        # a turn that replanned also pays what the new plan asks of the map first (its
        # waypoints' pairs, the problem's copies in the trace): apart, the turns of monitoring only
        quiet = [t for t, again in zip(least, replanned, strict=True) if not again]
        quiet_mean = f"{statistics.fmean(quiet) * 1000:.1f}" if quiet else "-"
        # of those, the turns that made the map work out a new floor (an item taken, put down,
        # seen or moved) and the rest: what a turn costs by what it changed
        both = [(t, f) for t, again, f in zip(least, replanned, new_floor, strict=True) if not again]
        kept = [t for t, f in both if not f]
        changed = [t for t, f in both if f]
        kept_mean = f"{statistics.fmean(kept) * 1000:.1f}" if kept else "-"
        changed_mean = (
            f"{statistics.fmean(changed) * 1000:.1f}, {len(changed) / len(both):.2f}" if changed else "-"
        )
        every = [run for mission in done.values() for run in mission]
        means = sorted(statistics.fmean(own) for own, *_ in every)
        world = statistics.median(statistics.fmean(w) for _, w, *_ in every)
        replans = [t for run in every for t in run[2]]
        rep = statistics.median(replans) if replans else float("nan")
        spread = (
            f"{means[0] * 1000:.1f}-{means[-1] * 1000:.1f}" if len(means) > 1 else f"{means[0] * 1000:.1f}"
        )
        plans = sum(len(mission[0][2]) for mission in done.values())
        print(
            f"| {size} | {room} | {len(least)} | {med * 1000:.1f} | {p90 * 1000:.1f} "
            f"| {statistics.fmean(least) * 1000:.1f} | {quiet_mean} | {kept_mean} | {changed_mean} "
            f"| {spread} | {world * 1000:.1f} | {plans} | {rep:.3f} "
            f"| {' / '.join(f'{m * 1000:.1f}' for m in per_seed)} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
