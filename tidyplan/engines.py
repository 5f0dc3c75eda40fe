"""Planning engines by name, and running one safely.

A plain registry: our presets by name; any other name goes to
unified-planning's factory as it is (`--planner enhsp`, say, if installed).

Running an engine keeps two promises of the command line: no subprocess
outlives the call (unified-planning kills the engine's process group on a
timeout, but not when the call is interrupted otherwise: `_reap` does), and
nothing is written into the user's directory (Fast Downward's translator writes
`output.sas` to the working directory and cannot remove it when killed at the
deadline: every engine runs inside a private temporary directory).
"""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import threading
import warnings
from dataclasses import dataclass, field

from unified_planning.engines import PlanGenerationResult, PlanGenerationResultStatus
from unified_planning.exceptions import UPException

from .errors import PlannerError


@dataclass(frozen=True, slots=True)
class Engine:
    """How to run one unified-planning engine."""

    up_name: str
    params: dict = field(default_factory=dict)
    anytime: bool = False
    about: str = ""


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
    "optimal": Engine("fast-downward-opt", about="Fast Downward A* with LM-cut: cost-optimal, can be slow"),
}
DEFAULT_ENGINE = "lama"
# Searches that accept axioms (an `exists` goal, a `forall` precondition):
AXIOM_FALLBACK = "lama-first"


def engine_names() -> list[str]:
    return sorted(ENGINES)


def run(up_task, engine: Engine, budget: float):
    """Run one engine on a UP problem for at most `budget` seconds."""
    factory = up_task.environment.factory
    try:
        with warnings.catch_warnings(), _private_directory():
            # UP warns when it cannot tell whether an engine supports a feature;
            # the engine's own exit status says so more precisely.
            warnings.simplefilter("ignore", UserWarning)
            return _run_engine(factory, up_task, engine, budget)
    except UPException as e:
        known = ", ".join(engine_names() + up_planner_names(factory))
        reason = str(e).strip() or "no such engine"
        raise PlannerError(
            f"planner '{engine.up_name}' cannot be used: {reason}; planners here: {known}"
        ) from None


def _run_engine(factory, up_task, engine: Engine, budget: float):
    planner = None
    try:
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
    results: list = []
    failures: list[BaseException] = []
    finished = threading.Event()

    def consume() -> None:
        try:
            for result in planner.get_solutions(problem, timeout=budget + 1.0):
                results.append(result)
                if result.plan is not None and not result.plan.actions:
                    _reap(planner)  # nothing beats the empty plan: stop searching

        except BaseException as e:  # handed to the caller below
            failures.append(e)
        finally:
            finished.set()

    reader = threading.Thread(target=consume, daemon=True)
    reader.start()
    if not finished.wait(budget):
        _reap(planner)  # the engine's output ends, and with it UP's generator
        finished.wait(5.0)
    if failures:
        raise failures[0]
    with_plan = [r for r in results if r.plan is not None]
    if with_plan:
        return with_plan[-1]
    if results:
        return results[-1]
    return PlanGenerationResult(PlanGenerationResultStatus.TIMEOUT, None, getattr(planner, "name", "anytime"))


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
