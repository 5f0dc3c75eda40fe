"""How often putting objects into the deposits leaves one outside, in the pybullet world.

    python bench/fill.py SCENARIO [SCENARIO ...] [--turns 2] [--deposits NAME,...]

For each scenario and each deposit: the deposit is filled with the scenario's objects of its
category in every order, each object first standing on open floor at a random turn about the
vertical (``--turns`` draws per order, seeded 0, 1, ...), taken from there and put in from the
deposit's approach pose, the other objects taken out of the room; no injected faults (every
grasp and release succeeds). Prints each filling that left an object outside its deposit (with
the failures of the puts), then per scenario the count of such fillings. Bad files or options
exit 2.
"""

from __future__ import annotations

import argparse
import itertools
import math
import random
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

FLOOR = (-1.4, 0.3)  # where the robot stands to take each object: open floor in the WRS rooms
TAKE = 0.55  # m in front of it, where the object stands


def fill(scenario, room, deposit, order, rnd) -> tuple[list, list[str]]:
    """One filling: the failures of each put, and the objects left outside the deposit."""
    import pybullet as p

    from sim.motion import settle
    from tidyplan.worlds.pybullet.world import BulletWorld
    from tidyplan.worlds.rates import Rates

    w = BulletWorld(
        scenario, room, seed=0, rates=Rates(1.0, 1.0, 1.0, false_negative=0.0, false_positive=0.0)
    )
    puts_away: list[str] = []
    try:
        # the other objects out of the way: in a mission the robot has cleared the way to the
        # deposit (case III's food box stands in the bin's corridor) and the deposit is its own
        for name, item in w.items.items():
            if name not in order:
                away = (50.0 + 2 * len(puts_away), 50.0, item.sz / 2)
                p.resetBasePositionAndOrientation(
                    w.bodies[name], away, (0, 0, 0, 1), physicsClientId=w.client
                )
                w._sync(name)
                puts_away.append(name)
        puts = []
        for name in order:
            item, body = w.items[name], w.bodies[name]
            w.hsr.set_base(*FLOOR, 0.0)
            w.robot = FLOOR
            turn = p.getQuaternionFromEuler((0, 0, rnd.uniform(-math.pi, math.pi)))
            at = (FLOOR[0] + TAKE, FLOOR[1], item.sz / 2 + 0.001)
            p.resetBasePositionAndOrientation(body, at, turn, physicsClientId=w.client)
            settle(w.hsr, 0.5)
            w._sync(name)
            out = w.grasp((w.items[name].x, w.items[name].y))
            w.hsr.set_base(*deposit.approach, math.pi)
            w.robot = deposit.approach
            if out.ok:
                out = w.place(deposit.name, deposit.approach)
            puts.append((name, out.failure))
        return puts, [n for n in order if w.items[n].state != "tidied"]
    finally:
        w.close()


def main(argv: list[str]) -> int:
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load
    from tidyplan.belief.geometry import RoomMap

    ap = argparse.ArgumentParser(prog="bench/fill.py", description=__doc__.strip().splitlines()[0])
    ap.add_argument("scenarios", nargs="+", metavar="SCENARIO")
    ap.add_argument("--turns", type=int, default=2, help="random turns of the objects per order (default 2)")
    ap.add_argument("--deposits", help="only these deposits (comma-separated names)")
    args = ap.parse_args(argv)
    if args.turns < 1:
        ap.error("--turns must be at least 1")
    for path in args.scenarios:
        try:
            scenario = load(path)
        except (OSError, ScenarioError) as e:
            print(f"{path}: {e}", file=sys.stderr)
            return 2
        room = RoomMap(scenario)
        bad = total = 0
        for d in scenario.deposits:
            if d.approach is None or (args.deposits and d.name not in args.deposits.split(",")):
                continue
            names = [i.name for i in scenario.items if i.category == d.category]
            for seed in range(args.turns):
                rnd = random.Random(seed)
                for order in itertools.permutations(names):
                    puts, outside = fill(scenario, room, d, order, rnd)
                    total += 1
                    if outside:
                        bad += 1
                        print(
                            f"{d.name} turns {seed} {' '.join(order)}: {puts} -> outside {outside}",
                            flush=True,
                        )
        print(f"{path}: {bad} of {total} fillings left an object outside its deposit")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
