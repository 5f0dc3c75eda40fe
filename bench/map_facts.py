"""How long the map's facts take for a room with every item where the scenario puts it.

    python bench/map_facts.py SCENARIO [SCENARIO ...]

For each scenario: CPU seconds of ``RoomMap.facts`` with all items placed and the robot at the
entrance (the first call: every grid new), then again with one item gone and the robot 0.3 m
along (what a turn of the loop asks: the static grid's paths are remembered), and the size of
what was found (waypoints, blocked pairs, ``blocks`` facts). Bad files exit 2 with the loader's
message.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv: list[str]) -> int:
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load
    from tidyplan.belief.geometry import RoomMap
    from tidyplan.belief.mapfacts import Placed

    if not argv:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    for path in argv:
        try:
            scenario = load(path)
        except (OSError, ScenarioError) as e:
            print(e, file=sys.stderr)
            return 2
        room = RoomMap(scenario)
        items = [Placed(i.name, i.category, i.x, i.y, i.on, i.sx, i.sy) for i in scenario.items]
        t0 = time.process_time()
        facts = room.facts(items, ("wp-entrance", room.entrance))
        first = time.process_time() - t0
        moved = (room.entrance[0] - 0.3, room.entrance[1])
        t0 = time.process_time()
        room.facts(items[1:], ("wp-robot", moved))
        again = time.process_time() - t0
        print(
            f"{Path(path).name}: {len(items)} items; facts {first:.2f} s CPU, again {again:.2f} s;"
            f" {len(facts.points)} waypoints, {len(facts.blocked)} blocked pairs, {len(facts.blocks)} blocks"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
