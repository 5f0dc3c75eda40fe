"""Fast Downward run directly: its translator in this process, its search as a child process.

Through unified-planning a plan costs three processes (Fast Downward's driver, its translator,
its search), the task written twice (unified-planning's problem, then its PDDL), and an
interpreter started twice. Here the plain PDDL the compiler writes goes straight to Fast
Downward's translator (the `fast-downward.translate` package that comes with up-fast-downward),
in this process; its SAS task goes to the search binary of the same package, whose plan files
are read as they appear. docs/planner.md has the measurements.

Time has two parts (`search`): the first plan is sought until `first_limit`; once there is one,
an anytime search improves it for `improve` seconds more. A search that ends before either
(proved the task unsolvable, or proved its last plan optimal) ends the call then.

No subprocess outlives the call: each search runs in its own process group, killed on the way
out whatever happened (an interrupt included), in a private temporary directory that is removed.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import io
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

from fast_downward.translate import main as translator
from fast_downward.translate import normalize, options, pddl, pddl_parser, timers
from fast_downward.translate.pddl import effects as fd_effects
from fast_downward.translate.pddl_parser import lisp_parser, parsing_functions

from tidyplan.errors import PlannerError

# Found without importing up_fast_downward, whose import brings unified-planning's (1.5 s).
_DOWNWARD = Path(importlib.util.find_spec("up_fast_downward").submodule_search_locations[0]) / "downward"
SEARCH_BINARY = _DOWNWARD / "builds" / "release" / "bin" / "downward"
POLL = 0.005  # seconds between looks at the search's plan files
_wait = time.sleep  # the wait between looks (a test interrupts the call there)


def alias(name: str) -> list[str]:
    """A search alias of Fast Downward's driver (`lama-first`, `seq-sat-lama-2011`, ...) as the
    search binary's arguments; read from the driver that ships with it, so it stays its own."""
    return list(_driver("aliases").ALIASES[name])


def _driver(module: str):
    """A module of Fast Downward's driver, loaded as a package of its own (see _DOWNWARD)."""
    package = "tidyplan_fast_downward_driver"
    if package not in sys.modules:
        init = _DOWNWARD / "driver" / "__init__.py"
        spec = importlib.util.spec_from_file_location(
            package, init, submodule_search_locations=[str(init.parent)]
        )
        sys.modules[package] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[package])
    return importlib.import_module(f"{package}.{module}")


# The search binary's exit codes (Fast Downward's driver/returncodes.py).
SUCCESS = 0
UNSOLVABLE, UNSOLVED_INCOMPLETE, UNSUPPORTED = 11, 12, 34


class Ending(Enum):
    SOLVED = "solved"  # a plan, and the search ended (it could not improve it, or was not anytime)
    IMPROVING = "improving"  # a plan; stopped while still improving it
    UNSOLVABLE = "unsolvable"
    GAVE_UP = "gave-up"  # an incomplete search ended without a plan
    OUT_OF_TIME = "out-of-time"  # no plan within the first-plan limit
    UNSUPPORTED = "unsupported"  # the search refuses the task (axioms for LM-cut, say)
    ERROR = "error"


@dataclass
class Plan:
    actions: list[tuple[str, ...]]  # (name, arg, ...) as the SAS task names them (the translator lower-cases)
    cost: int
    at: float  # time.perf_counter() when it was read


@dataclass
class Result:
    ending: Ending
    plan: Plan | None
    search_s: float = 0.0
    plans_found: int = 0
    message: str = ""
    first_plan_at: float | None = None  # time.perf_counter() of the first plan of any search


@dataclass(frozen=True, slots=True)
class Search:
    """One search configuration: the search binary's arguments, and whether it is anytime."""

    args: tuple[str, ...]
    anytime: bool


# ---------------------------------------------------------------------- translation
def translate(domain_text: str, problem_text: str):
    """Fast Downward's translator on PDDL text, in this process: its SAS task."""
    if options.options is None:
        options.set_options(["domain.pddl", "problem.pddl"])
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out), _guarded_foralls():
            domain = lisp_parser.parse_nested_list(io.StringIO(domain_text))
            problem = lisp_parser.parse_nested_list(io.StringIO(problem_text))
            task = parsing_functions.parse_task(domain, problem)
            with timers.timing("Normalizing task"):
                normalize.normalize(task)
            return translator.pddl_to_sas(task)
    except (SystemExit, pddl_parser.ParseError, AssertionError) as e:
        # The PDDL is the compiler's, from a checked task: this is a bug of ours or Fast Downward's.
        said = out.getvalue().strip().splitlines()[-3:]
        raise PlannerError(f"Fast Downward's translator refused the task: {e} {' '.join(said)}") from None


