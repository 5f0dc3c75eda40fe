"""The first-plan limit holds for the whole call (docs/planner.md, "Time"): on a task built so that
Fast Downward's translator cannot finish it (a grounding of 40^5 operators), `tidyplan plan
--first-plan-limit 10` ends with `not-found-in-time` (exit 3) and leaves no process behind; in
this process, `plan()` returns the same status with no translator or search still running, and
the next call gets a translator again.

No assertion here is about wall-clock time: the statuses and the processes are what is checked,
and the tests wait on processes, never sleep.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from processes import descendants, still_running_after

from tidyplan.pddl.reader import read
from tidyplan.planning import translator
from tidyplan.planning.planner import Status, plan

DERIVED = Path(__file__).parent / "data" / "derived"


def write_hard_task(folder: Path, n: int = 40) -> tuple[Path, Path]:
    """A goal no plan reaches, which only a full grounding shows: `step` over five chained links
    of a complete graph on n objects (n^5 operators for the translator to instantiate), and
    `finish` needs a self-link no object has."""
    domain = """(define (domain hard)
  (:requirements :typing :negative-preconditions)
  (:types thing)
  (:predicates (at ?a ?b ?c ?d ?e - thing) (link ?a ?b - thing) (done))
  (:action step
    :parameters (?a ?b ?c ?d ?e - thing)
    :precondition (and (link ?a ?b) (link ?b ?c) (link ?c ?d) (link ?d ?e))
    :effect (at ?a ?b ?c ?d ?e))
  (:action finish
    :parameters (?a - thing)
    :precondition (and (at ?a ?a ?a ?a ?a) (not (link ?a ?a)))
    :effect (done)))
