"""The command line keeps what the user had: `compile --out` never overwrites an
input or a foreign file, nor touches anything but its targets; a bad option is
one line and exit 2."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from tidyplan.cli.main import main

# A valid task that each test breaks in one place (tests/data, shared with test_bad_input.py).
DOMAIN = (Path(__file__).parent / "data" / "baseline-domain.pddl").read_text()
PROBLEM = (Path(__file__).parent / "data" / "baseline-problem.pddl").read_text()


def _run(cmd: list[str], args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(cmd + args, capture_output=True, text=True, cwd=cwd, timeout=120)


# ---------------------------------------------------------------- compile
def _compile(capsys, domain: Path, problem: Path, out: Path, *extra: str) -> tuple[int, str]:
    status = main(["compile", str(domain), str(problem), "--out", str(out), *extra])
    return status, capsys.readouterr().err


def test_compile_refuses_to_overwrite_an_input_file(expect_lines, write, tmp_path, capsys):
    domain, problem = write("domain.pddl", DOMAIN), write("problem.pddl", PROBLEM)
    status, err = _compile(capsys, domain, problem, tmp_path)
    assert status == 2
    expect_lines(err, [(str(domain), None, None, r".*input file.*")])
    assert (domain.read_text(), problem.read_text()) == (DOMAIN, PROBLEM)


def test_compile_refuses_to_overwrite_an_input_problem_file(write, tmp_path, capsys):
    """The problem input sits where the compiled problem would go."""
    domain, problem = write("in/d.pddl", DOMAIN), write("out/problem.pddl", PROBLEM)
    status, err = _compile(capsys, domain, problem, tmp_path / "out")
    assert status == 2
    assert "input file" in err and "Traceback" not in err
    assert problem.read_text() == PROBLEM
    assert not (tmp_path / "out" / "domain.pddl").exists()


def test_compile_refuses_a_foreign_file_and_leaves_it_as_it_was(expect_lines, write, tmp_path, capsys):
    domain, problem = write("d.pddl", DOMAIN), write("p.pddl", PROBLEM)
    foreign = write("out/domain.pddl", "my own notes\n")
    status, err = _compile(capsys, domain, problem, tmp_path / "out")
    assert status == 2
    expect_lines(err, [(str(foreign), None, None, r".*not written by tidyplan.*")])
    assert foreign.read_text() == "my own notes\n"
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["domain.pddl"]


def test_compile_writes_nothing_when_one_target_is_foreign(write, tmp_path, capsys):
    domain, problem = write("d.pddl", DOMAIN), write("p.pddl", PROBLEM)
    foreign = write("out/problem.pddl", "(define (problem mine))\n")
    status, _ = _compile(capsys, domain, problem, tmp_path / "out")
    assert status == 2
    assert foreign.read_text() == "(define (problem mine))\n"
    assert not (tmp_path / "out" / "domain.pddl").exists()


def test_compile_overwrites_its_own_previous_output(write, tmp_path, capsys):
    domain, problem = write("d.pddl", DOMAIN), write("p.pddl", PROBLEM)
    out = tmp_path / "out"
    assert _compile(capsys, domain, problem, out) == (0, "")
    first = (out / "problem.pddl").read_text()
    problem.write_text(PROBLEM.replace("b1 b2 - block", "b1 b2 b3 - block"))
    assert _compile(capsys, domain, problem, out) == (0, "")
    second = (out / "problem.pddl").read_text()
    assert "b3" not in first and "b3" in second
    assert sorted(p.name for p in out.iterdir()) == ["domain.pddl", "problem.pddl"]


def test_compile_does_not_touch_other_files_in_the_output_folder(write, tmp_path, capsys):
    domain, problem = write("d.pddl", DOMAIN), write("p.pddl", PROBLEM)
    bystander = write("out/domain.pddl.tmp", "someone else's file\n")
    status, _ = _compile(capsys, domain, problem, tmp_path / "out")
    assert status == 0
    assert bystander.exists() and bystander.read_text() == "someone else's file\n"


def test_compile_out_that_is_a_file_is_bad_input_not_a_traceback(write, tmp_path, tidyplan_cmd):
    write("d.pddl", DOMAIN)
    write("p.pddl", PROBLEM)
    write("taken", "a file, not a folder\n")
    done = _run(tidyplan_cmd, ["compile", "d.pddl", "p.pddl", "--out", "taken"], tmp_path)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert (tmp_path / "taken").read_text() == "a file, not a folder\n"


# ---------------------------------------------------------------- options
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["plan", "d.pddl", "p.pddl", "--time-budget", "-1"], r"tidyplan plan: error: .*--time-budget.*"),
        (["plan", "d.pddl", "p.pddl", "--time-budget", "nan"], r"tidyplan plan: error: .*--time-budget.*"),
        (["plan", "d.pddl", "p.pddl", "--max-stratum", "0"], r"tidyplan plan: error: .*--max-stratum.*"),
        (
            ["plan", "d.pddl", "p.pddl", "--first-plan-limit", "0"],
            r"tidyplan plan: error: .*--first-plan-limit.*",
        ),
        (["run", "--first-plan-limit", "-2"], r"tidyplan run: error: .*--first-plan-limit.*"),
        (["run", "--patience", "-0.5"], r"tidyplan run: error: .*--patience.*"),
        (["run", "--patience", "inf"], r"tidyplan run: error: .*--patience.*"),
        (
            ["compile", "d.pddl", "p.pddl", "--out", "o", "--max-stratum", "0"],
            r"tidyplan compile: error: .*--max-stratum.*",
        ),
        (["plan", "d.pddl", "p.pddl", "--planner", "no-such-planner"], r"tidyplan: .*no-such-planner.*"),
    ],
    ids=[
        "time-budget-negative",
        "time-budget-nan",
        "max-stratum-0",
        "first-plan-limit-0",
        "run-first-plan-limit-negative",
        "run-patience-negative",
        "run-patience-inf",
        "compile-max-stratum-0",
        "unknown-planner",
    ],
)
def test_bad_option_is_one_line_and_exit_2(write, tmp_path, tidyplan_cmd, args, message):
    write("d.pddl", DOMAIN)
    write("p.pddl", PROBLEM)
    done = _run(tidyplan_cmd, args, tmp_path)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert re.fullmatch(message, done.stderr.strip()), done.stderr
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------- run's scenario
def test_a_shipped_scenario_is_found_by_its_name_and_a_file_here_comes_first(tmp_path, monkeypatch):
    from tidyplan.loop.scenarios import project_file, scenario_path

    monkeypatch.chdir(tmp_path)
    assert scenario_path("case1") == project_file("problems/case1.toml")
    assert scenario_path("case1.toml") == project_file("problems/case1.toml")
    (tmp_path / "case1").write_text("")  # a file of that name here is the user's: it is read
    assert scenario_path("case1") == Path("case1")
    assert scenario_path("nosuch") == Path("nosuch")  # loading it says "no such file"
    assert scenario_path("sub/case1") == Path("sub/case1")  # a path is never looked up elsewhere


def test_an_internal_error_in_a_mission_is_one_line_naming_the_kept_trace_exit_4(
    tmp_path, capsys, monkeypatch
):
    """A bug of ours mid-mission: no traceback reaches the user; the trace so far is kept and
    readable, the traceback beside it for the report."""
    from tidyplan.cli.main import main
    from tidyplan.exec.bindings import MonitoredExecutor

    real, calls = MonitoredExecutor.execute, []

    def broken(self, *args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            raise ZeroDivisionError("a bug of ours")
        return real(self, *args, **kwargs)

    monkeypatch.setattr(MonitoredExecutor, "execute", broken)
    trace = tmp_path / "t.jsonl"
    args = [
        "run",
        "case1",
        "--world",
        "symbolic",
        "--planner",
        "lama-first",
        "--trace",
        str(trace),
        "--quiet",
    ]
    assert main(args) == 4
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith("tidyplan: internal error: ZeroDivisionError: a bug of ours; ")
    assert f"the trace so far is {trace}" in line and "Traceback" not in line
    saved = tmp_path / "t.traceback.txt"
    assert f"the traceback is in {saved}" in line and "ZeroDivisionError" in saved.read_text()
    monkeypatch.setattr(MonitoredExecutor, "execute", real)
    assert main(["trace", str(trace)]) == 0  # read up to its last whole event
    assert "action" in capsys.readouterr().out


def test_an_internal_error_elsewhere_is_one_line_exit_4(capsys, monkeypatch, tmp_path):
    from tidyplan.cli import main as cli

    def broken(args):
        raise KeyError("nobody expected this")

    monkeypatch.setitem(cli.COMMANDS, "check", broken)
    monkeypatch.delenv("TIDYPLAN_TRACEBACK", raising=False)
    assert cli.main(["check", str(tmp_path / "x.pddl")]) == 4
    (line,) = capsys.readouterr().err.splitlines()
    assert (
        line
        == "tidyplan: internal error: KeyError: 'nobody expected this' (TIDYPLAN_TRACEBACK=1 shows where)"
    )
