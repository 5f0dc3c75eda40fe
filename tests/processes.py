"""The processes a test started, and only those.

The test process is made a child subreaper (Linux ``prctl``), so a process its children leave
behind (a Fast Downward search, a mission under a killed sweep) is re-parented to it instead of
to init. Every process a test started is then a descendant of the test process, found by following
parent links from it: nothing else on the machine (a benchmark beside the tests, a second clone's
tests) is ever counted.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
from pathlib import Path

PR_SET_CHILD_SUBREAPER = 36


def become_subreaper() -> None:
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)


def _parents_and_states() -> dict[int, tuple[int, str]]:
    out = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError, ValueError, IndexError):
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
                out[int(entry.name)] = (int(fields[1]), fields[0])
    return out


def descendants(marker: bytes = b"") -> set[int]:
    """Running (not zombie) descendants of this process whose command line holds ``marker``."""
    table = _parents_and_states()
    children: dict[int, list[int]] = {}
    for pid, (ppid, _) in table.items():
        children.setdefault(ppid, []).append(pid)
    found, todo = set(), [os.getpid()]
    while todo:
        for child in children.get(todo.pop(), []):
            todo.append(child)
            if table[child][1] == "Z":
                continue
            with contextlib.suppress(OSError):
                if marker in (Path("/proc") / str(child) / "cmdline").read_bytes():
                    found.add(child)
    return found


def still_running_after(pids: set[int], timeout: float = 30.0) -> set[int]:
    """Wait (on each process itself, through a pidfd) until ``pids`` have ended; those still
    running after ``timeout`` seconds. A process that is being stopped (SIGTERM on its parent's
    death, say) ends in milliseconds; one left behind never does."""
    import select
    import time

    left, deadline = set(), time.monotonic() + timeout
    for pid in pids:
        try:
            fd = os.pidfd_open(pid)
        except ProcessLookupError:
            continue  # already gone
        try:
            if not select.select([fd], [], [], max(0.0, deadline - time.monotonic()))[0]:
                left.add(pid)
        finally:
            os.close(fd)
    return left
