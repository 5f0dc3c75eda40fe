"""A campaign of missions: the grid of every combination, and the table its rows go to.

A mission's configuration (``MissionConfig``) is the row's key: running the same sweep again
skips every configuration the table already has. The table is ``DIR/results.jsonl``, one row a
line, appended (flushed and synced) as each mission ends, so a killed sweep loses at most the
missions then running; ``DIR/results.csv`` is rewritten from it (temp file, rename) each time.
The engines that run the missions are in ``missions.py``; the summary by condition in
``report.py``.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import tempfile
from dataclasses import asdict, fields
from pathlib import Path

from tidyplan.errors import InputError
from tidyplan.sweep.config import MissionConfig
from tidyplan.worlds.rates import Rates

RESULTS = "results.jsonl"
RESULTS_CSV = "results.csv"
TRACES = "traces"


CONFIG_FIELDS = [f.name for f in fields(MissionConfig)]


def parse_seeds(text: str) -> list[int]:
    """``A-B`` (both included), ``N``, or a comma list of either."""
    seeds: list[int] = []
    for part in filter(None, (p.strip() for p in text.split(","))):
        first, sep, last = part.partition("-")
        try:
            a, b = int(first), int(last) if sep else int(first)
        except ValueError:
            raise InputError(f"--seeds: {part!r} is not A-B or a whole number") from None
        if a < 0 or b < a:
            raise InputError(f"--seeds: {part!r} is not a range A-B with 0 <= A <= B")
        seeds += [s for s in range(a, b + 1) if s not in seeds]
    if not seeds:
        raise InputError("--seeds: no seed given")
    return seeds


def canonical_faults(text: str) -> str:
    """One fault condition as a key: parts stripped and sorted, checked by ``Rates.parse``."""
    text = "" if text.strip().lower() == "none" else text
    Rates.parse(text, "--faults")  # InputError for an unknown fault or a bad rate
    return ",".join(sorted(p.strip() for p in text.split(",") if p.strip()))


def grid(scenarios, seeds, strategies, fault_sets, planners, world, **fixed) -> list[MissionConfig]:
    """Every combination, in a stable order (scenario, strategy, faults, planner, seed)."""
    return [
        MissionConfig(str(Path(s).resolve()), seed, strategy, faults, planner, world, **fixed)
        for s in scenarios
        for strategy in strategies
        for faults in fault_sets
        for planner in planners
        for seed in seeds
    ]


# ------------------------------------------------------------------ the table
class Table:
    """``DIR/results.jsonl`` and its CSV copy. Rows are dicts: the configuration's fields,
    ``status`` (``done``, ``crashed``, ``timeout``), ``error``, the mission's summary fields."""

    def __init__(self, folder: str | Path, warn=None) -> None:
        self.folder = Path(folder)
        self.path = self.folder / RESULTS
        self.warn = warn or (lambda message: None)
        self.rows: list[dict] = self._read()

    def _read(self) -> list[dict]:
        if not self.path.exists():
            return []
        rows = []
        text = self.path.read_text(errors="replace")
        for n, line in enumerate(text.splitlines(), 1):
            if not line.strip():
                continue
            try:
                rows.append(json.loads(line))
            except json.JSONDecodeError:
                self.warn(f"{self.path}:{n}: a row cut short (a killed sweep?): ignored")
        return rows

    def done(self) -> set[str]:
        return {MissionConfig.from_row(r).key for r in self.rows}

    def open_for_append(self) -> None:
        """Cut a last line left unfinished by a killed sweep, so new rows start on their own line."""
        self.folder.mkdir(parents=True, exist_ok=True)
        if not self.path.exists():
            return
        data = self.path.read_bytes()
        if data and not data.endswith(b"\n"):
            keep = data.rfind(b"\n") + 1
            self.warn(f"{self.path}: removed a last row cut short ({len(data) - keep} bytes)")
            with open(self.path, "r+b") as f:
                f.truncate(keep)
                os.fsync(f.fileno())

    def append(self, row: dict) -> None:
        with open(self.path, "a") as f:
            f.write(json.dumps(row, sort_keys=False) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.rows.append(row)
        self.write_csv()

    def write_csv(self) -> None:
        flat = [_flatten(r) for r in self.rows]
        columns = list(dict.fromkeys(c for r in [dict.fromkeys(CONFIG_FIELDS), *flat] for c in r))
        out = io.StringIO()
        writer = csv.DictWriter(out, columns, restval="", lineterminator="\n")
        writer.writeheader()
        writer.writerows(flat)
        write_atomically(self.folder / RESULTS_CSV, out.getvalue())


def _flatten(row: dict) -> dict:
    """Dicts one level down become ``key.sub`` columns; lists are written as JSON."""
    out: dict = {}
    for key, value in row.items():
        if isinstance(value, dict):
            for sub, v in value.items():
                out[f"{key}.{sub}"] = v
        elif isinstance(value, list):
            out[key] = json.dumps(value)
        else:
            out[key] = value
    return out


def write_atomically(path: Path, text: str) -> None:
    """Beside the target under a fresh name, then renamed: a reader never sees half a file."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def fresh_trace(folder: Path, config: MissionConfig) -> Path:
    """A trace path under ``folder/traces`` that no file has (a killed attempt's stays)."""
    base = folder / TRACES / config.trace_stem()
    path, n = base.with_suffix(".jsonl"), 1
    while path.exists() or path.with_suffix(".pddl").exists():
        n += 1
        path = base.parent / f"{base.name}-{n}.jsonl"
    return path


# ------------------------------------------------------------------ the campaign
def run_sweep(
    configs: list[MissionConfig],
    folder: str | Path,
    *,
    jobs: int = 1,
    ray: bool = False,
    address: str | None = None,
    limit: float = 600.0,
    target: str | None = None,
    warn=None,
    on_row=None,
    progress: bool = False,
) -> list[dict]:
    """Run the configurations the table in ``folder`` does not have yet, appending a row as each
    ends; returns the grid's rows (those found and those run), in the grid's order. ``limit``:
    wall seconds a mission may take before it is killed (a ``timeout`` row)."""
    from tidyplan.sweep import missions as sweep_run

    folder = Path(folder).resolve()
    table = Table(folder, warn)
    done = table.done()
    todo = [c for c in dict.fromkeys(configs) if c.key not in done]
    table.open_for_append()
    (folder / TRACES).mkdir(exist_ok=True)
    work = [{"config": asdict(c), "trace": str(fresh_trace(folder, c))} for c in todo]

    bar = _Bar(len(work), len(configs) - len(todo)) if progress and work else None

    def record(job: dict, outcome: dict) -> None:
        row = {**job["config"], "status": outcome.get("status", "crashed"), "error": outcome.get("error")}
        row.update({k: v for k, v in outcome.items() if k not in row and k not in CONFIG_FIELDS})
        row.setdefault("trace", job["trace"] if Path(job["trace"]).exists() else None)
        table.append(row)
        if bar is not None:
            bar.advance(row)
        if on_row is not None:
            on_row(row)

    engine_target = target or sweep_run.MISSION
    try:
        if ray:
            sweep_run.run_ray(work, address, jobs, limit, record, engine_target)
        else:
            sweep_run.run_local(work, jobs, limit, record, engine_target)
    finally:
        if bar is not None:
            bar.close()
    by_key = {MissionConfig.from_row(r).key: r for r in table.rows}
    return [by_key[c.key] for c in dict.fromkeys(configs) if c.key in by_key]


class _Bar:
    """rich's progress bar on stderr: missions ended, how many failed, time left."""

    def __init__(self, total: int, skipped: int) -> None:
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

        self.failed = 0
        self.progress = Progress(
            TextColumn("missions"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("{task.fields[note]}"),
            TimeRemainingColumn(),
            console=Console(stderr=True),
        )
        self.progress.start()
        note = f"({skipped} already in the table)" if skipped else ""
        self.task = self.progress.add_task("sweep", total=total, note=note)

    def advance(self, row: dict) -> None:
        self.failed += row["status"] != "done" or not row.get("success")
        self.progress.update(self.task, advance=1, note=f"{self.failed} not tidied")

    def close(self) -> None:
        self.progress.stop()
