"""Bad input, fuzzed: real files mutated at random never make a traceback or an unplaced message.

The inputs are the IPC corpus's domains and problems, the project's domains/, problems/ and
scenario files, and a trace made here by a short symbolic mission. The mutations and the
properties are bench/fuzz.py's (which runs 10,000 cases; here hypothesis runs a few hundred,
derandomized, so the suite is the same on every run): tokens and lines deleted, duplicated and
swapped, the file cut, bytes that are not UTF-8, 100,000 open brackets, brackets nested deep and
closed, numbers replaced by odd ones; for traces also JSON lines corrupted and bytes dropped.

Each case runs the command line in this process with TIDYPLAN_TRACEBACK=1, so a bug of ours
raises instead of becoming exit 4: `check` for PDDL (never `plan`: a search may rightly be
long), `run --world symbolic` with a 1 s simulated limit for scenarios (`check` takes PDDL
only), `trace` and `trace --html` for traces. What must hold (docs/commands.md): the exit status
is one the command defines (0 or 2; `run` also 1, a mission that failed); on exit 2 stderr has
at least one line and every line is one located message, said once: `path:line:col: ` inside
the file for PDDL, the file's path first for scenarios and traces.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tidyplan.cli.main import main

_spec = importlib.util.spec_from_file_location("bench_fuzz", Path(__file__).parents[1] / "bench" / "fuzz.py")
fuzz = importlib.util.module_from_spec(_spec)
sys.modules["bench_fuzz"] = fuzz  # its dataclasses look their module up there
_spec.loader.exec_module(fuzz)

CORPUS = fuzz.corpus_root()
CORPUS_SEEDS = fuzz.corpus_seeds(CORPUS) if CORPUS.is_dir() else []
PROJECT_SEEDS = fuzz.project_seeds()
NO_CORPUS = f"PDDL corpus not found at {CORPUS} (set {fuzz.CORPUS_ENV} to its folder)"

# derandomize and no example database: the same cases on every run and every machine
FUZZ = dict(
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def _seeds(kind: str, seeds: list) -> list:
    return [s for s in seeds if s.kind == kind]


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@pytest.fixture(scope="module")
def mission_trace(tmp_path_factory) -> Path:
    """Case I in the symbolic world with faults (replans and recoveries in it), 300 s simulated."""
    return fuzz.make_trace(tmp_path_factory.mktemp("mission"))


_count = iter(range(10**9))


def _holds(seed, names: list[str], data: bytes, folder: Path) -> None:
    """Run one mutated input and hold its outcome to the properties of the module's doc."""
    n = next(_count)
    case = folder / f"c{n}"
    case.mkdir()
    o = fuzz.run_case(seed, data, case, f"c{n}{seed.path.suffix}")
    where = f"{seed.name} after {names}: {' '.join(o.argv)}"
    assert o.traceback is None, f"{where}\n{o.traceback}"
    assert o.status in fuzz.STATUSES[seed.kind], f"{where}: exit {o.status}\n{o.err}"
    if o.status == 2:
        assert o.err.strip(), f"{where}: exit 2 and nothing said"
    if o.status == 2 or seed.kind in ("domain", "problem"):
        assert fuzz.unlocated(seed.kind, o.err, o.files) == [], f"{where}\n{o.err}"
    lines = o.err.splitlines()
    assert len(lines) == len(set(lines)), f"{where}: a message said twice\n{o.err}"


def _names(kind: str):
    return st.lists(st.sampled_from(fuzz.mutations_for(kind)), min_size=1, max_size=3)


