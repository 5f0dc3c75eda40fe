"""The command-line contract (docs/commands.md), and the README's own commands."""

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from tidyplan.cli.main import main

ROOT = Path(__file__).parent.parent
TIDY = str(ROOT / "domains" / "tidy.pddl")
AVS = str(ROOT / "domains" / "avs.pddl")


def _problem(name: str) -> str:
    return str(ROOT / "problems" / f"{name}.pddl")


def _plan_json(capsys, *args):
    status = main(["plan", *args, "--json", "--time-budget", "30"])
    out = capsys.readouterr().out
    return status, json.loads(out)


@pytest.mark.slow
def test_plan_json_has_the_contract_fields(capsys):
    status, result = _plan_json(capsys, TIDY, _problem("tidy-p2"))
    assert status == 0
    assert result["status"] == "solved"
    for key in ("status", "plan", "cost", "probability", "strata", "planning_time_s"):
        assert key in result
    for step in result["plan"]:
        assert set(step) >= {"name", "args", "assumption", "stratum", "probability", "cost"}
    assert result["strata"] == [1, 2]
    assert result["cost"] == pytest.approx(sum(s["cost"] for s in result["plan"]))
    probability = 1.0
    for step in result["plan"]:
        probability *= step["probability"]
    assert result["probability"] == pytest.approx(probability)


def test_not_found_in_time_exits_3_and_says_so(capsys, monkeypatch):
    from tidyplan.planning import fastdownward

    def out_of_time(sas, searches, first_deadline, improve, patience=None):
        return fastdownward.Result(fastdownward.Ending.OUT_OF_TIME, None)

    monkeypatch.setattr(fastdownward, "search", out_of_time)
    status = main(["plan", TIDY, _problem("tidy-p3"), "--first-plan-limit", "5"])
    assert status == 3
    assert "no plan found within 5 s, nothing proven (P1 out-of-time)" in capsys.readouterr().err
    status, result = _plan_json(capsys, TIDY, _problem("tidy-p3"))
    assert (status, result["status"]) == (3, "not-found-in-time")


@pytest.mark.slow
def test_no_plan_exits_1_and_says_why(capsys):
    # a budget no machine runs out of: proving P1 and P2 unsolvable must not race the clock
    # (under load the 1 s default ran out in P2, "gave-up", and the test failed)
    status = main(["plan", TIDY, _problem("tidy-p3"), "--max-stratum", "2"])
    captured = capsys.readouterr()
    assert status == 1
    assert "no plan within P1 unsolvable, P2 unsolvable" in captured.err
    status, result = _plan_json(capsys, TIDY, _problem("tidy-p3"), "--max-stratum", "1")
    assert status == 1
    assert result["status"] == "no-plan"
    assert result["plan"] == []


@pytest.mark.slow
def test_indirect_search_wins_as_in_the_papers_first_plan(capsys):
    """Göbelbecker Sec. 4: assume a room, a table in it and the cerealbox on it; search the table first."""
    status, result = _plan_json(capsys, AVS, _problem("avs-indirect"))
    assert status == 0
    names = [s["name"] for s in result["plan"]]
    assumed = [s for s in result["plan"] if s["assumption"]]
    assert {s["name"] for s in assumed} == {
        "assume-leads-to-room",
        "assume-obj-exists-in",
        "assume-obj-exists-on",
    }
    assert all(s["cost"] == 0 for s in assumed)
    table = names.index("search-for-object-in")
    assert result["plan"][table]["args"][0] == "table"
    assert names.index("search-for-object-on") > table
    assert result["probability"] == pytest.approx(0.6 * 0.9 * 0.7 * 0.8 * 0.8)
    assert result["cost"] == 22


@pytest.mark.slow
def test_direct_search_wins_when_tables_are_unlikely(capsys):
    status, result = _plan_json(capsys, AVS, _problem("avs-direct"))
    assert status == 0
    searches = [s for s in result["plan"] if s["name"].startswith("search-for-object")]
    assert [s["args"][0] for s in searches] == ["cerealbox"]


