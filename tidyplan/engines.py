"""Planning engines by name, and running one safely.

A plain registry: our presets by name; any other name goes to
unified-planning's factory as it is (`--planner enhsp`, say, if installed).

Running an engine keeps two promises of the command line: no subprocess
outlives the call (unified-planning kills the engine's process group on a
timeout, but not when the call is interrupted otherwise: `_reap` does), and
nothing is written into the user's directory (Fast Downward's translator writes
`output.sas` to the working directory and cannot remove it when killed at the
deadline: every engine runs inside a private temporary directory).

The default of `tidyplan plan`, `lama-optimal`, runs two Fast Downward searches
side by side (one per core): LAMA 2011 anytime, and a uniform-cost search, which
is cost-optimal and on the tidy domain's 12-object problems that state
`(shortest-paths)` ends in a fraction of a second. The optimal plan is taken
when that search ends within the budget; LAMA's best plan otherwise. A mission
plans with `lama` (MISSION_ENGINE). Measurements in docs/planner.md.
"""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import threading
import time
import warnings
from dataclasses import dataclass, field

from unified_planning.engines import PlanGenerationResult, PlanGenerationResultStatus
from unified_planning.exceptions import UPException
from up_fast_downward import FastDownwardPDDLPlanner

from .errors import PlannerError


@dataclass(frozen=True, slots=True)
class Engine:
    """How to run one unified-planning engine."""

    up_name: str
    params: dict = field(default_factory=dict)
    anytime: bool = False
    about: str = ""
    race_optimal: bool = False  # run a cost-optimal search beside this anytime one


# See docs/planner.md for the measurements behind the default.
ENGINES: dict[str, Engine] = {
    "lama": Engine(
        "fast-downward",
        {"fast_downward_anytime_alias": "seq-sat-lama-2011"},
        anytime=True,
        about="Fast Downward LAMA 2011, anytime: improves the plan's cost until the time budget",
    ),
    "lama-first": Engine(
        "fast-downward",
        {"fast_downward_alias": "lama-first"},
        about="Fast Downward LAMA's first iteration: fast, ignores action costs",
    ),
    "lama-optimal": Engine(
        "fast-downward",
        {"fast_downward_anytime_alias": "seq-sat-lama-2011"},
        anytime=True,
        race_optimal=True,
        about="LAMA anytime beside a cost-optimal uniform-cost search: the optimum when found in the budget",
    ),
    "optimal": Engine("fast-downward-opt", about="Fast Downward A* with LM-cut: cost-optimal, can be slow"),
}
DEFAULT_ENGINE = "lama-optimal"
# A mission's problems leave (shortest-paths) out (docs/planner.md): with every move open the
# optimal search needs about 2 s, so within the 1 s budget it would take the simulation's core
# for nothing.
MISSION_ENGINE = "lama"
# Uniform-cost search (Dijkstra: eager search ordered by g, no reopening): cost-
# optimal, takes axioms and conditional effects. On 12-object tidy-ups LM-cut,
# hmax, iPDB and Cartesian abstractions expanded as many states as no heuristic
# at all (the optimum is set by the order of visits, which relaxations do not
# see), and FD's astar(blind()) was 2 to 6 times slower than this over the same
# states (docs/planner.md).
OPTIMAL_RACER = "eager(single(g()),reopen_closed=false)"
# Searches that accept axioms (an `exists` goal, a `forall` precondition):
AXIOM_FALLBACK = "lama-first"


def engine_names() -> list[str]:
    return sorted(ENGINES)


def run(up_task, engine: Engine, budget: float):
    """Run one engine on a UP problem for at most `budget` seconds."""
    factory = up_task.environment.factory
    caught: list[BaseException] = []
    try:
        with warnings.catch_warnings(), _private_directory(), _thread_errors(caught):
            # UP warns when it cannot tell whether an engine supports a feature;
            # the engine's own exit status says so more precisely.
            warnings.simplefilter("ignore", UserWarning)
            result = _run_engine(factory, up_task, engine, budget)
        if caught and result.plan is None:
            raise caught[0]
        return result
    except PlannerError:
        raise
    except UPException as e:
        known = ", ".join(engine_names() + up_planner_names(factory))
        reason = str(e).strip() or "no such engine"
        raise PlannerError(
            f"planner '{engine.up_name}' cannot be used: {reason}; planners here: {known}"
        ) from None
    except Exception as e:  # from an engine's thread (see _thread_errors)
        raise PlannerError(f"planner '{engine.up_name}' failed: {type(e).__name__}: {e}") from None


@contextlib.contextmanager
def _thread_errors(caught: list[BaseException]):
    """unified-planning's anytime planners search in a thread of their own, where an exception
    (its PDDL writer refusing a problem, say) would print a traceback; it is kept for the caller
    instead, who reports it when no plan came."""
    previous = threading.excepthook

    def keep(args) -> None:
        if isinstance(args.exc_value, Exception):
            caught.append(args.exc_value)
        else:
            previous(args)

    threading.excepthook = keep
    try:
        yield
    finally:
        threading.excepthook = previous


def _run_engine(factory, up_task, engine: Engine, budget: float):
    planner = None
    try:
        if engine.race_optimal:
            return _race(up_task.problem, engine, budget)
        if engine.anytime:
            with factory.AnytimePlanner(name=engine.up_name, params=engine.params) as planner:
                return _anytime_until_deadline(planner, up_task.problem, budget)
        with factory.OneshotPlanner(name=engine.up_name, params=engine.params) as planner:
            return planner.solve(up_task.problem, timeout=budget)
    except UPException:
        raise
    except Exception as e:  # an engine's own bug must not reach the user as a traceback
        raise PlannerError(f"planner '{engine.up_name}' failed: {type(e).__name__}: {e}") from None
    finally:
        _reap(planner)


