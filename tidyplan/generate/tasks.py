"""Seeded tidy-up problems for ``domains/tidy.pddl`` in the WRS room, and their exact optimum.

Why: the planner's cost optimality needs a reference that shares no code with it. This module
builds a problem the way the simulation will (furniture boxes -> inflated occupancy grid ->
shortest path lengths between waypoints) and solves the same cost model independently, by
dynamic programming over subsets (Held-Karp), so a bench can hold the planner's plan cost to
``optimum(seed)``. The grid and its paths are ``sim.grid``'s (the simulation's own); otherwise
it imports only the standard library and numpy, never tidyplan.

Room (figures from docs/sources.md, Gazebo world of the WRS 2020 arena): x in [-3.0, 0.5],
y in [-2.0, 2.0] (3.5 m x 4 m; the deposit wall's furniture is centred at x = -2.7, so we put
the wall at x = -3.0 and the far wall 3.5 m away: our choice, not confirmed). The entrance
door is at the corner x = 0.5, y = -2.0 (our choice; the rules only say "at one corner").
Robot radius 0.22 m (HSR footprint about 0.43 m across). Grid 5 cm, 8-connected.
Floor items are not obstacles here: the distances are those of the static map (the paper's
pre-built occupancy grid); obstruction by floor items is modelled by `blocks` in P3 problems.

Cost model (must match tidy.pddl, whose costs are the robot's seconds): a move its travel time,
the path's length at the HSR's 0.22 m/s plus a 0.8 s stop (2 decimals); take_object 5.7,
deliver_it 10.2. ``optimum(..., seconds=False)`` is the same room in metres (a move its length,
take and deliver 1 each): the cost model of bench/tidygen_rooms.py's encoding.
"""

from __future__ import annotations

import argparse
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from sim.grid import CELL, ROBOT_RADIUS, Box, OccupancyGrid

X0, X1, Y0, Y1 = -3.0, 0.5, -2.0, 2.0
ITEM_GAP = 0.2  # objects at least 0.2 m apart (WRS world spawn rule)
GRASP_DIST, GRASP_MIN, GRASP_MAX = 0.45, 0.30, 0.65
CLEAR = ROBOT_RADIUS + 0.05  # a waypoint keeps the robot off floor items (radius ~5 cm)
ENTRANCE = (0.0, -1.6)
DELIVERY_X = -2.15  # waypoints in front of the deposit wall, just outside the inflation
CATEGORIES = ("food", "kitchen", "tool", "task")  # the 4 item categories (3 each at 12)
# tidy.pddl's costs, in seconds (tidyplan.belief.problem.travel_time writes a mission's the same way)
SPEED, STOP_S, TAKE_S, DELIVER_S = 0.22, 0.8, 5.7, 10.2


# sizes from the WRS rules; positions from the Gazebo world, except shelf and chair (our choice)
FURNITURE = (
    Box(-2.70, 1.00, 0.44, 0.99, "drawer"),
    Box(-2.70, -0.30, 0.40, 1.20, "deposit-table"),
    Box(-2.70, -1.70, 0.38, 0.33, "bin-a"),
    Box(-2.70, -1.20, 0.38, 0.33, "bin-b"),
    Box(-0.30, 0.20, 0.40, 1.20, "long-table"),
    Box(-0.30, 1.20, 0.40, 0.40, "tall-table"),
    Box(-1.90, 1.86, 0.80, 0.28, "shelf"),
    Box(-0.90, 1.70, 0.58, 0.54, "chair"),
)
# deposit -> (y of the deposit on the wall, category accepted); WRS rules, docs/sources.md
DEPOSITS = {
    "tray-a": (-0.75, "food"),
    "tray-b": (-0.45, "food"),
    "container-a": (-0.20, "kitchen"),
    "container-b": (0.10, "orientation"),
    "drawer": (1.00, "tool"),
    "bin-a": (-1.70, "task"),
    "bin-b": (-1.20, "unknown"),
}
# spawn zones (x range, y range, support); WRS world: half floor, a third long table, a sixth tall
ZONES = {
    "floor": ((-1.0, -0.4), (-0.35, 1.35)),
    "long-table": ((-0.45, -0.2), (-0.35, 0.7)),
    "tall-table": ((-0.45, -0.2), (1.0, 1.35)),
}


@dataclass(frozen=True, slots=True)
class Instance:
    """A generated problem: waypoints and their (x, y), rounded distances (inf: no path) and travel
    times, items."""

    waypoints: tuple[str, ...]
    xy: tuple[tuple[float, float], ...]
    dist: tuple[tuple[float, ...], ...]
    time: tuple[tuple[float, ...], ...]  # s: travel_time of each distance
    items: tuple[tuple[str, str, str, float, float], ...]  # name, category, support, x, y
    grasp: tuple[int, ...]  # waypoint index of each item's grasp waypoint


