"""A full disk while a trace is written: one clear error, and the trace kept up to its last whole event.

The disk is simulated: the writer's file takes N events, then part of the next line, then
raises ENOSPC as a full file system does (a real small tmpfs needs root to mount). The mission
runs in the symbolic world with a deterministic planner.
"""

from __future__ import annotations

import errno
import json
import os
from pathlib import Path

import pytest

from tidyplan.cli.main import main
from tidyplan.trace import writer as trace_writer
from tidyplan.trace.read import read_trace
from tidyplan.trace.writer import TraceWriteError, TraceWriter

MESSAGE = "cannot write the trace: no space left on device; it is kept, readable up to its last whole event"


class FullDisk:
    """A raw file that holds ``room`` events' lines, then takes ``partial`` bytes of the next
    one and raises ENOSPC for that write and every write after it."""

    def __init__(self, raw, room: int, partial: int = 17) -> None:
        self.raw, self.room, self.partial, self.lines = raw, room, partial, 0

    def write(self, data) -> int:
        if self.lines >= self.room:
            if self.partial:
                taken, self.partial = self.raw.write(bytes(data[: self.partial])), 0
                if taken:  # a short write, as the kernel gives when the last blocks fill
                    return taken
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        self.lines += bytes(data).count(b"\n")
        return self.raw.write(data)

    @property
    def closed(self) -> bool:
        return self.raw.closed

    def close(self) -> None:
        self.raw.close()


def _fill_after(monkeypatch, room: int) -> None:
    """Every TraceWriter made from here on writes to a disk with room for ``room`` events."""
    made = TraceWriter.__init__

    def init(self, *args, **kwargs):
        made(self, *args, **kwargs)
        self._file = FullDisk(self._file, room)

    monkeypatch.setattr(trace_writer.TraceWriter, "__init__", init)


def test_the_writer_fails_once_and_keeps_every_whole_event(tmp_path, monkeypatch):
    _fill_after(monkeypatch, 3)
    path = tmp_path / "t.jsonl"
    with TraceWriter(path) as trace:
        trace.emit("start", scenario="x")
        trace.emit("observe", new=[])
        trace.emit("observe", new=["a"])
        with pytest.raises(TraceWriteError) as failed:
            trace.emit("observe", new=["b"] * 20)
        # later events fail alike (none is dropped quietly), and so does a PDDL file
        with pytest.raises(TraceWriteError):
            trace.emit("observe", new=[])
        with pytest.raises(TraceWriteError):
            trace.save("domain.pddl", "(define)")
    assert failed.value.last_seq == 2
    assert failed.value.errno == errno.ENOSPC
    assert str(failed.value) == f"{path}: {MESSAGE} (seq 2)"
    lines = path.read_bytes().split(b"\n")
    assert len(lines) == 4 and len(lines[3]) == 17  # three whole events, then part of the fourth
    read = read_trace(path)
    assert [e["seq"] for e in read.events] == [0, 1, 2] and read.truncated
    assert not (tmp_path / "t.pddl" / "domain.pddl").exists()


def test_a_full_disk_mid_mission_is_one_line_exit_2_and_a_readable_trace(tmp_path, monkeypatch, capsys):
    _fill_after(monkeypatch, 25)
    path = tmp_path / "run.jsonl"
    args = ["run", "case1", "--world", "symbolic", "--seed", "0", "--planner", "lama-first", "--quiet"]
    status = main([*args, "--trace", str(path)])
    out, err = capsys.readouterr()
    assert status == 2
    assert err == f"{path}: {MESSAGE} (seq 24)\n"
    assert "Traceback" not in out + err
    assert not path.with_suffix(".traceback.txt").exists()

    whole = [json.loads(line) for line in path.read_text().split("\n")[:-1]]
    assert [e["seq"] for e in whole] == list(range(25))
    assert main(["trace", str(path), "--json"]) == 0
    out, err = capsys.readouterr()
    story = json.loads(out)
    assert story["complete"] is False and story["scenario"] == "case1"
    cut = "warning: cut off mid-line (a killed run?): read up to its last whole event, seq 24"
    assert f"{path}: {cut}" in err


def test_a_full_disk_while_saving_a_plans_pddl_names_the_file(tmp_path, monkeypatch, capsys):
    path = tmp_path / "run.jsonl"
    pddl = path.with_suffix(".pddl")
    write_text = Path.write_text

    def full(self, *args, **kwargs):
        if self.parent == pddl and self.name.startswith("replan-"):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(self))
        return write_text(self, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", full)
    args = ["run", "case1", "--world", "symbolic", "--seed", "0", "--planner", "lama-first", "--quiet"]
    assert main([*args, "--trace", str(path)]) == 2
    _, err = capsys.readouterr()
    first = pddl / "replan-000.pddl"
    assert err.startswith(f"{path}: cannot write the trace ({first}): no space left on device; it is kept")
    assert len(err.splitlines()) == 1
    read = read_trace(path)  # every event written is whole: the failure came between two
    assert not read.truncated and read.events[0]["kind"] == "start"
    assert read.of("plan") == []  # the plan whose problem could not be saved was not written
