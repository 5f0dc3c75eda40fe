"""Seeded tidy-up problems for ``domains/tidy-rooms.pddl``: bench/tidygen.py's rooms in other words.

    python bench/tidygen_rooms.py [--seed 0] [--items 12] [--out FILE]

The room, the items, their grasp waypoints and the path lengths are ``tidygen.build(seed)``'s,
unchanged; only the words differ. tidygen's waypoints become places (``p-entrance``,
``p-tray-a``, ``p-i3``), its items ``i1`` ... ``i12``, its deposits bins of the same names. An
item's category becomes the bins it belongs in (``belongs``: every deposit accepting that
category), so the problem has no categories. Every move is open: ``connected`` for every
ordered pair of places with a path, at its length (2 decimals); nothing like tidy.pddl's
``(shortest-paths)``. The cost model is tidygen's (move = path length, pick 1, store 1), so
``tidygen.optimum(seed, seconds=False)`` is this problem's optimum too (in metres).
"""

from __future__ import annotations

import argparse
import itertools
import math
from pathlib import Path

from tidyplan.generate import tasks as tidygen  # noqa: E402


def _place(waypoint: str) -> str:
    """tidygen's waypoint name as a place: wp-entrance -> p-entrance, wp-o3 -> p-i3."""
    rest = waypoint.removeprefix("wp-")
    if rest.startswith("o") and rest[1:].isdigit():
        rest = "i" + rest[1:]
    return "p-" + rest


def generate(seed: int, n_items: int = 12) -> str:
    """The problem text for ``domains/tidy-rooms.pddl`` of tidygen's room ``seed``."""
    inst = tidygen.build(seed, n_items)
    places = [_place(w) for w in inst.waypoints]
    items = [(f"i{k + 1}", cat) for k, (_name, cat, *_rest) in enumerate(inst.items)]
    lines = [
        f";; tidygen_rooms seed {seed}, {n_items} items, for tidy-rooms.pddl: tidygen's room {seed}",
        ";; (bench/tidygen.py) in other words; every move open. Items (name tidygen-name category):",
        *(f";;   {n} {o[0]} {c}" for (n, c), o in zip(items, inst.items, strict=True)),
        f"(define (problem tidy-rooms-{seed}-{n_items})",
        "  (:domain tidy-rooms)",
        "  (:objects",
        "    " + " ".join(places) + " - place",
        "    " + " ".join(n for n, _ in items) + " - item",
        "    " + " ".join(tidygen.DEPOSITS) + " - bin)",
        "  (:init",
        "    (= (total-cost) 0)",
        f"    (at-robot {places[0]}) (free-hand)",
    ]
    for (name, cat), g in zip(items, inst.grasp, strict=True):
        bins = [b for b, (_y, accepted) in tidygen.DEPOSITS.items() if accepted == cat]
        lines.append(f"    (on {name} {places[g]})" + "".join(f" (belongs {name} {b})" for b in bins))
    for b in tidygen.DEPOSITS:
        lines.append(f"    (bin-at {b} {places[inst.waypoints.index(f'wp-{b}')]})")
    for a, b in itertools.permutations(range(len(places)), 2):
        d = inst.dist[a][b]
        if math.isfinite(d):
            lines.append(
                f"    (connected {places[a]} {places[b]}) (= (travel-cost {places[a]} {places[b]}) {d:.2f})"
            )
    lines[-1] += ")"
    goal = " ".join(f"(stored {n})" for n, _ in items)
    lines += [f"  (:goal (and {goal}))", "  (:metric minimize (total-cost)))", ""]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0, help="tidygen's seed (the same room and items)")
    ap.add_argument("--items", type=int, default=12, help="number of items (12: the WRS task)")
    ap.add_argument("--out", help="write the problem here (default: stdout)")
    args = ap.parse_args()
    text = generate(args.seed, args.items)
    if args.out:
        Path(args.out).write_text(text, encoding="utf-8")
    else:
        print(text, end="")


if __name__ == "__main__":
    main()
