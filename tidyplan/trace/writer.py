"""The trace: one JSON object a line, flushed as written, so a killed run leaves a readable file.

A trace that cannot be written (a full disk, most often) ends the run with ``TraceWriteError``:
one line naming the trace and the system's reason, the file kept as it is. Each line goes to
the file in one unbuffered write, so nothing of a failed line waits in a buffer to be written
later: the file ends with whole events, or with part of the line that failed, which the
reader drops (tidyplan.trace.read).

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

from tidyplan.errors import Diagnostic, InputError
from tidyplan.pddl import model as m
from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.writer import domain_text, problem_text
from tidyplan.trace.events import SCHEMA_VERSION


class TraceWriteError(InputError):
    """The trace (or a PDDL file beside it) could not be written: exit status 2, as for any file
    the user named that cannot be used. ``last_seq``: the last event wholly in the file."""

    def __init__(self, path: Path, err: OSError, last_seq: int | None) -> None:
        self.path, self.errno, self.last_seq = path, err.errno, last_seq
        reason = (err.strerror or str(err)).strip()
        reason = reason[:1].lower() + reason[1:]  # "no space left on device", inside a sentence
        kept = (
            f"it is kept, readable up to its last whole event (seq {last_seq})"
            if last_seq is not None
            else "it holds no event"
        )
        where = f" ({err.filename})" if err.filename and Path(err.filename) != path else ""
        what = f"cannot write the trace{where}: {reason}; {kept}"
        super().__init__(Diagnostic(str(path), None, None, what))


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
        self.pddl_dir = self.path.with_name(self.path.stem + ".pddl")
        self._written: int | None = None  # seq of the last event wholly in the file
        self._failed: TraceWriteError | None = None
        # Never overwrite: a trace, or the PDDL folder of one, that exists is someone's run.
        # Unbuffered: each event is one write of its whole line (see _record).
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._file = open(self.path, "xb", buffering=0)  # noqa: SIM115 - closed in close()
        except OSError as err:
            if isinstance(err, FileExistsError):
                raise
            raise TraceWriteError(self.path, err, None) from None
        try:
            self.pddl_dir.mkdir()
        except FileExistsError:
            self._file.close()
            self.path.unlink()
            raise
        except OSError as err:
            self._file.close()
            raise TraceWriteError(self.path, err, None) from None

    def _record(self, event: dict) -> None:
        if self._failed is not None:  # once failed, every later event fails alike: none is lost quietly
            raise self._failed
        data = memoryview((json.dumps(event, separators=(",", ":")) + "\n").encode("utf-8"))
        try:
            while data:  # a raw write may take part of the line; the rest follows
                data = data[self._file.write(data) :]
        except OSError as err:
            self._fail(err)
        self._written = event["seq"]

    def _fail(self, err: OSError):
        self._failed = TraceWriteError(self.path, err, self._written)
        raise self._failed from None

    def save(self, name: str, text: str) -> str:
        """Write a file into the PDDL folder; returns its path relative to the trace's folder."""
        if self._failed is not None:
            raise self._failed
        target = self.pddl_dir / name
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text, encoding="utf-8")
        except OSError as err:
            self._fail(err)
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
        except TraceWriteError:
            raise  # a full disk ends the run, not only the copy
        except Exception as err:  # noqa: BLE001 - a plain copy is a convenience; the plan goes on
            out["plain_error"] = str(err)
        return out

    def close(self) -> None:
        if not self._file.closed:
            self._file.close()