@contextlib.contextmanager
def _guarded_foralls():
    """Fast Downward's translator instantiates a universal effect over every tuple of objects of
    its variables' types, and only then tests the condition. tidy.pddl's take_object has one,
    `(forall (?a ?b - waypoint) (when (blocks ?o ?a ?b) ...))`: at 96 objects that is 2,809
    tuples for each take operator. Where the condition has a positive atom over every variable,
    only the tuples the translator could find true (in the initial state or reachable) are
    tried, in the order the translator would have tried them, so the SAS task is the same
    (tests/test_grounding.py compares them); the translation of a 96-object problem took
    3.5-4.3 s so, 4.9-5.1 s without (docs/planner.md)."""
    original = fd_effects.Effect.instantiate
    facts: dict[str, set[tuple[str, ...]]] = {}
    # (predicate, positions of the values the action binds) -> those values -> the atoms' args
    by_bound: dict[tuple[str, tuple[int, ...]], dict[tuple[str, ...], list[tuple[str, ...]]]] = {}

    def instantiate(self, var_mapping, init_facts, fluent_facts, objects_by_type, result):
        guard = _guard(self)
        if guard is None:
            return original(self, var_mapping, init_facts, fluent_facts, objects_by_type, result)
        if not facts:
            for fact in (*init_facts, *fluent_facts):
                if isinstance(fact, pddl.Atom):
                    facts.setdefault(fact.predicate, set()).add(tuple(fact.args))
        names = [p.name for p in self.parameters]
        fixed = tuple(i for i, arg in enumerate(guard.args) if arg not in names)
        key = (guard.predicate, fixed)
        if key not in by_bound:
            table = by_bound[key] = {}
            for args in facts.get(guard.predicate, ()):
                table.setdefault(tuple(args[i] for i in fixed), []).append(args)
        wanted = tuple(var_mapping.get(guard.args[i], guard.args[i]) for i in fixed)
        places = [{o: i for i, o in enumerate(objects_by_type.get(p.type_name, []))} for p in self.parameters]
        combos = []
        for args in by_bound[key].get(wanted, ()):
            bound: dict[str, str] = {}
            if any(bound.setdefault(a, v) != v for a, v in zip(guard.args, args, strict=True) if a in names):
                continue  # a variable twice in the atom, with two values
            try:
                at = [places[k][bound[name]] for k, name in enumerate(names)]
            except KeyError:  # an object not of the variable's type
                continue
            combos.append((at[::-1], [bound[name] for name in names]))
        mapping = var_mapping.copy()
        for _, objects in sorted(combos):  # the first variable varies fastest, as the translator's
            mapping.update(zip(names, objects, strict=True))
            self._instantiate(mapping, init_facts, fluent_facts, result)

    fd_effects.Effect.instantiate = instantiate
    try:
        yield
    finally:
        fd_effects.Effect.instantiate = original


def _guard(effect):
    """A positive atom of the effect's condition over all its variables, or None."""
    if not effect.parameters:
        return None
    names = {p.name for p in effect.parameters}
    parts = effect.condition.parts if isinstance(effect.condition, pddl.Conjunction) else (effect.condition,)
    for part in parts:
        if isinstance(part, pddl.Atom) and names <= set(part.args):
            return part
    return None


def sas_text(sas_task) -> str:
    out = io.StringIO()
    sas_task.output(out)
    return out.getvalue()


# ---------------------------------------------------------------------- search
def search(
    sas: str, searches: Sequence[Search], first_deadline: float, improve: float, patience: float | None = None
) -> Result:
    """Run the searches side by side (one process each) on one SAS task.

    The first plan is sought until `first_deadline` (a `time.perf_counter()` time); after the
    first plan of any search, `improve` seconds more. With `patience`, where every search is
    anytime, the improvement also ends once no cheaper plan has come for `patience` seconds: LAMA
    on a mission's replans mostly finds its plans in the first tenths of a second and then none
    (docs/planner.md), and the robot waits for every second it deliberates. A search that ends
    with a plan it cannot improve (a non-anytime search, or an anytime one that finished) ends
    the call: with more
    than one search, the first listed that ended so wins (the optimal search beside LAMA), else
    the cheapest plan found.
    """
    start = time.perf_counter()
    if start >= first_deadline:  # the limit was spent before the search (translating, say)
        return Result(Ending.OUT_OF_TIME, None, message="no time left for the search")
    with tempfile.TemporaryDirectory(prefix="tidyplan-fd-") as tmp:
        sas_path = os.path.join(tmp, "output.sas")
        with open(sas_path, "w", encoding="ascii", errors="replace") as f:
            f.write(sas)
        result = _search(sas_path, tmp, searches, first_deadline, improve, patience)
    result.search_s = time.perf_counter() - start
    return result


