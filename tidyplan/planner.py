"""Planning engines, time budgets and plan results.

`plan()` takes a dialect task, compiles it (`pddl.compile`), converts it to
unified-planning (`pddl.to_up`) and asks an engine by name, stratum by stratum
(`strata`). Results come back in the file's own names, with each step's
probability, cost and stratum and the plan's Göbelbecker criterion.

Engines and how they are run are in `tidyplan.engines`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from enum import Enum

from unified_planning.engines import PlanGenerationResultStatus as UpStatus

from .criterion import Score, score
from .engines import AXIOM_FALLBACK, DEFAULT_ENGINE, ENGINES, Engine, run
from .pddl import model as m
from .pddl.compile import CompiledTask, compile_task
from .pddl.to_up import to_up
from .strata import Attempt, Outcome, plan_by_strata

DEFAULT_TIME_BUDGET = 1.0  # wall-clock seconds for one whole plan() call
MIN_ATTEMPT_TIME = 0.25  # a later stratum still gets this long when the budget is spent
CLEANUP_TIME = 0.04  # stopping the engine and reading its plan, measured at about 20 ms


class Status(Enum):
    SOLVED = "solved"
    NO_PLAN = "no-plan"  # proven: no plan within any stratum
    UNKNOWN = "unknown"  # the budget ran out before a plan or a proof
    ERROR = "error"


@dataclass(frozen=True, slots=True)
class Step:
    name: str
    args: tuple[str, ...]
    assumption: bool
    stratum: int
    probability: float
    cost: float

    @property
    def text(self) -> str:
        """The step as the trace writes it: ``(name arg ...)``."""
        return "(" + " ".join((self.name, *self.args)) + ")"

    def to_json(self) -> dict:
        return {
            "name": self.name,
            "args": list(self.args),
            "assumption": self.assumption,
            "stratum": self.stratum,
            "probability": self.probability,
            "cost": self.cost,
        }

    def __str__(self) -> str:
        return "(" + " ".join((self.name,) + self.args) + ")"


@dataclass(frozen=True)
class PlanResult:
    status: Status
    steps: tuple[Step, ...]
    score: Score | None
    stratum: int | None  # the operator set the plan needed (P1, P2, ...)
    attempts: tuple[Attempt, ...]
    planning_time_s: float
    engine: str
    message: str = ""

    @property
    def strata(self) -> list[int]:
        return sorted({s.stratum for s in self.steps})

    def to_json(self) -> dict:
        return {
            "status": self.status.value,
            "plan": [s.to_json() for s in self.steps],
            "cost": self.score.cost if self.score else None,
            "probability": self.score.probability if self.score else None,
            "criterion": self.score.criterion if self.score else None,
            "reward": self.score.reward if self.score else None,
            "stratum": self.stratum,
            "strata": self.strata,
            "planning_time_s": round(self.planning_time_s, 4),
            "engine": self.engine,
            "attempts": [
                {"stratum": a.stratum, "outcome": a.outcome.value, "seconds": round(a.seconds, 4)}
                for a in self.attempts
            ],
            "message": self.message,
        }


def plan(
    domain: m.Domain,
    problem: m.Problem,
    planner: str = DEFAULT_ENGINE,
    time_budget: float = DEFAULT_TIME_BUDGET,
    max_stratum: int | None = None,
    strata: bool = True,
    escalate_unproven: bool = True,
) -> PlanResult:
    """One plan for the task, ranked by strata, then by the criterion.

    `time_budget` is wall-clock seconds for the whole call: compilation and
    every stratum tried. Each attempt gets what remains (at least
    MIN_ATTEMPT_TIME); an anytime engine returns its best plan at the deadline.

    With `strata=False` every operator is available at once and only the
    criterion ranks plans: what the O-FSM ranking would cost, for comparison.
    `escalate_unproven=False`: a stratum that ran out of time ends the call (status
    UNKNOWN) instead of handing over to the next (`tidyplan.strata.plan_by_strata`).
    """
    start = time.perf_counter()
    task = compile_task(domain, problem)
    engine = ENGINES.get(planner, Engine(planner))
    messages: list[str] = []

    def solve(sub: CompiledTask):
        t0 = time.perf_counter()
        deadline = t0 + max(MIN_ATTEMPT_TIME, time_budget - (t0 - start))
        outcome, steps = _solve_once(sub, task, engine, deadline, messages)
        return outcome, steps, time.perf_counter() - t0

    if strata:
        steps, stratum, attempts = plan_by_strata(task, solve, max_stratum, escalate_unproven)
    else:
        flat = task if max_stratum is None else task.restrict(max_stratum)
        outcome, steps, seconds = solve(flat)
        stratum = max((s.stratum for s in steps), default=1) if steps is not None else None
        attempts = [Attempt(max(flat.strata), outcome, seconds)]
    elapsed = time.perf_counter() - start
    if steps is None:
        outcomes = {a.outcome for a in attempts}
        if Outcome.ERROR in outcomes:
            status = Status.ERROR
        elif outcomes == {Outcome.UNSOLVABLE}:
            status = Status.NO_PLAN
        else:
            status = Status.UNKNOWN
        tried = ", ".join(f"P{a.stratum} {a.outcome.value}" for a in attempts)
        messages.insert(0, f"no plan within {tried}")
        return PlanResult(status, (), None, None, tuple(attempts), elapsed, planner, "; ".join(messages))
    result_score = score((s.cost for s in steps), (s.probability for s in steps), task.reward)
    return PlanResult(Status.SOLVED, tuple(steps), result_score, stratum, tuple(attempts), elapsed, planner)


def _solve_once(sub: CompiledTask, task: CompiledTask, engine: Engine, deadline: float, messages: list[str]):
    up_task = to_up(sub.domain, sub.problem)
    # The engine's clock starts after our conversion: give it what is left.
    budget = max(MIN_ATTEMPT_TIME, deadline - time.perf_counter() - CLEANUP_TIME)
    result = run(up_task, engine, budget)
    if result.status == UpStatus.UNSUPPORTED_PROBLEM and engine is not ENGINES[AXIOM_FALLBACK]:
        # Some searches refuse axioms (LM-cut, for one); FD makes axioms of an
        # `exists` goal or a negated quantifier. Retry with one that takes them.
        messages.append(f"{engine.up_name} refused the task (axioms?); used {AXIOM_FALLBACK}")
        result = run(up_task, ENGINES[AXIOM_FALLBACK], budget)
    if result.plan is not None:  # an empty plan too: the goal holds already
        return Outcome.SOLVED, _steps(result.plan, task)
    if result.status == UpStatus.UNSOLVABLE_PROVEN:
        return Outcome.UNSOLVABLE, None
    if result.status in (UpStatus.UNSOLVABLE_INCOMPLETELY, UpStatus.TIMEOUT, UpStatus.MEMOUT):
        return Outcome.GAVE_UP, None  # an incomplete search that found nothing proves nothing
    if time.perf_counter() >= deadline - CLEANUP_TIME:
        # Killed at the deadline mid-translation, FD reports an internal error: out of time.
        messages.append(f"{engine.up_name} ran out of time")
        return Outcome.GAVE_UP, None
    log = " ".join(lm.message for lm in result.log_messages or [] if lm.message)
    messages.append(f"{engine.up_name} ended with {result.status.name}: {log.strip()[-300:]}")
    return Outcome.ERROR, None


def _steps(up_plan, task: CompiledTask) -> list[Step]:
    steps = []
    for ai in up_plan.actions:
        name = ai.action.name
        args = tuple(p.object().name for p in ai.actual_parameters)
        info = task.info[name]
        steps.append(
            Step(
                name=info.name,
                args=args,
                assumption=info.is_assumption,
                stratum=info.stratum,
                probability=task.step_probability(name, args),
                cost=task.step_cost(name, args),
            )
        )
    return steps