@lru_cache(maxsize=1)
def _room() -> OccupancyGrid:
    """The static map: the room's walls and furniture inflated by the robot radius, 5 cm cells."""
    return OccupancyGrid((X0, X1, Y0, Y1), FURNITURE, cell=CELL, radius=ROBOT_RADIUS)


def _grasp_point(
    x: float, y: float, cells: list[tuple[float, float]], avoid: list[tuple[float, float]]
) -> tuple[float, float] | None:
    """A reachable free cell centre about 0.45 m from the item (the arm's comfortable reach) on
    which the robot stands clear of every floor item and other waypoint in ``avoid``; ties go to
    the lowest (x, y), which is the lowest cell index."""
    best: tuple[float, tuple[float, float]] | None = None
    for c in cells:
        d = math.dist(c, (x, y))
        if GRASP_MIN <= d <= GRASP_MAX and all(math.dist(c, a) >= CLEAR for a in avoid):
            key = (abs(d - GRASP_DIST), c)
            if best is None or key < best:
                best = key
    return None if best is None else best[1]


def _zone_counts(n: int) -> dict[str, int]:
    """Half on the floor, a third on the long table, the rest on the tall table (6/4/2 at 12)."""
    n_floor, n_long = (n + 1) // 2, n // 3
    return {"floor": n_floor, "long-table": n_long, "tall-table": n - n_floor - n_long}


def _closure(dist: Sequence[Sequence[float]]) -> list[list[float]]:
    """Floyd-Warshall: the cheapest chain of moves between every two waypoints."""
    d = [list(r) for r in dist]
    n = len(d)
    for k, i, j in itertools.product(range(n), repeat=3):
        if d[i][k] + d[k][j] < d[i][j]:
            d[i][j] = d[i][k] + d[k][j]
    return d


def _no_detour_pays(dist: Sequence[Sequence[float]], tolerance: float = 0.02) -> bool:
    """Every pair has a path no longer than any two-hop route (distances rounded to 1 cm)."""
    n = len(dist)
    return all(
        dist[i][j] <= dist[i][k] + dist[k][j] + tolerance for i, j, k in itertools.permutations(range(n), 3)
    )


@lru_cache(maxsize=32)
def build(seed: int, n_items: int = 12) -> Instance:
    """Place items, choose waypoints and compute all-pairs path lengths; deterministic in seed."""
    rng = np.random.default_rng(seed)
    room = _room()
    start = room.nearest_free(*ENTRANCE)
    reachable = room.free_cells(reachable_from=start)
    names, points = ["wp-entrance"], [start]
    for dep, (y, _cat) in DEPOSITS.items():
        names.append(f"wp-{dep}")
        points.append(room.nearest_free(DELIVERY_X, y, reachable_from=start))
    cats = [CATEGORIES[k % len(CATEGORIES)] for k in range(n_items)]
    cats = [cats[k] for k in rng.permutation(n_items)]
    items: list[tuple[str, str, str, float, float]] = []
    grasp: list[int] = []
    supports = [z for z, k in _zone_counts(n_items).items() for _ in range(k)]
    for k, support in enumerate(supports):
        (xa, xb), (ya, yb) = ZONES[support]
        for _attempt in range(10000):
            x, y = round(float(rng.uniform(xa, xb)), 3), round(float(rng.uniform(ya, yb)), 3)
            if any(math.dist((x, y), (o[3], o[4])) < ITEM_GAP for o in items):
                continue
            if support == "floor" and (
                any(b.clearance(x, y) < 0.05 for b in FURNITURE)  # not inside or under furniture
                or any(math.dist((x, y), p) < CLEAR for p in points)  # off waypoints
            ):
                continue
            floor = [(o[3], o[4]) for o in items if o[2] == "floor"]
            point = _grasp_point(x, y, reachable, floor + points)
            if point is not None:
                break
        else:
            raise RuntimeError(f"seed {seed}: no place for item {k + 1}")
        items.append((f"o{k + 1}", cats[k], support, x, y))
        names.append(f"wp-o{k + 1}")
        points.append(point)
        grasp.append(len(points) - 1)
    rows = [[math.inf if v is None else round(v, 2) for v in r] for r in room.path_lengths(points)]
    # Rounding to cents can make a chain of moves a cent cheaper than the direct one (about one
    # pair in eight); closing the rounded matrix restores the triangle inequality, so a plan
    # never detours through another waypoint to save a rounding cent.
    dist = tuple(tuple(round(v, 2) for v in r) for r in _closure(rows))
    xy = tuple((round(x, 3), round(y, 3)) for x, y in points)
    time = tuple(tuple(travel_time(v) for v in r) for r in dist)
    return Instance(tuple(names), xy, dist, time, tuple(items), tuple(grasp))


def travel_time(metres: float) -> float:
    """A move's seconds as tidy.pddl's problems state them (inf stays inf: no path)."""
    return math.inf if not math.isfinite(metres) else round(metres / SPEED + STOP_S, 2)