class _Running:
    def __init__(self, index: int, search: Search, sas_path: str, tmp: str) -> None:
        self.search = search
        self.plan_path = os.path.join(tmp, f"plan-{index}")
        self.log = open(os.path.join(tmp, f"log-{index}"), "w+b")  # noqa: SIM115 - closed in stop()
        try:
            with open(sas_path, "rb") as sas:
                self.process = subprocess.Popen(
                    [str(SEARCH_BINARY), *search.args, "--internal-plan-file", self.plan_path],
                    stdin=sas,
                    stdout=self.log,
                    stderr=subprocess.STDOUT,
                    cwd=tmp,
                    start_new_session=True,  # its own process group: killed whole in stop()
                )
        except OSError as e:
            self.log.close()
            raise PlannerError(f"cannot start Fast Downward's search ({SEARCH_BINARY}): {e}") from None
        self.plans: list[Plan] = []
        self.started = time.perf_counter()

    def poll_plans(self) -> None:
        """Read plan files that are complete (a plan ends with its cost line)."""
        while True:
            n = len(self.plans) + 1
            path = f"{self.plan_path}.{n}" if self.search.anytime else self.plan_path
            if not self.search.anytime and self.plans:
                return
            plan = _read_plan(path, time.perf_counter())
            if plan is None:
                return
            self.plans.append(plan)

    def ended(self) -> int | None:
        return self.process.poll()

    def stop(self) -> None:
        if self.process.poll() is None:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(self.process.pid, signal.SIGKILL)
        with contextlib.suppress(Exception):
            self.process.wait(timeout=5)
        self.log.close()

    def tail(self) -> str:
        with contextlib.suppress(Exception):
            self.log.flush()
            self.log.seek(0)
            lines = self.log.read().decode("utf-8", "replace").strip().splitlines()
            return " ".join(lines[-3:])[-300:]
        return ""


_COST = re.compile(r";\s*cost\s*=\s*(\d+)")


def _read_plan(path: str, at: float) -> Plan | None:
    try:
        with open(path, encoding="ascii", errors="replace") as f:
            text = f.read()
    except FileNotFoundError:
        return None
    cost = _COST.search(text)
    if cost is None:
        return None  # still being written
    actions = [tuple(line.strip()[1:-1].split()) for line in text.splitlines() if line.startswith("(")]
    return Plan(actions, int(cost.group(1)), at)


def _search(sas_path: str, tmp: str, searches, first_deadline: float, improve: float, patience: float | None):
    running: list[_Running] = []
    try:
        for i, s in enumerate(searches):
            running.append(_Running(i, s, sas_path, tmp))
        result = _follow(running, first_deadline, improve, patience)
    finally:
        for r in running:
            r.stop()
    found = [p.at for r in running for p in r.plans]
    result.first_plan_at = min(found, default=None)
    return result


def _follow(running: list[_Running], first_deadline: float, improve: float, patience: float | None) -> Result:
    first_at: float | None = None
    best, best_at = None, 0.0  # the cheapest plan so far, and when it came
    if not all(r.search.anytime for r in running):
        patience = None  # an optimal search beside LAMA is waited for: its plan ends the call
    while True:
        for r in running:
            r.poll_plans()
            if r.plans and not r.search.anytime:
                return Result(Ending.SOLVED, r.plans[-1], plans_found=1)  # its one plan: final
        codes = [r.ended() for r in running]
        for r, code in zip(running, codes, strict=True):
            if code is None:
                continue
            r.poll_plans()  # a plan written just before the end
            if r.plans and (code == SUCCESS or not r.search.anytime):
                return Result(Ending.SOLVED, r.plans[-1], plans_found=len(r.plans))
            if code == UNSOLVABLE and not any(x.plans for x in running):
                return Result(Ending.UNSOLVABLE, None)
        found = [p for r in running for p in r.plans]
        if found and first_at is None:
            first_at = time.perf_counter()
        if found and (best is None or min(p.cost for p in found) < best):
            best, best_at = min(p.cost for p in found), time.perf_counter()
        if all(code is not None for code in codes):
            return _ended(running, codes, found)
        now = time.perf_counter()
        if (first_at is not None and now >= first_at + improve) or (
            first_at is None and now >= first_deadline
        ):
            break
        if patience is not None and best is not None and now >= best_at + patience:
            break  # no cheaper plan for `patience` seconds
        _wait(POLL)
    for r in running:
        r.poll_plans()
    found = [p for r in running for p in r.plans]
    if found:
        return Result(Ending.IMPROVING, min(found, key=lambda p: p.cost), plans_found=len(found))
    return Result(Ending.OUT_OF_TIME, None, message="no plan within the first-plan limit")


def _ended(running: list[_Running], codes: list[int | None], found: list[Plan]) -> Result:
    if found:
        return Result(Ending.SOLVED, min(found, key=lambda p: p.cost), plans_found=len(found))
    if UNSUPPORTED in codes:
        r = running[codes.index(UNSUPPORTED)]
        return Result(Ending.UNSUPPORTED, None, message=r.tail())
    if all(code == UNSOLVED_INCOMPLETE for code in codes):
        return Result(Ending.GAVE_UP, None, message="the search ended without a plan (incomplete)")
    said = "; ".join(f"exit {c}: {r.tail()}" for r, c in zip(running, codes, strict=True))
    return Result(Ending.ERROR, None, message=f"Fast Downward's search failed ({said})")
