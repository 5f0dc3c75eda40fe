"""`tidyplan serve` called as the VS Code PDDL extension calls it: POST /solve over loopback with
{"domain", "problem"}, options in the query (docs/editor.md)."""

from __future__ import annotations

import json
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest
from processes import descendants, still_running_after

REPO = Path(__file__).resolve().parent.parent
TIDY = REPO / "domains" / "tidy.pddl"


@pytest.fixture(scope="module")
def service():
    """A server on an ephemeral port; its first line names the port."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "tidyplan", "serve", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    line = proc.stdout.readline()
    assert "POST http://127.0.0.1:" in line, line
    url = line.split("POST ", 1)[1].split()[0]
    yield url, proc
    proc.terminate()
    assert proc.wait(timeout=30) == 0  # "0 on shutdown"
    proc.stdout.close()


def solve(url: str, domain: str, problem: str, query: str = "") -> dict:
    body = json.dumps({"domain": domain, "problem": problem}).encode()
    req = urllib.request.Request(url + query, data=body, headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=120) as r:
        assert r.status == 200
        return json.loads(r.read())


def test_it_listens_on_loopback_by_default(service):
    url, _ = service
    assert url.startswith("http://127.0.0.1:") and url.endswith("/solve")


def test_case_one_compiled_is_planned(service, tmp_path):
    """Case I's first problem, from the belief as the loop writes it, compiled to plain PDDL by
    `tidyplan compile`: a plan the extension reads, each step named "(action arg ...)"."""
    from sim.scenario.read import load
    from tidyplan.belief.geometry import RoomMap
    from tidyplan.belief.problem import write
    from tidyplan.belief.state import Belief
    from tidyplan.worlds.symbolic import SymbolicWorld

    scenario = load(REPO / "problems" / "case1.toml")
    room = RoomMap(scenario)
    belief = Belief(scenario, room)
    belief.observe(SymbolicWorld(scenario, room, seed=0).look(), None)
    goal = [k.name for k in belief.untidied()]
    (tmp_path / "case1.pddl").write_text(write(belief, belief.facts(), goal, [], "case1").text)
    out = tmp_path / "plain"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "tidyplan",
            "compile",
            str(TIDY),
            str(tmp_path / "case1.pddl"),
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    url, _ = service
    answer = solve(
        url, (out / "domain.pddl").read_text(), (out / "problem.pddl").read_text(), "?planner=lama-first"
    )
    assert answer["status"] == "ok", answer
    plan = answer["result"]["plan"]
    assert plan and all(s["name"].startswith("(") and s["name"].endswith(")") for s in plan)
    taken = {s["name"].split()[1] for s in plan if s["name"].startswith("(take_object")}
    assert taken and taken <= set(goal)
    assert answer["result"]["length"] == len(plan) and answer["result"]["output"]


def test_a_dialect_domain_with_assumptions_is_planned_with_stratum_probability_and_criterion(service):
    url, _ = service
    answer = solve(url, TIDY.read_text(), (REPO / "problems" / "tidy-p3.pddl").read_text())
    assert answer["status"] == "ok", answer
    r = answer["result"]
    assert r["stratum"] == max(s["stratum"] for s in r["plan"])
    p = 1.0
    for s in r["plan"]:
        p *= s["probability"]
    assert r["probability"] == pytest.approx(p)
    assert r["criterion"] == pytest.approx(r["cost"] + r["reward"] * (1 - r["probability"]))
    assert f"P{r['stratum']}" in r["output"]


def test_a_problem_with_virtual_objects_plans_through_an_assumption(service):
    url, _ = service
    problem = (REPO / "problems" / "avs-indirect.pddl").read_text()
    answer = solve(url, (REPO / "domains" / "avs.pddl").read_text(), problem)
    assert answer["status"] == "ok", answer
    assert any(s["assumption"] for s in answer["result"]["plan"])
    assert answer["result"]["probability"] < 1


def test_a_syntax_error_is_an_error_with_its_place(service):
    url, _ = service
    domain = TIDY.read_text().replace(":stratum 2", ":stratum two")
    answer = solve(url, domain, (REPO / "problems" / "tidy-p1.pddl").read_text())
    assert answer["status"] == "error"
    line = domain[: domain.index(":stratum two")].count("\n") + 1
    assert f"domain.pddl:{line}:" in answer["result"]["error"], answer
    assert "unexpected 'two'" in answer["result"]["error"]


def test_bad_requests_are_answered_not_crashed_on(service):
    url, _ = service
    assert solve(url, "", "", "?bogus=1")["status"] == "error"
    req = urllib.request.Request(url, data=b"not json", headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=30) as r:
        assert json.loads(r.read())["status"] == "error"
    assert solve(url, "(define", ")")["status"] == "error"


def _gripper(balls: int) -> tuple[str, str]:
    domain = """(define (domain gripper) (:requirements :strips)
  (:predicates (room ?r) (ball ?b) (gripper ?g) (at-robby ?r) (at ?b ?r) (free ?g) (carry ?o ?g))
  (:action move :parameters (?from ?to)
    :precondition (and (room ?from) (room ?to) (at-robby ?from))
    :effect (and (at-robby ?to) (not (at-robby ?from))))
  (:action pick :parameters (?obj ?room ?gripper)
    :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (at ?obj ?room)
                       (at-robby ?room) (free ?gripper))
    :effect (and (carry ?obj ?gripper) (not (at ?obj ?room)) (not (free ?gripper))))
  (:action drop :parameters (?obj ?room ?gripper)
    :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (carry ?obj ?gripper) (at-robby ?room))
    :effect (and (at ?obj ?room) (free ?gripper) (not (carry ?obj ?gripper)))))"""
    names = " ".join(f"b{i}" for i in range(balls))
    problem = (
        f"(define (problem g) (:domain gripper) (:objects ra rb left right {names})\n"
        "(:init (room ra) (room rb)"
        " (gripper left) (gripper right) (at-robby ra) (free left) (free right)"
        + "".join(f" (ball b{i}) (at b{i} ra)" for i in range(balls))
        + ")\n(:goal (and"
        + "".join(f" (at b{i} rb)" for i in range(balls))
        + ")))"
    )
    return domain, problem


def test_a_request_past_its_limit_ends_with_its_planner_gone(service):
    """A cost-optimal search on 40 balls does not end in 2 s: the reply says so, and no process
    of that request (the planning child, the search) is left, under the server or orphaned
    (this test process is their subreaper: an orphan would come back to it)."""
    url, proc = service
    answer = solve(url, *_gripper(40), "?planner=optimal&timeout=2&budget=1")
    assert answer["status"] == "error" and answer["result"].get("timeout"), answer
    assert "2 s" in answer["result"]["error"]
    left = descendants(b"problem.pddl") | descendants(b"downward")
    assert still_running_after(left) == set()
    assert proc.poll() is None  # the server lives on