def _anytime_until_deadline(planner, problem, budget: float):
    """The last plan an anytime engine found within `budget` seconds.

    unified-planning checks an anytime engine's timeout only once a second
    (it waits on the engine's output with a 1 s `select`), which overran a 1 s
    budget by up to 80 %. Here the results are read in a thread and the
    engine is killed at the deadline itself; UP's timeout stays as a backstop.
    """
    deadline = time.monotonic() + budget
    changed = threading.Event()
    search = _Search(planner, lambda p: p.get_solutions(problem, timeout=budget + 1.0), changed)
    try:
        while not search.ended.is_set():
            found = search.best()
            if found is not None and found.plan is not None and not found.plan.actions:
                break  # nothing beats the empty plan: stop searching
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            changed.wait(remaining)
            changed.clear()
    finally:
        _stop((planner, search))
    if search.failure is not None:
        raise search.failure
    return search.best() or PlanGenerationResult(
        PlanGenerationResultStatus.TIMEOUT, None, getattr(planner, "name", "anytime")
    )


class _FastDownward(FastDownwardPDDLPlanner):
    """Fast Downward with its translator output beside its plan file, in the
    engine's own temporary directory rather than the working directory, so that
    two can run at once."""

    def _base_cmd(self, plan_filename: str):
        sas = os.path.join(os.path.dirname(os.path.abspath(plan_filename)), "output.sas")
        return super()._base_cmd(plan_filename) + ["--sas-file", sas]


class _Search:
    """One engine's search in a thread: its results so far, and whether it ended."""

    def __init__(self, planner, results_of, changed: threading.Event):
        self.planner, self.results, self.failure = planner, [], None
        self.ended = threading.Event()

        def follow() -> None:
            try:
                for result in results_of(planner):
                    self.results.append(result)
                    changed.set()
            except BaseException as e:  # handed to the caller
                self.failure = e
            finally:
                self.ended.set()
                changed.set()

        threading.Thread(target=follow, daemon=True).start()

    def best(self):
        with_plan = [r for r in self.results if r.plan is not None]
        return with_plan[-1] if with_plan else (self.results[-1] if self.results else None)


UNSOLVABLE = PlanGenerationResultStatus.UNSOLVABLE_PROVEN


def _race(problem, engine: Engine, budget: float):
    """An anytime search and a cost-optimal one side by side until the deadline.

    The optimal search's plan wins as soon as it has one (no plan can be cheaper,
    so the anytime search is stopped). Either search proving that no plan exists
    ends the race. At the deadline, the anytime search's best plan."""
    deadline = time.monotonic() + budget
    changed = threading.Event()
    anytime_planner = _FastDownward(**engine.params)
    optimal_planner = _FastDownward(fast_downward_search_config=OPTIMAL_RACER)
    anytime = _Search(anytime_planner, lambda p: p.get_solutions(problem, timeout=budget + 1.0), changed)
    optimal = _Search(optimal_planner, lambda p: [p.solve(problem, timeout=budget + 1.0)], changed)
    try:
        while True:
            found = optimal.best()
            if found is not None and (found.plan is not None or found.status is UNSOLVABLE):
                return found
            last = anytime.best()
            if last is not None and last.plan is None and last.status is UNSOLVABLE:
                return last
            if anytime.ended.is_set() and optimal.ended.is_set():
                break
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            changed.wait(remaining)
            changed.clear()
    finally:
        _stop((anytime_planner, anytime), (optimal_planner, optimal))
    last = anytime.best()
    if last is not None and last.plan is not None:
        return last
    for search in (anytime, optimal):
        if search.failure is not None:
            raise search.failure
    # No plan: the anytime search's word (a refusal of axioms, say) before the optimal one's.
    timeout = PlanGenerationResult(PlanGenerationResultStatus.TIMEOUT, None, "lama-optimal")
    return last or optimal.best() or timeout


def _stop(*running) -> None:
    """Stop each (planner, search): reap until every search thread has ended, since one may
    still be writing its files and start its engine only after a first kill (an interrupt
    early in the call)."""
    stop = time.monotonic() + 5.0
    while not all(search.ended.is_set() for _, search in running) and time.monotonic() < stop:
        for planner, _ in running:
            _reap(planner)
        time.sleep(0.02)


def _reap(planner) -> None:
    """Kill the engine's process group if it is still running (an interrupt, an error)."""
    process = getattr(planner, "_process", None)
    if process is None or process.poll() is not None:
        return
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(os.getpgid(process.pid), signal.SIGKILL)
    with contextlib.suppress(Exception):
        process.wait(timeout=5)


@contextlib.contextmanager
def _private_directory():
    """Run with a fresh temporary working directory; remove it afterwards."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="tidyplan-") as tmp:
        os.chdir(tmp)
        try:
            yield tmp
        finally:
            os.chdir(here)


def up_planner_names(factory) -> list[str]:
    """unified-planning's engines that can plan (not validators, not compilers)."""
    names = []
    for name in factory.engines:
        try:
            if factory.engine(name).is_oneshot_planner():
                names.append(name)
        except Exception:  # an engine that fails to load is not one we can offer
            continue
    return names


def check_name(name: str) -> None:
    """Refuse an engine name before anything is written (a run's trace, say)."""
    if name in ENGINES:
        return
    from unified_planning.environment import get_environment

    known = up_planner_names(get_environment().factory)
    if name not in known:
        raise PlannerError(
            f"planner '{name}' cannot be used: no such engine; planners here: "
            + ", ".join(engine_names() + known)
        )