# ------------------------------------------------------------------ PDDL
@pytest.mark.skipif(not CORPUS_SEEDS, reason=NO_CORPUS)
@settings(max_examples=60, **FUZZ)
@given(data=st.data())
def test_a_mutated_ipc_domain_is_read_or_refused_at_a_place_inside_it(data, folder):
    seed = data.draw(st.sampled_from(_seeds("domain", CORPUS_SEEDS)), label="seed")
    names = data.draw(_names("domain"), label="mutations")
    names, mutated = fuzz.mutate("domain", seed.path.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


@pytest.mark.skipif(not CORPUS_SEEDS, reason=NO_CORPUS)
@settings(max_examples=60, **FUZZ)
@given(data=st.data())
def test_a_mutated_ipc_problem_is_read_or_refused_at_a_place_inside_it(data, folder):
    seed = data.draw(st.sampled_from(_seeds("problem", CORPUS_SEEDS)), label="seed")
    names = data.draw(_names("problem"), label="mutations")
    names, mutated = fuzz.mutate("problem", seed.path.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


@settings(max_examples=80, **FUZZ)
@given(data=st.data())
def test_a_mutated_project_domain_or_problem_is_read_or_refused_at_a_place_inside_it(data, folder):
    seeds = _seeds("domain", PROJECT_SEEDS) + _seeds("problem", PROJECT_SEEDS)
    seed = data.draw(st.sampled_from(seeds), label="seed")
    names = data.draw(_names(seed.kind), label="mutations")
    names, mutated = fuzz.mutate(seed.kind, seed.path.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


# ------------------------------------------------------------------ scenarios
@settings(max_examples=40, **FUZZ)
@given(data=st.data())
def test_a_mutated_scenario_runs_or_is_refused_naming_its_file(data, folder):
    seed = data.draw(st.sampled_from(_seeds("scenario", PROJECT_SEEDS)), label="seed")
    names = data.draw(_names("scenario"), label="mutations")
    names, mutated = fuzz.mutate("scenario", seed.path.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


# ------------------------------------------------------------------ traces
@settings(max_examples=60, **FUZZ)
@given(data=st.data())
def test_a_damaged_trace_is_told_or_refused_in_one_line(data, folder, mission_trace):
    seed = fuzz.Seed("trace", mission_trace)
    names = data.draw(_names("trace"), label="mutations")
    names, mutated = fuzz.mutate("trace", mission_trace.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


@settings(max_examples=40, **FUZZ)
@given(data=st.data())
def test_a_damaged_trace_becomes_a_page_or_is_refused_in_one_line(data, folder, mission_trace):
    seed = fuzz.Seed("html", mission_trace)
    names = data.draw(_names("html"), label="mutations")
    names, mutated = fuzz.mutate("html", mission_trace.read_bytes(), data.draw(st.randoms()), names)
    _holds(seed, names, mutated, folder)


# ------------------------------------------------------------------ the properties themselves
def test_the_location_check_flags_what_it_should(tmp_path):
    """`unlocated` is what every case above leans on: it must refuse what is not located."""
    f = tmp_path / "d.pddl"
    f.write_text("(define\n  (domain d))\n")  # lines 1-2, then the empty line where the file ends
    ok = [f"{f}:1:1: fine", f"{f}:2:14: just past the end of line 2", f"{f}:3:1: where the file ends"]
    assert fuzz.unlocated("domain", "\n".join(ok), [f]) == []
    for bad in (f"{f}: no place", "elsewhere:1:1: another file"):
        assert fuzz.unlocated("domain", bad, [f]) == [bad]
    for bad in (f"{f}:4:1: past the end", f"{f}:2:15: past line 2", f"{f}:0:1: line 0", f"{f}:1:0: col 0"):
        assert fuzz.unlocated("domain", bad, [f]) == [f"outside the file (3 lines): {bad}"]
    assert fuzz.unlocated("trace", f"{f}: not a tidyplan trace: line 3 is not JSON", [f]) == []
    assert fuzz.unlocated("trace", "tidyplan: something", [f]) == ["tidyplan: something"]


def test_the_generators_are_seeded():
    """The benchmark's figures come back with its seed: the same mutations from the same seed."""
    import random

    data = fuzz.project_seeds()[0].path.read_bytes()
    runs = [fuzz.mutate("domain", data, random.Random(7)) for _ in range(2)]
    assert runs[0] == runs[1] and runs[0][1] != data


# ------------------------------------------------------------------ what the fuzzing found
def _check(capsys, *paths: Path) -> tuple[int, list[str]]:
    status = main(["check", *map(str, paths)])
    return status, capsys.readouterr().err.splitlines()


def test_text_before_the_define_with_a_paren_left_open_is_a_syntax_error_not_an_index_error(write, capsys):
    """Found by bench/fuzz.py: nothing open where the parser stopped made `never_closed` index an
    empty stack (IndexError, exit 4). The parser's own message is the first mistake."""
    path = write("d.pddl", "x (define")
    assert _check(capsys, path) == (2, [f"{path}:1:1: unexpected 'x'; expected '('"])
    path = write("e.pddl", "(define (domain d)) (")
    status, err = _check(capsys, path)
    assert status == 2 and len(err) == 1 and err[0].startswith(f"{path}:1:21: unexpected '('")


def test_a_nul_byte_in_pddl_is_refused_at_its_line_and_column(write, capsys):
    """Found by bench/fuzz.py: a NUL byte was "binary file" with no place; now where it is."""
    path = write("d.pddl", b"(define (domain d)\n  (:requirements\x00 :strips))\n")
    assert _check(capsys, path) == (2, [f"{path}:2:17: binary file, not PDDL text"])


FORMULA_DOMAIN = """\
(define (domain d)
  (:predicates (p))
  (:action a :parameters () :precondition (and {} (p)) :effect (not (p))))
"""


def test_formulas_nested_past_the_limit_are_refused_at_the_first_paren_too_deep(write, capsys):
    """Found by bench/fuzz.py: `(and (and ... ))` 1,000 deep (balanced) ran the checker out of
    Python's recursion limit (RecursionError, exit 4). The reader refuses more than MAX_DEPTH
    levels at the first '(' past it; a file nested exactly MAX_DEPTH deep is read."""
    from tidyplan.pddl.syntax import MAX_DEPTH

    outer = 3  # define, action, the precondition's (and
    at_limit = MAX_DEPTH - outer
    path = write("ok.pddl", FORMULA_DOMAIN.format("(and " * at_limit + ")" * at_limit))
    status, err = _check(capsys, path)
    assert (status, err) == (0, [])
    deep = 1000
    text = FORMULA_DOMAIN.format("(and " * deep + ")" * deep)
    path = write("deep.pddl", text)
    # the first '(' past the limit: the (at_limit + 1)-th put in after the precondition's (and
    line, col = 3, text.splitlines()[2].index("(and ") + 1 + 5 * (at_limit + 1)
    message = f"nested more than {MAX_DEPTH} levels deep; tidyplan reads formulas up to that depth"
    assert _check(capsys, path) == (2, [f"{path}:{line}:{col}: {message}"])


def _trace_with(mission_trace: Path, name: str, line: str) -> Path:
    """The mission's trace with ``line`` put in as its fourth line, beside it."""
    lines = mission_trace.read_text().split("\n")
    path = mission_trace.parent / name
    path.write_text("\n".join([*lines[:3], line, *lines[3:]]))
    return path


@pytest.mark.parametrize(
    ("line", "why"),
    [
        ('{"kind": "x", "a": ' + "[" * 100_000 + "]" * 100_000 + "}", "line 4 is nested too deeply to read"),
        ('{"kind": "x", "a": ' + "9" * 5000 + "}", "line 4 has a number of too many digits to read"),
    ],
    ids=["nested-100000-deep", "number-of-5000-digits"],
)
def test_a_trace_line_json_cannot_decode_is_bad_input_not_a_traceback(mission_trace, capsys, line, why):
    """Found by bench/fuzz.py: json.loads raises RecursionError and ValueError (Python's 4,300-digit
    limit for int()) besides JSONDecodeError; both escaped the reader (exit 4)."""
    path = _trace_with(mission_trace, f"json-{len(line)}.jsonl", line)
    assert main(["trace", str(path)]) == 2
    assert capsys.readouterr().err.splitlines() == [f"{path}: not a tidyplan trace: {why}"]


@pytest.mark.parametrize(
    ("event", "why"),
    [
        ({"kind": "observe", "new": 1.5}, 'whose "new" is not a list of strings'),
        ({"kind": "action", "action": "(x)", "ok": True, "metres": {}}, 'whose "metres" is not a number'),
        ({"kind": "action", "action": "(x)", "ok": True, "path": [[1]]}, 'whose "path" is not a list of'),
        ({"kind": "unit", "unit": "grasp", "step": "do", "action": 3}, 'whose "action" is not a string'),
    ],
    ids=["observe-new-a-number", "action-metres-an-object", "action-path-a-1d-point", "unit-action-a-number"],
)
def test_a_trace_event_with_a_field_of_the_wrong_kind_is_bad_input_not_a_traceback(
    mission_trace, capsys, event, why
):
    """Found by bench/fuzz.py: fields the readers take as they are (a count's list, a distance, the
    track's points, a unit's action) of another kind were TypeError, ValueError or AttributeError in
    the story or the page (exit 4). The reader now checks them where they are present."""
    import json

    path = _trace_with(
        mission_trace, f"field-{len(why)}.jsonl", json.dumps({"sim_s": 1, "wall_s": 1, **event})
    )
    for args in ([], ["--html", str(path.with_suffix(".html"))]):
        assert main(["trace", str(path), *args]) == 2
        (line,) = capsys.readouterr().err.splitlines()
        assert line.startswith(f"{path}: not a tidyplan trace: line 4: ") and why in line, line


def test_recovery_steps_missing_a_field_are_counted_not_a_traceback(mission_trace, capsys):
    """Found by bench/fuzz.py: a recovery event without its failure class sorted None among the
    classes' names (TypeError). It is counted under None, listed last."""
    import json

    step = {"kind": "recovery", "sim_s": 1, "wall_s": 1, "unit": "grasp", "layer": "retry"}
    path = _trace_with(mission_trace, "recovery.jsonl", json.dumps(step))
    assert main(["trace", str(path), "--json"]) == 0
    by_class = json.loads(capsys.readouterr().out)["recovery_steps"]["by_class"]
    assert list(by_class)[-1] == "null" and by_class["null"] == 1


@pytest.mark.parametrize(
    ("value", "why"),
    [
        ("[" * 100_000 + "]" * 100_000, "arrays or inline tables nested too deeply to read"),
        ("9" * 5000, "a number of too many digits to read"),
    ],
    ids=["nested-100000-deep", "number-of-5000-digits"],
)
def test_a_scenario_tomllib_cannot_decode_is_bad_input_not_a_traceback(write, value, why):
    """Found by bench/fuzz.py: tomllib raises RecursionError and ValueError besides its
    TOMLDecodeError; both escaped the scenario reader (exit 4 from `tidyplan run`)."""
    from sim.scenario.model import ScenarioError
    from sim.scenario.read import load

    path = write("s.toml", f"schema = 1\nname = {value}\n")
    with pytest.raises(ScenarioError) as info:
        load(path)
    assert info.value.messages == [f"{path}: {why}"]


def test_a_plan_events_problem_name_the_os_refuses_is_a_file_not_there_not_the_pages_fault(
    mission_trace, capsys
):
    """Found by bench/fuzz.py: a problem path of 100,000 characters made Path.is_file raise
    ENAMETOOLONG, which `--html` reported as its own page's "cannot write the page: File name too
    long" (exit 2, the wrong file named). The page is written, as for a PDDL folder gone; `--replan`
    says it cannot compare the facts."""
    import json

    lines = mission_trace.read_text().split("\n")
    replans = []
    for i, line in enumerate(lines):  # every plan event's problem named so
        if '"kind": "plan"' in line or '"kind":"plan"' in line:
            event = json.loads(line)
            event["problem"] = "x" * 100_000
            lines[i] = json.dumps(event)
            replans.append(event["replan"])
    assert max(replans) >= 1  # a replan to compare with the one before it
    path = mission_trace.parent / "long-name.jsonl"
    path.write_text("\n".join(lines))
    page = mission_trace.parent / "long-name.html"
    assert main(["trace", str(path), "--html", str(page)]) == 0
    assert page.is_file() and "cannot write" not in capsys.readouterr().err
    assert main(["trace", str(path), "--replan", str(max(replans))]) == 0
    assert "cannot be had (File name too long)" in capsys.readouterr().out


def test_an_action_whose_units_are_not_names_is_bad_input_not_a_traceback(mission_trace, capsys):
    """Found by bench/fuzz.py: an action event's ``units`` as a number made the score's count of
    deliveries raise a TypeError."""
    import json

    lines = mission_trace.read_text().split("\n")
    at = next(i for i, line in enumerate(lines) if '"kind":"action"' in line or '"kind": "action"' in line)
    event = json.loads(lines[at])
    event["units"] = 3
    lines[at] = json.dumps(event)
    path = mission_trace.parent / "units.jsonl"
    path.write_text("\n".join(lines))
    assert main(["trace", str(path)]) == 2
    err = capsys.readouterr().err
    assert '"units"' in err and "Traceback" not in err
