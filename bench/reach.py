"""Where the HSR's hand reaches upright: distance out from the base's centre by height.

    python bench/reach.py [--step 0.05]

The simulated HSR (``sim/robot.py``) stands at the origin; for each height and distance the
hand is asked to a point straight ahead of the base (``HSR.reach``, ``strict``: the hand within
0.1 rad of the wanted orientation, turned any way about the vertical, the base turning in
place). Prints one table per orientation: the hand pointing down (the top grasp) and held level
(the side grasp of a tall object), pointing ahead and pointing sideways (as where the robot
faces a deposit but the object is held as it was taken, from another side), "#" where the hand
comes within 2 cm of the point.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv: list[str]) -> int:
    import pybullet as p

    from sim.robot import HAND_DOWN, HSR, REACHED, hand_level

    ap = argparse.ArgumentParser(prog="bench/reach.py", description=__doc__.strip().splitlines()[0])
    ap.add_argument("--step", type=float, default=0.05, help="m between the distances (default 0.05)")
    args = ap.parse_args(argv)
    if not 0.01 <= args.step <= 0.2:
        ap.error("--step must be between 0.01 and 0.2")
    client = p.connect(p.DIRECT)
    try:
        hsr = HSR(client)
        distances = [round(0.3 + k * args.step, 3) for k in range(int(0.6 / args.step) + 1)]
        heights = [0.1, 0.2, 0.3, 0.4, 0.5, 0.65, 0.8, 0.95, 1.1]
        tables = (
            ("hand pointing down", HAND_DOWN),
            ("hand level", hand_level(0.0)),
            ("hand level, pointing 90 degrees from the base's heading", hand_level(math.pi / 2)),
        )
        for title, orientation in tables:
            print(f"{title}: distance out (m) by height (m); # = reached within {REACHED} m")
            print("height  " + " ".join(f"{d:4.2f}" for d in distances))
            for z in reversed(heights):
                row = []
                for d in distances:
                    _, err = hsr.reach((d, 0.0, z), orientation, strict=True)
                    row.append("   #" if err <= REACHED else "   .")
                print(f"{z:5.2f}  " + " ".join(row))
            print()
    finally:
        p.disconnect(client)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
