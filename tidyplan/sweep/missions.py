"""Run the sweep's missions, each in a process of its own: on a local pool, or on Ray.

A mission is ``python -m tidyplan.sweep.missions TARGET RESULT`` with its job (configuration and trace
path) on stdin: a fresh interpreter, so one pybullet client per process and nothing shared. The
process has a session of its own and, past the per-mission limit, is asked to stop (SIGTERM:
the mission's clean-up closes its planner) and then killed with everything it started. A mission
that raises, dies or hangs is a row that says so (``crashed``, ``timeout``), never the end of
the sweep. The child asks the kernel for SIGTERM when its parent dies (a sweep killed with -9,
a Ray worker cancelled), so no mission outlives the sweep that started it.

``TARGET`` is ``module:function`` called with the job's configuration dict and trace path,
returning the summary; tests inject their own (one that hangs, one that raises).
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from collections import deque
from pathlib import Path

MISSION = "tidyplan.sweep.missions:mission"
GRACE_S = 3.0  # after SIGTERM, seconds a mission has to close its planner before SIGKILL
RAY_INSTALL = "pip install '.[ray]'"


def mission(config: dict, trace: str) -> dict:
    """The real mission: ``tidyplan.loop.mission.run`` with the configuration's options."""
    from tidyplan.loop.mission import run
    from tidyplan.sweep.config import MissionConfig

    config = MissionConfig.from_row(config)
    return run(config.scenario_file, trace, config.settings())


# ------------------------------------------------------------------ one mission, in a child
def start(job: dict, target: str = MISSION) -> tuple[subprocess.Popen, str, object]:
    """Start a mission's process; returns it, its result file and its output file."""
    fd, result = tempfile.mkstemp(prefix="tidyplan-sweep-", suffix=".json")
    os.close(fd)
    os.unlink(result)  # the child writes it (renamed into place) only when the mission returned
    output = tempfile.TemporaryFile()  # the child's stdout and stderr: the tail explains a crash
    # unbuffered, it and what it starts: a mission that dies (a segfault in the physics engine,
    # os._exit) has written its last lines, which are the row's explanation
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    process = subprocess.Popen(
        [sys.executable, "-u", "-m", "tidyplan.sweep.missions", target, result],
        stdin=subprocess.PIPE,
        stdout=output,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # its own process group, killed whole
        env=env,
    )
    with contextlib.suppress(BrokenPipeError):
        process.stdin.write(json.dumps(job).encode())
        process.stdin.close()
    return process, result, output


def finish(process: subprocess.Popen, result: str, output, timed_out: float | None) -> dict:
    """The outcome of an ended (or timed-out) child: status, error, summary."""
    if timed_out is not None:
        stop(process)
    try:
        if timed_out is not None:
            return {"status": "timeout", "error": f"no result within {timed_out:g} s (wall); killed"}
        if os.path.exists(result):
            with open(result) as f:
                return json.load(f)
        return {
            "status": "crashed",
            "error": f"the process ended with status {process.returncode}: " + _tail(output),
        }
    finally:
        with contextlib.suppress(OSError):
            os.unlink(result)
        output.close()


def stop(process: subprocess.Popen) -> None:
    """SIGTERM to the mission's group, then SIGKILL to it and to every process it started (Fast
    Downward's searches run in sessions of their own)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(process.pid, signal.SIGTERM)
    with contextlib.suppress(subprocess.TimeoutExpired):
        process.wait(timeout=GRACE_S)
    for pid in [*descendants(process.pid), process.pid]:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(pid, signal.SIGKILL)
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(pid, signal.SIGKILL)
    process.wait()


def descendants(pid: int) -> list[int]:
    """Every process under ``pid`` (children, grandchildren, ...), from /proc."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError, ValueError, IndexError):
                ppid = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
                children.setdefault(ppid, []).append(int(entry.name))
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def _tail(output) -> str:
    with contextlib.suppress(Exception):
        output.seek(0)
        lines = output.read().decode("utf-8", "replace").strip().splitlines()
        return " | ".join(lines[-3:])[-400:]
    return ""


def run_one(job: dict, limit: float, target: str = MISSION) -> dict:
    """One mission, start to end, blocking (what a Ray task runs). A task Ray runs again (its
    worker or node died) finds its first attempt's trace at the job's path, and a trace is never
    overwritten: the attempt writes a fresh one beside it, and its row names that one."""
    first = job["trace"]
    job = {**job, "trace": _fresh_attempt_trace(job)}
    process, result, output = start(job, target)
    try:
        process.wait(timeout=limit)
        timed_out = None
    except subprocess.TimeoutExpired:
        timed_out = limit
    except BaseException:
        stop(process)
        raise
    outcome = finish(process, result, output, timed_out)
    if job["trace"] != first and "trace" not in outcome:  # a crashed retry: its own trace, not the first's
        outcome["trace"] = job["trace"] if Path(job["trace"]).exists() else None
    return outcome