@pytest.mark.slow
def test_compiled_pddl_plans_the_same_with_fast_downward_alone(tmp_path, capsys):
    """`compile` writes plain PDDL that another tool solves to a plan of the same cost."""
    assert main(["compile", TIDY, _problem("tidy-p1"), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    status, original = _plan_json(capsys, TIDY, _problem("tidy-p1"), "--planner", "optimal")
    status_c, compiled = _plan_json(
        capsys, str(tmp_path / "domain.pddl"), str(tmp_path / "problem.pddl"), "--planner", "optimal"
    )
    assert status == status_c == 0
    assert [(s["name"], s["args"]) for s in compiled["plan"]] == [
        (s["name"], s["args"]) for s in original["plan"]
    ]


def _readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    block = re.search(r"```\n(.*?)```", text, re.DOTALL)
    assert block is not None, "README has no code block"
    return [line for line in block.group(1).splitlines() if line.strip()]


def test_readme_opens_with_exactly_two_commands():
    lines = (ROOT / "README.md").read_text().splitlines()
    assert lines[0].startswith("# ")
    first_block = _readme_commands()
    assert len(first_block) == 2
    assert first_block[0].startswith("pip install") and "tidyplan" in first_block[0]
    assert "pytest" in first_block[1]


def test_readme_is_a_front_door_whose_links_are_there():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) < 150
    assert not re.search(r"\b[0-9a-f]{7,40}\b", text), "a commit hash in the README"
    assert "../shared" not in text, "the README names a file outside the repository"
    for link in re.findall(r"\]\(([^)#]+)\)", text):
        assert (ROOT / link).exists(), link


@pytest.mark.slow
def test_readmes_python_example_runs(tmp_path, monkeypatch):
    """The README's Python block, as a user would paste it, in a folder of its own."""
    block = re.search(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.DOTALL)
    assert block is not None
    monkeypatch.chdir(tmp_path)
    done = subprocess.run([sys.executable, "-c", block.group(1)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    success, delivered, replans = done.stdout.split()
    assert success == "True" and delivered == "12" and int(replans) >= 0
    assert os.listdir(tmp_path) == []  # no trace unless asked


@pytest.mark.slow
def test_readmes_main_command_runs(tidyplan_cmd, tmp_path):
    """The part after the install: the installed package is already under test. It runs the
    default mission (case III) and writes its trace under runs/ in the folder it runs in."""
    command = shlex.split(_readme_commands()[0].split("&&", 1)[1].strip())
    assert command[0] == "tidyplan"
    done = subprocess.run(
        tidyplan_cmd + command[1:], cwd=tmp_path, capture_output=True, text=True, timeout=900
    )
    assert done.returncode == 0, done.stderr
    assert "tidied 12/12" in done.stderr and "success" in done.stdout
    (trace,) = (tmp_path / "runs").glob("*.jsonl")
    assert f"trace {trace.relative_to(tmp_path)}" in done.stdout


@pytest.mark.slow
@pytest.mark.parametrize(
    "domain, problem",
    [(TIDY, "tidy-p1"), (TIDY, "tidy-p2"), (TIDY, "tidy-p3"), (AVS, "avs-indirect"), (AVS, "avs-direct")],
)
def test_val_accepts_our_plans_on_the_compiled_pddl(domain, problem, tmp_path, capsys, val):
    """VAL reads the plain PDDL `tidyplan compile` writes, so it can hold our plans to it.

    The dialect's plans (assumptions included: they are actions in plain PDDL)
    are valid there, and VAL's plan value is the compiled integer cost.
    """
    from tidyplan.pddl.compile import compile_task
    from tidyplan.pddl.criterion import integer_cost
    from tidyplan.pddl.reader import read

    assert main(["compile", domain, _problem(problem), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    status, result = _plan_json(capsys, domain, _problem(problem))
    assert status == 0
    verdict = val(
        tmp_path / "domain.pddl",
        tmp_path / "problem.pddl",
        ["(" + " ".join([s["name"], *s["args"]]) + ")" for s in result["plan"]],
    )
    assert verdict.valid, verdict.output
    task = compile_task(*read(domain, _problem(problem)))
    value = float(re.search(r"^Final value: (\S+)", verdict.output, re.MULTILINE).group(1))
    expected = sum(
        integer_cost(s["cost"], s["probability"], result["reward"], task.scale) for s in result["plan"]
    )
    assert value == expected


@pytest.mark.slow
@pytest.mark.parametrize("planner", ["lama-optimal", "lama", "lama-first", "optimal"])
def test_a_goal_that_already_holds_is_an_empty_plan(planner, tmp_path, capsys):
    (tmp_path / "d.pddl").write_text(
        "(define (domain lights) (:predicates (on))\n"
        "  (:action switch :parameters () :precondition () :effect (on)))"
    )
    (tmp_path / "p.pddl").write_text("(define (problem lit) (:domain lights) (:init (on)) (:goal (on)))")
    status, result = _plan_json(
        capsys, str(tmp_path / "d.pddl"), str(tmp_path / "p.pddl"), "--planner", planner
    )
    assert (status, result["status"], result["plan"], result["cost"]) == (0, "solved", [], 0)
    assert result["probability"] == 1
