"""docs/dialect.md: a bad file gets one `path:line:col: what is wrong` line per error,
exit status 2, no traceback, and nothing else on the machine is touched.

Positions are computed from the text each test writes: a diagnostic points at the
element that is wrong (the predicate name of an atom, the number after
`:probability`, the `increase` keyword, the declared name whose type is unknown).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tidyplan.cli.main import main

# A valid task that each test breaks in one place (tests/data, shared with test_cli_input.py).
DOMAIN = (Path(__file__).parent / "data" / "baseline-domain.pddl").read_text()
PROBLEM = (Path(__file__).parent / "data" / "baseline-problem.pddl").read_text()
ACTION = """\
  (:action pick
    :parameters (?x - block)
    :precondition (clear ?x)
    :effect (and (held ?x) (not (clear ?x)) (increase (total-cost) 1))))
"""


def _domain_with(action_text: str) -> str:
    """The domain with its action replaced (the text must close the domain too)."""
    assert DOMAIN.endswith(ACTION)
    return DOMAIN[: -len(ACTION)] + action_text


def _run(cmd: list[str], args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(cmd + args, capture_output=True, text=True, cwd=cwd, timeout=120)


def _check_in_process(capsys, *paths: Path) -> tuple[int, str, str]:
    status = main(["check", *map(str, paths)])
    out = capsys.readouterr()
    return status, out.out, out.err


# ------------------------------------------------------------ the baseline
def test_the_baseline_files_are_valid(write, capsys):
    status, out, err = _check_in_process(capsys, write("domain.pddl", DOMAIN), write("problem.pddl", PROBLEM))
    assert (status, err) == (0, "")
    assert "ok" in out


# ------------------------------------------------------ unbalanced parens
def test_missing_close_paren_at_the_end_points_at_the_open_define(
    expect_lines, write, tidyplan_cmd, tmp_path, position
):
    text = DOMAIN.rstrip().removesuffix(")") + "\n"
    write("domain.pddl", text)
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 2
    line, col = position(text, "(define")  # line 2: line 1 is a comment
    expect_lines(done.stderr, [("domain.pddl", line, col, r"unbalanced parenthesis: .*never closed.*")])


def test_missing_close_paren_of_a_section_points_at_that_section(expect_lines, write, capsys, position):
    """`(:predicates ...` left open: the diagnostic names its line, not the `(define` on line 2."""
    text = DOMAIN.replace("(held ?x - block))\n", "(held ?x - block)\n")
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, "(:predicates")
    expect_lines(err, [(str(path), line, col, r"unbalanced parenthesis.*")])


def test_extra_close_paren_points_at_it(expect_lines, write, tidyplan_cmd, tmp_path, position):
    text = DOMAIN + ")\n"
    write("domain.pddl", text)
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 2
    line, col = position(text, ")\n", text.count(")\n"))  # the last one, alone on its line
    assert (line, col) == (text.count("\n"), 1)
    expect_lines(done.stderr, [("domain.pddl", line, col, r"unbalanced parenthesis: .*closes nothing.*")])


def test_parens_in_comments_do_not_count(write, capsys):
    text = DOMAIN.replace("(:types block)", "(:types block) ; ((( not code )")
    status, _, err = _check_in_process(capsys, write("domain.pddl", text))
    assert (status, err) == (0, "")


# --------------------------------------------------------- undeclared names
def test_undeclared_predicate_points_at_its_name(expect_lines, write, tidyplan_cmd, tmp_path, position):
    text = DOMAIN.replace(":precondition (clear ?x)", ":precondition (and (clear ?x) (free ?x))")
    write("domain.pddl", text)
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 2
    line, col = position(text, "free ?x")
    expect_lines(done.stderr, [("domain.pddl", line, col, r"undeclared predicate 'free'")])


def test_undeclared_type_points_at_what_it_types(expect_lines, write, capsys, position):
    text = DOMAIN.replace("(held ?x - block)", "(held ?h - blok)")
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, "?h - blok")
    expect_lines(err, [(str(path), line, col, r"undeclared type 'blok'.*'\?h'.*")])


def test_undeclared_object_in_a_problem_points_at_its_atom(
    expect_lines, write, tidyplan_cmd, tmp_path, position
):
    problem = PROBLEM.replace("(on b1 b2)", "(on b1 b3)")
    write("domain.pddl", DOMAIN)
    write("problem.pddl", problem)
    done = _run(tidyplan_cmd, ["check", "domain.pddl", "problem.pddl"], tmp_path)
    assert done.returncode == 2
    line, col = position(problem, "on b1 b3")
    expect_lines(done.stderr, [("problem.pddl", line, col, r"undeclared object 'b3'")])


def test_undeclared_object_in_a_goal(expect_lines, write, capsys, position):
    problem = PROBLEM.replace("(:goal (held b1))", "(:goal (held b7))")
    status, _, err = _check_in_process(capsys, write("d.pddl", DOMAIN), path := write("p.pddl", problem))
    assert status == 2
    line, col = position(problem, "held b7")
    expect_lines(err, [(str(path), line, col, r"undeclared object 'b7'")])


def test_wrong_number_of_arguments(expect_lines, write, capsys, position):
    text = DOMAIN.replace(":precondition (clear ?x)", ":precondition (on ?x)")
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, "on ?x)")
    expect_lines(err, [(str(path), line, col, r"'on' takes 2 arguments, given 1")])


def test_wrong_number_of_arguments_in_a_problem(expect_lines, write, capsys, position):
    problem = PROBLEM.replace("(clear b1)", "(clear b1 b2)")
    status, _, err = _check_in_process(capsys, write("d.pddl", DOMAIN), path := write("p.pddl", problem))
    assert status == 2
    line, col = position(problem, "clear b1 b2")
    expect_lines(err, [(str(path), line, col, r"'clear' takes 1 argument, given 2")])


def test_every_error_gets_its_own_line_in_file_order(expect_lines, write, capsys, position):
    text = DOMAIN.replace("(held ?x - block)", "(held ?x - blok)").replace(
        ":precondition (clear ?x)", ":precondition (and (free ?x) (on ?x))"
    )
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    expect_lines(
        err,
        [
            (str(path), *position(text, "?x - blok"), r"undeclared type 'blok'.*"),
            (str(path), *position(text, "free ?x"), r"undeclared predicate 'free'"),
            (str(path), *position(text, "on ?x)"), r"'on' takes 2 arguments, given 1"),
        ],
    )


# ------------------------------------------------------------- extensions
@pytest.mark.parametrize("value", ["0", "1.5", "-0.2"])
def test_probability_outside_zero_one_points_at_the_number(expect_lines, write, capsys, position, value):
    text = DOMAIN.replace(
        "    :precondition (clear ?x)", f"    :probability {value}\n    :precondition (clear ?x)"
    )
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, f":probability {value}")
    expect_lines(
        err, [(str(path), line, col + len(":probability "), r"probability .* of 'pick' is outside \(0, 1\]")]
    )


def test_probability_one_is_allowed(write, capsys):
    text = DOMAIN.replace("    :precondition (clear ?x)", "    :probability 1\n    :precondition (clear ?x)")
    status, _, err = _check_in_process(capsys, write("domain.pddl", text))
    assert (status, err) == (0, "")


BELOW, ABOVE = r"stratum of 'pick' must be .*at least 1", r"stratum of 'pick' must be at most 1000000"


# Too large is read exactly, not through a float (1e400 was an OverflowError, exit 4), and never
# built as an integer of a billion digits.
@pytest.mark.parametrize(
    "value, message",
    [("0", BELOW), ("-1", BELOW), ("1.5", BELOW)]
    + [(v, ABOVE) for v in ("1e400", "99999999999999999999999", "1e999999999", "1000001")],
)
def test_stratum_not_whole_or_out_of_range_points_at_the_number(
    expect_lines, write, capsys, position, value, message
):
    text = DOMAIN.replace(
        "    :precondition (clear ?x)", f"    :stratum {value}\n    :precondition (clear ?x)"
    )
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, f":stratum {value}")
    expect_lines(err, [(str(path), line, col + len(":stratum "), message)])


@pytest.mark.parametrize("value, stratum", [("2.0", 2), ("1000000", 1_000_000), ("3e0", 3)])
def test_a_whole_stratum_written_as_a_decimal_is_read_exactly(write, value, stratum):
    from tidyplan.pddl.reader import read_domain

    text = DOMAIN.replace(
        "    :precondition (clear ?x)", f"    :stratum {value}\n    :precondition (clear ?x)"
    )
    (action,) = [a for a in read_domain(write("domain.pddl", text)).actions if a.name == "pick"]
    assert action.stratum == stratum


def test_numbers_too_large_for_a_float_are_bad_input_at_their_place(expect_lines, write, capsys, position):
    """1e400 reads as infinity: as a cost, an init value or the goal reward it was an internal
    error (exit 4) when the task was compiled; now the check says where."""
    domain_text = DOMAIN.replace("(increase (total-cost) 1)", "(increase (total-cost) 1e400)")
    domain = write("domain.pddl", domain_text)
    status, _, err = _check_in_process(capsys, domain)
    assert status == 2
    line, col = position(domain_text, "increase (total-cost) 1e400)")
    expect_lines(err, [(str(domain), line, col, r"action cost inf of 'pick' is not a finite number")])

    numeric = DOMAIN.replace("(:functions (total-cost) - number)", "(:functions (total-cost) (w ?x - block))")
    problem_text = PROBLEM.replace(
        "(:init (clear b1)", "(:goal-reward 1e400)\n  (:init (= (w b1) 1e400) (clear b1)"
    )
    problem = write("problem.pddl", problem_text)
    status, _, err = _check_in_process(capsys, write("domain.pddl", numeric), problem)
    assert status == 2
    w, reward = position(problem_text, "w b1) 1e400"), position(problem_text, "1e400)\n")
    expect_lines(
        err,
        [
            (str(problem), *w, r"value inf of \(w b1\) is not a finite number"),
            (str(problem), *reward, r"goal reward must be a positive finite number, not inf"),
        ],
    )


def test_assumption_with_a_cost_effect_points_at_the_increase(
    expect_lines, write, tidyplan_cmd, tmp_path, position
):
    text = _domain_with(
        ACTION.removesuffix(")\n") + "\n  (:assumption guess\n"
        "    :parameters (?x - block)\n"
        "    :precondition (not (held ?x))\n"
        "    :effect (and (clear ?x) (increase (total-cost) 1))))\n"
    )
    write("domain.pddl", text)
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 2
    line, col = position(text, "increase (total-cost) 1", 2)
    expect_lines(done.stderr, [("domain.pddl", line, col, r"assumption 'guess' has a cost effect.*")])


def test_extension_without_its_requirement_flag_is_a_warning_not_an_error(
    expect_lines, write, tidyplan_cmd, tmp_path, position
):
    text = DOMAIN.replace(" :probabilities", "").replace(
        "    :precondition (clear ?x)", "    :probability 0.9\n    :precondition (clear ?x)"
    )
    write("domain.pddl", text)
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 0, done.stderr
    assert "domain.pddl: ok" in done.stdout
    line, col = position(text, "pick")
    expect_lines(done.stderr, [("domain.pddl", line, col, r"warning: .*:probabilities.*")])


# ------------------------------------------------------------- not PDDL
def test_binary_file(expect_lines, write, tidyplan_cmd, tmp_path):
    write("domain.pddl", b"\x7fELF\x02\x01\x01\x00\x00\x00(define")
    done = _run(tidyplan_cmd, ["check", "domain.pddl"], tmp_path)
    assert done.returncode == 2
    expect_lines(done.stderr, [("domain.pddl", 1, 8, r"binary file, not PDDL text")])  # the first NUL byte


def test_missing_file(expect_lines, tmp_path, capsys):
    path = tmp_path / "nowhere.pddl"
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    expect_lines(err, [(str(path), None, None, r"no such file")])


def test_missing_problem_file(expect_lines, write, tmp_path, capsys):
    path = tmp_path / "nowhere.pddl"
    status, _, err = _check_in_process(capsys, write("domain.pddl", DOMAIN), path)
    assert status == 2
    expect_lines(err, [(str(path), None, None, r"no such file")])


def test_directory_given_as_a_file(expect_lines, tmp_path, capsys):
    (tmp_path / "dir.pddl").mkdir()
    status, _, err = _check_in_process(capsys, tmp_path / "dir.pddl")
    assert status == 2
    expect_lines(err, [(str(tmp_path / "dir.pddl"), None, None, r".*directory.*")])


def test_syntax_error_points_at_the_unexpected_token(expect_lines, write, capsys, position):
    text = DOMAIN.replace(":parameters (?x - block)", ":parameters (?x - )")
    path = write("domain.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, "?x - )")
    expect_lines(err, [(str(path), line, col + len("?x - "), r"unexpected '\)'.*")])


def test_problem_given_where_a_domain_is_expected(expect_lines, write, capsys):
    path = write("problem.pddl", PROBLEM)
    status, _, err = _check_in_process(capsys, path, path)
    assert status == 2
    expect_lines(err, [(str(path), 1, 1, r"expected a domain, found a problem")])


def test_domain_given_where_a_problem_is_expected(expect_lines, write, capsys):
    path = write("domain.pddl", DOMAIN)
    status, _, err = _check_in_process(capsys, path, path)
    assert status == 2
    expect_lines(err, [(str(path), 2, 1, r"expected a problem, found a domain")])


def test_problem_given_as_domain_after_a_comment_points_at_its_define(expect_lines, write, capsys, position):
    text = ";; p: a problem, with a header comment\n\n" + PROBLEM
    path = write("problem.pddl", text)
    status, _, err = _check_in_process(capsys, path)
    assert status == 2
    line, col = position(text, "(define")
    expect_lines(err, [(str(path), line, col, r"expected a domain, found a problem")])