def generate(seed: int, n_items: int = 12) -> str:
    """The dialect problem text for ``domains/tidy.pddl`` (plain PDDL apart from real costs)."""
    inst = build(seed, n_items)
    wp, items = inst.waypoints, inst.items
    used = sorted({c for _, c in DEPOSITS.values()})
    lines = [
        f";; tidygen seed {seed}, {n_items} items: WRS tidy-up room, robot at the entrance.",
        ";; Travel times: shortest paths on a 5 cm grid, furniture inflated by 0.22 m, at 0.22 m/s",
        ";; plus a 0.8 s stop.",
        ";; Items (name category support x y):",
        *(f";;   {n} {c} {s} {x:.3f} {y:.3f}" for n, c, s, x, y in items),
        ";; Waypoints (name x y):",
        *(f";;   {n} {x:.3f} {y:.3f}" for n, (x, y) in zip(wp, inst.xy, strict=True)),
        f";; optimum (bench/tidygen.py --optimum): {optimum(seed, n_items):.2f}",
        f"(define (problem tidygen-{seed}-{n_items})",
        "  (:domain tidy)",
        "  (:objects",
        "    " + " ".join(wp) + " - waypoint",
        "    " + " ".join(n for n, *_ in items) + " - item",
        "    " + " ".join(DEPOSITS) + " - deposit",
        "    " + " ".join(used) + " - category)",
        "  (:init",
        "    (= (total-cost) 0)",
        "    (robot-at wp-entrance) (hand-empty)",
    ]
    if _no_detour_pays(inst.time):
        lines.append("    (shortest-paths)")  # tidy.pddl: moves go only where there is work
    for (name, cat, *_), g in zip(items, inst.grasp, strict=True):
        lines.append(f"    (item-at {name} {wp[g]}) (of-category {name} {cat})")
    for dep, (_y, cat) in DEPOSITS.items():
        lines.append(f"    (deposit-at {dep} wp-{dep}) (accepts {dep} {cat})")
    for a, b in itertools.permutations(range(len(wp)), 2):
        t = inst.time[a][b]
        if math.isfinite(t):
            lines.append(f"    (path {wp[a]} {wp[b]}) (= (travel-time {wp[a]} {wp[b]}) {t:.2f})")
    lines[-1] += ")"
    goal = " ".join(f"(tidied {n})" for n, *_ in items)
    lines += [f"  (:goal (and {goal}))", "  (:metric minimize (total-cost)))", ""]
    return "\n".join(lines)


def optimum(seed: int, n_items: int = 12, seconds: bool = True) -> float:
    """Exact optimal total-cost by DP over subsets (Held-Karp); ``seconds`` False: in metres.

    State: (set of tidied items, robot location), the location being the entrance at the start
    or the waypoint of the deposit last delivered to. The deposit is part of the state, not
    minimised greedily, because it fixes where the next leg starts. One step: move to an item's
    grasp waypoint, take, move to a deposit accepting its category, deliver. The hand
    holds one item, so every plan is such a sequence; moves cost the cheapest chain of moves.
    """
    inst = build(seed, n_items)
    # a no-op on build's matrices; kept so the DP relies on nothing else
    d = _closure(inst.time if seconds else inst.dist)
    take, deliver = (TAKE_S, DELIVER_S) if seconds else (1, 1)
    dep_wps = {name: inst.waypoints.index(f"wp-{name}") for name in DEPOSITS}
    choices = [[dep_wps[n] for n, (_y, c) in DEPOSITS.items() if c == cat] for _, cat, *_ in inst.items]
    layers: list[dict[int, float]] = [{} for _ in range(1 << n_items)]  # mask -> {loc: cost}
    layers[0][0] = 0.0  # waypoint 0 is the entrance
    for mask in range(1 << n_items):  # masks only grow, so increasing order is topological
        for loc, cost in layers[mask].items():
            for i in range(n_items):
                if mask >> i & 1:
                    continue
                g, nxt = inst.grasp[i], layers[mask | 1 << i]
                for w in choices[i]:
                    c = cost + d[loc][g] + take + d[g][w] + deliver
                    if c < nxt.get(w, math.inf):
                        nxt[w] = c
    return round(min(layers[-1].values()), 2)


def main() -> None:
    """Command line: write a problem, or print its optimum."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0, help="random seed (the problem is a function of it)")
    ap.add_argument("--items", type=int, default=12, help="number of items (12: the WRS task)")
    ap.add_argument("--out", help="write the problem here (default: stdout)")
    ap.add_argument("--optimum", action="store_true", help="print the optimal total-cost")
    args = ap.parse_args()
    if args.optimum:
        print(f"{optimum(args.seed, args.items):.2f}")
        return
    text = generate(args.seed, args.items)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text)
    else:
        print(text, end="")


if __name__ == "__main__":
    main()
