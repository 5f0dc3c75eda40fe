"""The floor to compare a mission against: the time an omniscient robot with the same speeds
needs to tidy a room, and the most WRS score it reaches in the time limit.

    python bench/floor.py SCENARIO... [--results RESULTS.jsonl] [--grasp-s 3.1] [--place-s 9.2]
                          [--pull-s 12.0] [--time-limit 900] [--restarts 20]

The omniscient robot knows every item from the start, never looks, never fails. It drives at the
scenario's speed (the HSR's 0.22 m/s) along the shortest paths of the static map at the base's own
radius (furniture only, no safety margin: no floor item is ever in its way, so this is a floor,
not a plan), from each item's grasp pose
(the belief's choice for a room where every item is known) to the nearest deposit of its
category, opening each closed drawer once first (a pull, then the drawer's approach is where the
robot stands anyway). A grasp, a put and a pull cost what the arm's motions cost the pybullet
robot: by default the medians of the `grasp`, `place` and `pull_handle` units' `do` over the
Task 1 sweep of docs/results.md (18 rooms, 581 grasps, 549 puts, 54 pulls; looks excluded; the
base turning on the way to what it works on, as the floor's robot does too: its turns are free).

The tour is an asymmetric travelling salesman problem (from a deposit to the next item): nearest
neighbour from each of ``--restarts`` starts, then 2-opt and or-opt moves until none helps. The
score within the limit is the best prefix of that tour, with the drawers opened first or not at
all (then their items are left): a heuristic's figure, a floor for the score a planner should
aim at, not a proof of the most there is.

With ``--results`` (a sweep's results.jsonl), each mission's simulated time over its room's floor.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import statistics
import sys
from pathlib import Path

from sim.scenario.model import ORIENTATION
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import ENTRANCE, Placed, deposit_waypoint
from tidyplan.loop.deadline import improve
from tidyplan.loop.scenarios import load_scenario
from tidyplan.trace.score import TIME_LIMIT_S

GRASP_S, PLACE_S, PULL_S = 3.1, 9.2, 12.0  # s: medians of the pybullet units' do, see above
ALL_AWAY = DRAWERS_BONUS = 50


def room_floor(scenario, grasp_s: float, place_s: float, pull_s: float, restarts: int, limit: float) -> dict:
    room = RoomMap(scenario)
    items = [Placed(i.name, i.label, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items]
    facts = room.facts(items)
    static = room.grid((), bare=True)  # the base's own radius, no margin: a floor
    names = [deposit_waypoint(d.name) for d in scenario.deposits] + [ENTRANCE]
    names += [facts.grasp[i.name] for i in scenario.items if i.name in facts.grasp]
    pts = [facts.points[n] for n in names]
    lengths = static.path_lengths(pts)
    index = {n: k for k, n in enumerate(names)}
    speed = scenario.robot.speed

    def drive(a: str, b: str) -> float:
        d = lengths[index[a]][index[b]]
        return math.inf if d is None else d / speed

    oriented = any(d.category == ORIENTATION for d in scenario.deposits)
    unreached = [i.name for i in scenario.items if i.name not in facts.grasp]
    jobs = []  # (item, its grasp waypoint, the deposits it may go to, points it scores)
    for i in scenario.items:
        if i.name in unreached:
            continue
        # an orientation item goes to the orientation box (it scores its category there too), an
        # unknown object where unknown objects go
        cat = ORIENTATION if oriented and i.orientation is not None else i.label
        deps = [d for d in scenario.deposits if d.category == cat]
        # 10 in a deposit, 10 the right category, 10 standing where it is an orientation item
        jobs.append((i.name, facts.grasp[i.name], deps, 30 if cat == ORIENTATION else 20))
    drawers = [d for d in scenario.deposits if d.drawer is not None and d.drawer.closed]

    def leg(j: int, frm: str) -> tuple[float, str]:
        """Seconds from waypoint ``frm`` to take job j and put it away; where the robot ends."""
        _, wp, deps, _ = jobs[j]
        best = min(deps, key=lambda d: drive(wp, deposit_waypoint(d.name)))
        to = deposit_waypoint(best.name)
        return drive(frm, wp) + grasp_s + drive(wp, to) + place_s, to

    def cost(order: list[int], start: str) -> float:
        total, at = 0.0, start
        for j in order:
            s, at = leg(j, at)
            total += s
        return total

    def opening() -> tuple[float, str]:
        """Seconds to open every closed drawer from the entrance, nearest first; where it ends."""
        total, at, left = 0.0, ENTRANCE, list(drawers)
        while left:
            d = min(left, key=lambda d: drive(at, deposit_waypoint(d.name)))
            total += drive(at, deposit_waypoint(d.name)) + pull_s
            at = deposit_waypoint(d.name)
            left.remove(d)
        return total, at

    def tour(subset: list[int], start: str) -> list[int]:
        rng = random.Random(0)
        best: list[int] | None = None
        for r in range(max(1, restarts)):
            left, order, at = list(subset), [], start
            if r:
                rng.shuffle(left)
            while left:  # nearest neighbour, ties in the shuffled order
                j = min(left, key=lambda j: leg(j, at)[0])
                order.append(j)
                at = leg(j, at)[1]
                left.remove(j)
            order = improve(order, lambda o: cost(o, start))
            if best is None or cost(order, start) < cost(best, start):
                best = order
        return best or []

    open_s, after = opening()
    everything = tour(list(range(len(jobs))), after)
    floor_s = open_s + cost(everything, after)
    # the most score in the limit: the drawers opened first and the whole tour's prefix, or the
    # drawers never opened and the items that need none
    needs = {j for j, (_, _, deps, _) in enumerate(jobs) if all(d in drawers for d in deps)}
    plain = tour([j for j in range(len(jobs)) if j not in needs], ENTRANCE)
    score = max(
        _prefix_score(everything, after, open_s, leg, jobs, limit, DRAWERS_BONUS if drawers else 0),
        _prefix_score(plain, ENTRANCE, 0.0, leg, jobs, limit, 0),
    )
    return {
        "scenario": scenario.name,
        "objects": len(scenario.items),
        "unreached": unreached,
        "floor_s": round(floor_s, 1),
        "drawers_s": round(open_s, 1),
        "best_score_within_limit": score,
        "deliveries": len(everything),
    }


def _prefix_score(order, start, t0, leg, jobs, limit, drawers_bonus) -> int:
    """The score of doing ``order`` from ``start`` at ``t0`` until the limit."""
    t, at, score = t0, start, 0
    if t0 > limit:
        return 0
    for j in order:
        s, to = leg(j, at)
        if t + s > limit:
            return score + (drawers_bonus if score else 0)
        t, at, score = t + s, to, score + jobs[j][3]
    return score + (drawers_bonus if score else 0) + (ALL_AWAY if len(order) == len(jobs) else 0)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenarios", nargs="+", metavar="SCENARIO")
    ap.add_argument("--results", help="a sweep's results.jsonl: each mission's time over its floor")
    ap.add_argument("--grasp-s", type=float, default=GRASP_S)
    ap.add_argument("--place-s", type=float, default=PLACE_S)
    ap.add_argument("--pull-s", type=float, default=PULL_S)
    ap.add_argument("--time-limit", type=float, default=TIME_LIMIT_S)
    ap.add_argument("--restarts", type=int, default=20)
    args = ap.parse_args(argv)
    floors = {}
    print("| room | objects | floor (s) | of it, the drawers (s) | most WRS score within the limit |")
    print("| --- | --- | --- | --- | --- |")
    for path in args.scenarios:
        scenario = load_scenario(path)
        f = room_floor(scenario, args.grasp_s, args.place_s, args.pull_s, args.restarts, args.time_limit)
        floors[scenario.name] = f
        extra = f" ({len(f['unreached'])} unreached: {' '.join(f['unreached'])})" if f["unreached"] else ""
        print(
            f"| {f['scenario']} | {f['objects']} | {f['floor_s']:.0f} | {f['drawers_s']:.0f} "
            f"| {f['best_score_within_limit']}{extra} |"
        )
    if args.results:
        ratios = []
        print("\n| mission | world | simulated (s) | over the floor | WRS within the limit |")
        print("| --- | --- | --- | --- | --- |")
        for line in Path(args.results).read_text().splitlines():
            r = json.loads(line)
            f = floors.get(r.get("scenario"))
            if f is None or not r.get("sim_time_s"):
                continue
            if not math.isfinite(f["floor_s"]):
                continue  # a room the floor could not cross (said in the first table)
            ratio = r["sim_time_s"] / f["floor_s"]
            ratios.append(ratio)
            row = (r["scenario"], r["world"], f"{r['sim_time_s']:.0f}", f"{ratio:.2f}")
            row += (f"{r['wrs_score']:.0f}",)
            print("| " + " | ".join(row) + " |")
        if ratios:
            median = statistics.median(ratios)
            print(f"\nmedian mission time over the floor: {median:.2f} ({len(ratios)} missions)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
