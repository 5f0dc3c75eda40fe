"""Whole-process time of `tidyplan check` against unified-planning's PDDLReader.

    python bench/parse_speed.py [--repeat N] [DOMAIN PROBLEM]

Defaults to the corpus's nomystery p01 (110 KB, 3,700 init facts), the
largest file there. Each side is a fresh Python process that imports what it
needs and reads the pair; the figure is the median wall time of N runs.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CORPUS = Path(os.environ.get("TIDYPLAN_PDDL_CORPUS", ROOT.parent / "shared" / "pddl-corpus"))

UP_READ = (
    "import sys\n"
    "from unified_planning.io import PDDLReader\n"
    "PDDLReader().parse_problem(sys.argv[1], sys.argv[2])\n"
)


def _median_seconds(cmd: list[str], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("domain", nargs="?", default=str(CORPUS / "nomystery-sat11-strips" / "domain.pddl"))
    ap.add_argument("problem", nargs="?", default=str(CORPUS / "nomystery-sat11-strips" / "p01.pddl"))
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    if not Path(args.problem).exists():
        sys.exit(f"{args.problem}: no such file (set TIDYPLAN_PDDL_CORPUS)")
    tidyplan = [sys.executable, "-m", "tidyplan", "check", args.domain, args.problem]
    up = [sys.executable, "-c", UP_READ, args.domain, args.problem]
    _median_seconds(tidyplan, 1)  # warm the grammar cache and the file cache
    ours = _median_seconds(tidyplan, args.repeat)
    theirs = _median_seconds(up, args.repeat)
    print(f"file: {args.problem}")
    print(f"tidyplan check:          {ours:6.2f} s (median of {args.repeat})")
    print(f"unified-planning reader: {theirs:6.2f} s (median of {args.repeat})")
    print(f"ratio: {ours / theirs:.3f} (goal: at most 0.25)")


if __name__ == "__main__":
    main()
