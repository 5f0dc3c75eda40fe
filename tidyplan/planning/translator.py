"""Fast Downward's translator in a child process, so that a time limit holds through translation.

The translator is Python and cannot be stopped from inside the process that runs it: on a task
with a huge grounding (IPC 2023's labyrinth) it ran for minutes past a 10 s first-plan limit.
Here it runs in a worker process (`python -m tidyplan.planning.translator`), started once and
kept for the process's later calls (an interpreter and the translator's import cost 0.2-0.3 s,
paid once, and `warm()` starts it while our own reading and compiling run). A translation
that reaches its deadline kills the worker; the next call starts another.

No worker outlives its parent: it is started with the parent-death signal (SIGKILL, Linux's
`PR_SET_PDEATHSIG`), ends when its input closes, and is killed at exit. The signal comes when the
*thread* that forked the worker ends (prctl(2)), so workers are forked by the main thread or by
one thread kept for the purpose (`_spawn`): forked by a request thread of `tidyplan serve`, the
shared worker was killed when that request ended, perhaps inside the next request's translation.

The protocol is one line each way: the parent writes a folder holding `domain.pddl` and
`problem.pddl`; the worker writes `output.sas` there and answers `ok`, or `error <message>`.
"""

from __future__ import annotations

import atexit
import contextlib
import ctypes
import os
import queue
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time

from tidyplan.errors import PlannerError

PR_SET_PDEATHSIG = 1


def _die_with_parent() -> None:  # runs in the child between fork and exec
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)


_spawns: queue.Queue = queue.Queue()
_spawner: threading.Thread | None = None
_spawner_lock = threading.Lock()


def _spawn(command: list[str], **options) -> subprocess.Popen:
    """``subprocess.Popen`` from a thread that lives as long as the process (the main thread, or
    a daemon thread started once), so the parent-death signal means the process's death."""
    global _spawner
    if threading.current_thread() is threading.main_thread():
        return subprocess.Popen(command, **options)
    with _spawner_lock:
        if _spawner is None:
            _spawner = threading.Thread(target=_spawn_loop, name="tidyplan-translator-spawner", daemon=True)
            _spawner.start()
    answer: queue.Queue = queue.Queue(maxsize=1)
    _spawns.put((command, options, answer))
    started, value = answer.get()
    if not started:
        raise value
    return value


def _spawn_loop() -> None:
    while True:
        command, options, answer = _spawns.get()
        try:
            answer.put((True, subprocess.Popen(command, **options)))
        except BaseException as e:  # noqa: BLE001 - raised in the thread that asked
            answer.put((False, e))


class OutOfTime(Exception):
    """The translation reached its deadline (the worker was killed)."""


class Worker:
    """One translator process, used one translation at a time."""

    def __init__(self) -> None:
        self.process: subprocess.Popen | None = None

    def start(self) -> None:
        if self.process is not None and self.process.poll() is None:
            return
        self.stop()  # one that ended (killed at a deadline, or it crashed): its pipes
        self.process = _spawn(
            [sys.executable, "-m", "tidyplan.planning.translator"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            preexec_fn=_die_with_parent,  # noqa: PLW1509 - prctl only, no locks taken
            start_new_session=True,  # an interrupt at the terminal is the parent's to handle
        )

    def translate(self, domain_text: str, problem_text: str, deadline: float) -> str:
        """The SAS task's text; raises OutOfTime at `deadline` (a time.perf_counter() time)."""
        with tempfile.TemporaryDirectory(prefix="tidyplan-translate-") as tmp:
            for name, text in (("domain.pddl", domain_text), ("problem.pddl", problem_text)):
                with open(os.path.join(tmp, name), "w", encoding="utf-8") as f:
                    f.write(text)
            if time.perf_counter() >= deadline:
                raise OutOfTime
            self.start()
            assert self.process is not None and self.process.stdin and self.process.stdout
            try:
                self.process.stdin.write((tmp + "\n").encode())
                self.process.stdin.flush()
                reply = self._reply(deadline)
            except OutOfTime:
                self.stop()
                raise
            except BaseException:  # an interrupt, say: the worker is in an unknown state
                self.stop()
                raise
            if reply is None:
                code = self.stop()
                raise PlannerError(f"Fast Downward's translator ended without an answer (exit {code})")
            if reply != "ok":
                raise PlannerError(reply.removeprefix("error ").strip())
            with open(os.path.join(tmp, "output.sas"), encoding="ascii", errors="replace") as f:
                return f.read()

    def _reply(self, deadline: float) -> str | None:
        """The worker's answer line, None if it ended; OutOfTime at the deadline."""
        out = self.process.stdout
        line = b""
        while not line.endswith(b"\n"):
            left = deadline - time.perf_counter()
            if left <= 0:
                raise OutOfTime
            ready, _, _ = select.select([out], [], [], left)
            if not ready:
                continue
            chunk = os.read(out.fileno(), 4096)
            if not chunk:
                return None
            line += chunk
        return line.decode("utf-8", "replace").strip()

    def stop(self) -> int | None:
        """Kill the worker and wait for it; its exit code."""
        p, self.process = self.process, None
        if p is None:
            return None
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(p.pid, signal.SIGKILL)
        with contextlib.suppress(ProcessLookupError):
            p.kill()
        for stream in (p.stdin, p.stdout):
            with contextlib.suppress(OSError):
                stream.close()
        return p.wait()


_shared = Worker()
_lock = threading.Lock()
atexit.register(_shared.stop)


def warm() -> None:
    """Start the shared worker now (it imports the translator while the caller compiles)."""
    if _lock.acquire(blocking=False):
        try:
            _shared.start()
        finally:
            _lock.release()


def translate(domain_text: str, problem_text: str, deadline: float) -> str:
    """Fast Downward's translation of the PDDL texts (SAS text), in a worker process; raises
    OutOfTime at `deadline`. A call while another thread translates gets a worker of its own."""
    if _lock.acquire(blocking=False):
        try:
            return _shared.translate(domain_text, problem_text, deadline)
        finally:
            _lock.release()
    own = Worker()
    try:
        return own.translate(domain_text, problem_text, deadline)
    finally:
        own.stop()


def _serve() -> None:
    """The worker's loop: a folder a line, the answer a line; ends when its input closes."""
    from tidyplan.planning import fastdownward

    answers = os.fdopen(os.dup(1), "w")  # the protocol's own copy of stdout: nothing else writes to it
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)  # what the translator prints goes nowhere
    for line in sys.stdin.buffer:
        folder = line.decode().strip()
        try:
            with open(os.path.join(folder, "domain.pddl"), encoding="utf-8") as f:
                domain_text = f.read()
            with open(os.path.join(folder, "problem.pddl"), encoding="utf-8") as f:
                problem_text = f.read()
            sas = fastdownward.sas_text(fastdownward.translate(domain_text, problem_text))
            with open(os.path.join(folder, "output.sas"), "w", encoding="ascii", errors="replace") as f:
                f.write(sas)
            answer = "ok"
        except PlannerError as e:
            answer = "error " + " ".join(str(e).split())
        except Exception as e:  # noqa: BLE001 - told to the parent, which raises it
            answer = (
                f"error Fast Downward's translator failed: {type(e).__name__}: {' '.join(str(e).split())}"
            )
        answers.write(answer + "\n")
        answers.flush()


if __name__ == "__main__":
    _serve()