"""
    objects = " ".join(f"o{i}" for i in range(n))
    links = " ".join(f"(link o{i} o{j})" for i in range(n) for j in range(n) if i != j)
    problem = f"(define (problem hard-1) (:domain hard) (:objects {objects} - thing)"
    problem += f" (:init {links}) (:goal (done)))"
    d, p = folder / "domain.pddl", folder / "problem.pddl"
    d.write_text(domain)
    p.write_text(problem)
    return d, p


def _planners_left() -> set[int]:
    """Translator workers and Fast Downward searches this test process started, still running."""
    return descendants(b"tidyplan.planning.translator") | descendants(b"downward")


def test_plan_command_on_a_task_too_big_to_translate_ends_not_found_in_time(tmp_path, tidyplan_cmd):
    d, p = write_hard_task(tmp_path)
    before = _planners_left()
    done = subprocess.run(
        [*tidyplan_cmd, "plan", str(d), str(p), "--first-plan-limit", "10", "--json"],
        capture_output=True,
        text=True,
        timeout=300,  # a hang fails the test instead of stopping the suite
    )
    assert done.returncode == 3, done.stderr
    out = json.loads(done.stdout)
    assert out["status"] == "not-found-in-time"
    assert "translator" in out["message"]
    # whatever the command started ended with it (orphans come back to this process, the subreaper)
    assert not still_running_after(_planners_left() - before)
    assert _planners_left() <= before


def test_plan_returns_not_found_in_time_with_no_planner_process_left(tmp_path):
    d, p = write_hard_task(tmp_path)
    domain, problem = read(d, p)
    result = plan(domain, problem, first_plan_limit=3)
    assert result.status is Status.TIMEOUT
    assert "nothing proven" in result.message and "translator" in result.message
    # on return, not a moment later: the worker was killed and waited for, and no search started
    assert translator._shared.process is None
    assert not _planners_left()
    # the next call starts a translator again, and plans
    domain, problem = read(DERIVED / "domain.pddl", DERIVED / "problem.pddl")
    result = plan(domain, problem, time_budget=0.5)
    assert result.status is Status.SOLVED
    assert translator._shared.process is not None and translator._shared.process.poll() is None


def test_the_translator_worker_is_kept_across_calls():
    domain, problem = read(DERIVED / "domain.pddl", DERIVED / "problem.pddl")
    assert plan(domain, problem, time_budget=0.2).status is Status.SOLVED
    first = translator._shared.process.pid
    assert plan(domain, problem, time_budget=0.2).status is Status.SOLVED
    assert translator._shared.process.pid == first


def test_the_translator_worker_dies_with_its_parent(tmp_path):
    """A parent killed outright (SIGKILL: no atexit, no cleanup) takes its worker with it."""
    script = tmp_path / "parent.py"
    script.write_text(
        "import os, signal, sys\n"
        "from tidyplan.planning import translator\n"
        "translator.warm()\n"
        "print(translator._shared.process.pid, flush=True)\n"
        "sys.stdin.readline()\n"
        "os.kill(os.getpid(), signal.SIGKILL)\n"
    )
    parent = subprocess.Popen(
        [sys.executable, str(script)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    worker = int(parent.stdout.readline())
    assert worker in descendants(b"tidyplan.planning.translator")
    parent.stdin.write("\n")
    parent.stdin.flush()
    parent.wait(timeout=60)
    assert not still_running_after({worker})


def test_a_worker_started_by_a_thread_that_ended_still_translates():
    """`tidyplan serve` answers each request in a thread of its own. Linux sends the parent-death
    signal when the thread that forked the child ends, not the process: a worker one request
    started was killed at that request's end, perhaps inside another request's translation."""
    translator._shared.stop()
    starter = threading.Thread(target=translator.warm)
    starter.start()
    starter.join()
    while os.path.exists(f"/proc/self/task/{starter.native_id}"):  # gone from the kernel too:
        time.sleep(0.01)  # the signal, if any, is sent as the thread exits
    pid = translator._shared.process.pid
    domain = "(define (domain d) (:predicates (p) (q)) (:action a :precondition (p) :effect (q)))"
    problem = "(define (problem t) (:domain d) (:init (p)) (:goal (q)))"
    assert "begin_operator" in translator.translate(domain, problem, time.perf_counter() + 120)
    assert translator._shared.process.pid == pid  # the same worker answered


def test_a_limit_spent_before_the_search_starts_no_search():
    domain, problem = read(DERIVED / "domain.pddl", DERIVED / "problem.pddl")
    result = plan(domain, problem, first_plan_limit=0.0)
    assert result.status is Status.TIMEOUT
    assert not descendants(b"downward")


def test_the_loops_grounder_stops_at_its_deadline(tmp_path):
    """The loop grounds in this process (tidyplan.planning.grounding): it looks at the clock as it
    enumerates, and a deadline already past ends it at its next look."""
    from tidyplan.pddl.compile import compile_task
    from tidyplan.planning import grounding

    d, p = write_hard_task(tmp_path, n=7)
    task = compile_task(*read(d, p))
    with pytest.raises(grounding.OutOfTime):
        grounding.Grounder().ground(task.domain, task.problem, deadline=time.perf_counter())
    # without a deadline the same task grounds (and shows its goal unreachable)
    assert grounding.Grounder().ground(task.domain, task.problem).unsolvable


def test_a_mission_whose_replans_run_out_ends_unproven_and_leaves_no_planner(tmp_path):
    """The loop's rules for a replan not found in time (tidyplan.loop.loop: try the narrower
    goals, then end saying nothing was proven), with the real planner: every call runs out."""
    from tidyplan.loop.mission import run
    from tidyplan.loop.options import Settings

    scenario = Path(__file__).parent.parent / "problems" / "case3.toml"
    before = _planners_left()  # the translator an earlier test left for later calls, if any
    summary = run(scenario, tmp_path / "trace.jsonl", Settings(world="symbolic", first_plan_limit=1e-6))
    assert not summary["success"]
    assert "not planned in time, unproven" in summary["reason"]
    events = [json.loads(line) for line in (tmp_path / "trace.jsonl").read_text().splitlines()]
    plans = [e for e in events if e.get("kind") == "plan"]
    assert plans and {e["status"] for e in plans} == {"not-found-in-time"}
    assert _planners_left() <= before


def test_a_translator_worker_that_died_is_replaced_at_the_next_call():
    domain, problem = read(DERIVED / "domain.pddl", DERIVED / "problem.pddl")
    translator.warm()
    dead = translator._shared.process
    dead.kill()
    dead.wait()
    assert plan(domain, problem, time_budget=0.2).status is Status.SOLVED
    assert translator._shared.process is not dead and translator._shared.process.poll() is None
