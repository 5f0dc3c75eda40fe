"""The trace: one JSON object a line, flushed as written, so a killed run leaves a readable file.

Every event has ``v`` (schema version), ``kind``, ``seq`` (0, 1, 2, ...), ``wall_s`` (seconds
since the run began) and ``sim_s`` (the world's simulated clock). The kinds and their fields
are documented in docs/trace.md; a reader skips kinds it does not know.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any

from tidyplan.pddl import model as m
from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.writer import domain_text, problem_text
from tidyplan.trace.events import SCHEMA_VERSION


class NoTrace:
    """The events of a run that writes no trace (``tidyplan.run(..., trace=None)``): each goes
    to the listener only, and no PDDL is saved. ``TraceWriter`` writes them too."""

    path: Path | None = None

    def __init__(self, clock=lambda: 0.0) -> None:
        self._seq = 0
        self._start = time.perf_counter()
        self._clock = clock
        self.listener = None  # called with each event, e.g. to show progress

    def emit(self, kind: str, **fields: Any) -> dict:
        event = {
            "v": SCHEMA_VERSION,
            "seq": self._seq,
            "kind": kind,
            "wall_s": round(time.perf_counter() - self._start, 3),
            "sim_s": round(self._clock(), 2),
            **fields,
        }
        self._seq += 1
        self._record(event)
        if self.listener is not None:
            self.listener(event)
        return event

    def now(self) -> float:
        """The simulated clock the events are stamped with (``sim_s``)."""
        return self._clock()

    def _record(self, event: dict) -> None:
        pass

    def save(self, name: str, text: str) -> str | None:
        return None

    def save_replan(
        self, base: str, text: str, domain: m.Domain, problem: m.Problem, task=None
    ) -> dict[str, str]:
        return {}

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class TraceWriter(NoTrace):
    """Append events to a JSON-lines file; the folder beside it holds the PDDL of every plan."""

    def __init__(self, path: str | os.PathLike, clock=lambda: 0.0) -> None:
        super().__init__(clock)
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.pddl_dir = self.path.with_name(self.path.stem + ".pddl")
        # Never overwrite: a trace, or the PDDL folder of one, that exists is someone's run.
        self._file = open(self.path, "x", encoding="utf-8")  # noqa: SIM115 - closed in close()
        try:
            self.pddl_dir.mkdir()
        except FileExistsError:
            self._file.close()
            self.path.unlink()
            raise

    def _record(self, event: dict) -> None:
        self._file.write(json.dumps(event, separators=(",", ":")) + "\n")
        self._file.flush()

    def save(self, name: str, text: str) -> str:
        """Write a file into the PDDL folder; returns its path relative to the trace's folder."""
        target = self.pddl_dir / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
        return os.path.relpath(target, self.path.parent)

    def save_replan(
        self, base: str, text: str, domain: m.Domain, problem: m.Problem, task=None
    ) -> dict[str, str]:
        """The files of one plan: the dialect problem ``text`` as ``base.pddl``, and the plain
        PDDL the compiler makes of it in ``base/`` (``task``: the planner's compilation of it, if
        it has one); returns the ``plan`` event's path fields."""
        out = {"problem": self.save(f"{base}.pddl", text)}
        try:
            task = task or compile_task(domain, problem)
            out["plain_domain"] = self.save(f"{base}/domain.pddl", domain_text(task.domain))
            out["plain_problem"] = self.save(f"{base}/problem.pddl", problem_text(task.problem))
        except Exception as err:  # noqa: BLE001 - a plain copy is a convenience; the plan goes on
            out["plain_error"] = str(err)
        return out

    def close(self) -> None:
        if not self._file.closed:
            self._file.close()