def _fresh_attempt_trace(job: dict) -> str:
    """The job's trace path, or the first free one beside it named as ``grid.fresh_trace`` names
    them (``STEM-2.jsonl``, ``STEM-3.jsonl``, ...), if an attempt has written there."""
    path = Path(job["trace"])
    base, n = re.sub(r"-\d+$", "", path.stem), 1  # a stem ends "-s<seed>"; "-<n>" only on a fresh one
    while path.exists() or path.with_suffix(".pddl").exists():
        n += 1
        path = path.with_name(f"{base}-{n}.jsonl")
    return str(path)


# ------------------------------------------------------------------ engines
def run_local(jobs: list[dict], workers: int, limit: float, on_outcome, target: str = MISSION) -> None:
    """``workers`` missions at a time on this machine; ``on_outcome(job, outcome)`` as each ends.
    Interrupted (Ctrl-C, SIGTERM), it stops every running mission before passing the
    interruption on."""
    pending, running = deque(jobs), {}
    try:
        while pending or running:
            while pending and len(running) < workers:
                job = pending.popleft()
                running[id(job)] = (job, *start(job, target), time.monotonic() + limit)
            time.sleep(0.02)
            for key, (job, process, result, output, deadline) in list(running.items()):
                ended = process.poll() is not None
                if ended or time.monotonic() > deadline:
                    del running[key]
                    on_outcome(job, finish(process, result, output, None if ended else limit))
    finally:
        for _, process, result, output, _ in running.values():
            stop(process)
            finish(process, result, output, None)


def run_ray(jobs: list[dict], address: str | None, workers: int, limit: float, on_outcome, target=MISSION):
    """The same missions as Ray tasks (one CPU each: Ray places them; ``max_retries`` re-runs a
    task whose worker or node died). Each task runs its mission in a child process as the local
    pool does, so a crash or a hang is the same row. A Ray started here is shut down at the end;
    interrupted, the tasks still running are cancelled (force: their workers killed)."""
    from tidyplan.errors import InputError

    try:
        import ray
    except ImportError:
        raise InputError(f"--ray: Ray is not installed; install the extra: {RAY_INSTALL}") from None
    try:
        if address:
            ray.init(address=address, log_to_driver=False)
        else:
            # "local": always a Ray of our own, never one a `ray start` left running here
            ray.init(address="local", num_cpus=workers, include_dashboard=False, log_to_driver=False)
    except (ConnectionError, ValueError, RuntimeError) as e:
        raise InputError(f"--ray {address or ''}: Ray did not start: {e}".replace("  ", " ")) from None
    remote = ray.remote(num_cpus=1, max_retries=2)(run_one)
    refs: dict = {}
    try:
        refs = {remote.remote(job, limit, target): job for job in jobs}
        while refs:
            ready, _ = ray.wait(list(refs), num_returns=1)
            for ref in ready:
                job = refs.pop(ref)
                try:
                    outcome = ray.get(ref)
                except ray.exceptions.RayError as e:  # retries exhausted: the sweep goes on
                    outcome = {"status": "crashed", "error": f"Ray: {type(e).__name__}: {str(e)[-300:]}"}
                on_outcome(job, outcome)
    finally:
        if address:  # a cluster outlives us: its workers running our tasks are killed
            for ref in refs:
                with contextlib.suppress(Exception):
                    ray.cancel(ref, force=True)
        # A Ray started here ends with everything in it, each mission going with its worker (it
        # asked for SIGTERM on its parent's death). Force-cancelling there first raced the
        # tasks' replies and aborted the driver in Ray 2.60 (task_manager.cc, CompletePendingTask)
        ray.shutdown()


# ------------------------------------------------------------------ the child's side
def _die_with_parent() -> None:
    """Linux: SIGTERM when the parent dies, so a sweep killed with -9 takes its missions along."""
    with contextlib.suppress(Exception):
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


class _Terminated(BaseException):
    pass


def _terminated(signum, frame) -> None:
    raise _Terminated(signum)


def child_main(target: str, result: str) -> int:
    _die_with_parent()
    signal.signal(signal.SIGTERM, _terminated)  # unwind: `finally` blocks stop the planner
    job = json.load(sys.stdin)
    module, _, name = target.partition(":")
    try:
        summary = getattr(importlib.import_module(module), name)(job["config"], job["trace"])
        outcome = {"status": "done", "error": None, **summary}
    except Exception as e:  # noqa: BLE001 - a crash is a row of the table
        tb = traceback.format_exc(limit=4).strip().splitlines()
        outcome = {"status": "crashed", "error": f"{type(e).__name__}: {e} ({' | '.join(tb[-3:])})"[-600:]}
    tmp = result + ".tmp"
    with open(tmp, "w") as f:
        json.dump(outcome, f)
    os.replace(tmp, result)
    return 0


if __name__ == "__main__":
    sys.exit(child_main(sys.argv[1], sys.argv[2]))
