"""Planning engines by name, and running one safely.

A plain registry: our presets by name, each a set of Fast Downward searches run directly
(`tidyplan.planning.fastdownward`: the SAS task from `tidyplan.planning.grounding`, the search binary of the
up-fast-downward package); any other name goes to unified-planning's factory as it is
(`--planner enhsp`, say, if installed), as a one-shot planner.

Running an engine keeps two promises of the command line: no subprocess outlives the call, and
nothing is written into the user's directory (every engine runs inside a private temporary
directory, removed afterwards).

The default of `tidyplan plan`, `lama-optimal`, runs two searches side by side (one per core): a
uniform-cost search, which is cost-optimal and on the tidy domain's 12-object problems that
state `(shortest-paths)` ends in a fraction of a second, and LAMA 2011 anytime. The optimal plan
is taken when that search ends within the improvement time after LAMA's first plan; LAMA's best
plan otherwise. A mission plans with `lama` (MISSION_ENGINE). Measurements in docs/planner.md.
"""

from __future__ import annotations

import contextlib
import os
import signal
import tempfile
import warnings
from dataclasses import dataclass

from tidyplan.errors import PlannerError
from tidyplan.planning.fastdownward import Search, alias

# Uniform-cost search (Dijkstra: eager search ordered by g, no reopening): cost-
# optimal, takes axioms and conditional effects. On 12-object tidy-ups LM-cut,
# hmax, iPDB and Cartesian abstractions expanded as many states as no heuristic
# at all (the optimum is set by the order of visits, which relaxations do not
# see), and FD's astar(blind()) was 2 to 6 times slower than this over the same
# states (docs/planner.md).
OPTIMAL_RACER = "eager(single(g()),reopen_closed=false)"


@dataclass(frozen=True, slots=True)
class Engine:
    """A preset (Fast Downward searches run side by side) or a unified-planning engine's name."""

    up_name: str = ""  # a unified-planning engine, run one-shot (no `searches`)
    searches: tuple[Search, ...] = ()
    about: str = ""
    fallback: str | None = None  # the preset to use where these searches refuse the task (axioms)

    @property
    def anytime(self) -> bool:
        return any(s.anytime for s in self.searches)


def _lama() -> Search:
    return Search(tuple(alias("seq-sat-lama-2011")), anytime=True)


# See docs/planner.md for the measurements behind the default.
ENGINES: dict[str, Engine] = {
    "lama": Engine(
        searches=(_lama(),),
        about="Fast Downward LAMA 2011, anytime: improves the plan's cost for the time budget",
    ),
    "lama-first": Engine(
        searches=(Search(tuple(alias("lama-first")), anytime=False),),
        about="Fast Downward LAMA's first iteration: fast, ignores action costs",
    ),
    "lama-optimal": Engine(
        searches=(Search(("--search", OPTIMAL_RACER), anytime=False), _lama()),
        about="a cost-optimal search beside LAMA anytime: the optimum when found in the time budget",
    ),
    "optimal": Engine(
        searches=(Search(tuple(alias("seq-opt-lmcut")), anytime=False),),
        about="Fast Downward A* with LM-cut: cost-optimal, can be slow",
        fallback="lama-first",  # LM-cut refuses axioms (a translated `exists` goal, say)
    ),
}
DEFAULT_ENGINE = "lama-optimal"
# A mission's problems leave (shortest-paths) out (docs/planner.md): with every move open the
# optimal search needs about 2 s, so it would only take the simulation's core.
MISSION_ENGINE = "lama"
# ... whose improvement a mission ends once no cheaper plan came for this many seconds: on the
# 33 problems of missions of `python bench/patience.py --seeds 2 --repeat 2 --patience 0.3,0.5`
# (costs in seconds, 2026-12-07) 0.3 s and 0.5 s each gave 31 plans as good as the whole 1 s
# (worst 1.2% dearer), in a median 0.41 s against 0.61 s; ten Task 1 rooms in pybullet took
# 13164 s against 13196 s in all (docs/planner.md, "Patience").
MISSION_PATIENCE = 0.3
DEFAULT_TIME_BUDGET = 1.0  # seconds an anytime engine improves its first plan
DEFAULT_FIRST_PLAN_LIMIT = 60.0  # seconds to find a first plan, for the whole call


def engine_names() -> list[str]:
    return sorted(ENGINES)


def run(up_task, engine: Engine, budget: float):
    """Run a unified-planning engine, one-shot, on a UP problem for at most `budget` seconds."""
    from unified_planning.exceptions import UPException  # only here: its import takes 1.5 s

    factory = up_task.environment.factory
    planner = None
    try:
        with warnings.catch_warnings(), _private_directory():
            # UP warns when it cannot tell whether an engine supports a feature;
            # the engine's own exit status says so more precisely.
            warnings.simplefilter("ignore", UserWarning)
            with factory.OneshotPlanner(name=engine.up_name) as planner:
                return planner.solve(up_task.problem, timeout=budget)
    except PlannerError:
        raise
    except UPException as e:
        known = ", ".join(engine_names() + up_planner_names(factory))
        reason = str(e).strip() or "no such engine"
        raise PlannerError(
            f"planner '{engine.up_name}' cannot be used: {reason}; planners here: {known}"
        ) from None
    except Exception as e:  # an engine's own bug must not reach the user as a traceback
        raise PlannerError(f"planner '{engine.up_name}' failed: {type(e).__name__}: {e}") from None
    finally:
        _reap(planner)  # unified-planning kills its engine on a timeout, not on an interrupt


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
