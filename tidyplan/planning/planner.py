"""Planning engines, time limits and plan results.

`plan()` takes a dialect task, compiles it (`pddl.compile`) and asks an engine by name, stratum
by stratum (`strata`). For our presets the compiled task is grounded from the model
(`tidyplan.planning.grounding`; Fast Downward's translator where the task is outside its fragment) and
searched by Fast Downward's search binary (`tidyplan.planning.fastdownward`); any other engine gets it
through unified-planning (`pddl.to_up`). Results come back in the file's own names, with each
step's probability, cost and stratum and the plan's Göbelbecker criterion.

Time has two limits. The first plan is sought for at most `first_plan_limit` seconds (the
whole call, every stratum tried); an anytime engine then improves it for `time_budget` seconds.
A call that finds no first plan within the limit ends "not found in time" (Status.TIMEOUT),
never "no plan", and never hands over to a higher stratum: Occam's razor asks for a plan of
the lowest stratum that has one, and a timeout does not say that P_K has none.

Engines and how they are run are in `tidyplan.planning.engines`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum

from tidyplan.errors import PlannerError
from tidyplan.pddl import model as m
from tidyplan.pddl.compile import CompiledTask, compile_task
from tidyplan.pddl.criterion import Score, score
from tidyplan.pddl.writer import domain_text, problem_text
from tidyplan.planning import fastdownward, grounding, moves, translator
from tidyplan.planning.engines import (
    DEFAULT_ENGINE,
    DEFAULT_FIRST_PLAN_LIMIT,
    DEFAULT_TIME_BUDGET,
    ENGINES,
    Engine,
    run,
)
from tidyplan.planning.shortcut import shortcut
from tidyplan.planning.strata import Attempt, Outcome, plan_by_strata


class Status(Enum):
    SOLVED = "solved"
    NO_PLAN = "no-plan"  # proven: no plan within any stratum
    TIMEOUT = "not-found-in-time"  # no first plan within the first-plan limit; nothing proven
    UNKNOWN = "unknown"  # an incomplete search ended without a plan; nothing proven
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
    # seconds: compile, ground, sas (or translate, or to_up), search; first_plan: from the call's
    # start to the first plan (the time_budget counts from there)
    phases: dict[str, float] = field(default_factory=dict)
    plans_found: int = 0  # plans the searches reported (an anytime search improving: more than 1)
    task: CompiledTask | None = field(default=None, repr=False, compare=False)  # as compiled here

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
            "phases": {k: round(v, 4) for k, v in self.phases.items()},
            "plans_found": self.plans_found,
        }


def plan(
    domain: m.Domain,
    problem: m.Problem,
    planner: str = DEFAULT_ENGINE,
    time_budget: float = DEFAULT_TIME_BUDGET,
    max_stratum: int | None = None,
    strata: bool = True,
    escalate_unproven: bool = True,
    first_plan_limit: float = DEFAULT_FIRST_PLAN_LIMIT,
    grounder: grounding.Grounder | None = None,
    reduce_moves: bool = True,
    patience: float | None = None,
    keep: Callable[[str], bool] | None = lambda obj: False,
    started: float | None = None,
) -> PlanResult:
    """One plan for the task, ranked by strata, then by the criterion.

    The first plan is sought for at most `first_plan_limit` seconds (compilation and every
    stratum tried); an anytime engine improves it for `time_budget` seconds more.

    A `grounder` (the loop's, kept across its replans) grounds the task from the model, reusing
    the ground operators of the previous task; without one, Fast Downward's translator does, in
    this process (it finds mutex groups, which the grounder does not: on floortile they halved
    the search; on the tidy domain they made no difference, docs/planner.md).

    With `strata=False` every operator is available at once and only the criterion ranks plans:
    what the O-FSM ranking would cost, for comparison. `escalate_unproven=False`: a stratum whose
    incomplete search ended without a plan ends the call (status UNKNOWN) instead of handing
    over to the next (`tidyplan.planning.strata.plan_by_strata`); running out of time always ends it.

    With `patience`, an anytime engine's improvement also ends once no cheaper plan has come for
    that many seconds (`tidyplan.planning.fastdownward.search`; never while an optimal search runs beside).

    With `reduce_moves`, a domain's pure moves go only to where there is work
    (`tidyplan.planning.moves`: the same optimum, far fewer states); plans come back in the task's words.

    The plan found loses its detours (`tidyplan.planning.shortcut`: two steps of one action that
    chain, one step where that is sound and cheaper), never passing over an object ``keep``
    names; ``keep=None`` leaves the plan as the search found it.

    `started` (a time.perf_counter() time) is when the caller's clock for the first-plan limit
    began (before reading the files, for `tidyplan plan`); the call's own start otherwise.
    Translation runs in a worker process killed at the limit (`tidyplan.planning.translator`), the
    searches in processes killed at it, and the phases in this process are followed by a look at
    the clock: a call past its limit ends "not found in time" within a fraction of a second.
    """
    start = time.perf_counter()
    deadline = (start if started is None else started) + first_plan_limit
    engine = ENGINES.get(planner, Engine(up_name=planner))
    if engine.searches and grounder is None:
        translator.warm()  # the translator's process starts while we compile
    task = compile_task(domain, problem)
    messages: list[str] = []
    phases = {"compile": time.perf_counter() - start}

    found = [0]  # plans the searches reported, over the strata tried

    def solve(sub: CompiledTask):
        t0 = time.perf_counter()
        # per stratum: what the restricted task's actions never do is part of the argument
        reduced = moves.reduce_moves(sub) if reduce_moves else None
        _add(phases, "moves", time.perf_counter() - t0)
        if reduced is not None:
            sub = reduced.task
        if time.perf_counter() >= deadline:
            messages.append("the first-plan limit ran out before the search")
            return Outcome.OUT_OF_TIME, None, time.perf_counter() - t0

        def read_back(actions) -> list[Step]:
            return _steps([reduced.original(a) for a in actions] if reduced else actions, task)

        if engine.searches:
            outcome, steps, first, plans = _solve_direct(
                sub, read_back, engine, deadline, (time_budget, patience), grounder, messages, phases
            )
        else:
            outcome, steps, first, plans = _solve_up(sub, read_back, engine, deadline, messages, phases)
        found[0] += plans
        if outcome is Outcome.SOLVED:
            phases["first_plan"] = (first or time.perf_counter()) - start
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
        elif Outcome.OUT_OF_TIME in outcomes:
            status = Status.TIMEOUT
        elif outcomes == {Outcome.UNSOLVABLE}:
            status = Status.NO_PLAN
        else:
            status = Status.UNKNOWN
        tried = ", ".join(f"P{a.stratum} {a.outcome.value}" for a in attempts)
        if status is Status.TIMEOUT:
            messages.insert(0, f"no plan found within {first_plan_limit:g} s, nothing proven ({tried})")
        else:
            messages.insert(0, f"no plan within {tried}")
        return PlanResult(
            status, (), None, None, tuple(attempts), elapsed, planner, "; ".join(messages), phases, 0, task
        )
    if keep is not None:
        t0 = time.perf_counter()
        steps = shortcut(steps, task, keep)
        phases["shortcut"] = time.perf_counter() - t0
    result_score = score((s.cost for s in steps), (s.probability for s in steps), task.reward)
    return PlanResult(
        Status.SOLVED,
        tuple(steps),
        result_score,
        stratum,
        tuple(attempts),
        elapsed,
        planner,
        "; ".join(messages),
        phases,
        found[0],
        task,
    )


def _add(phases: dict[str, float], name: str, seconds: float) -> None:
    phases[name] = phases.get(name, 0.0) + seconds


_ENDINGS = {
    fastdownward.Ending.UNSOLVABLE: Outcome.UNSOLVABLE,
    fastdownward.Ending.GAVE_UP: Outcome.GAVE_UP,
    fastdownward.Ending.OUT_OF_TIME: Outcome.OUT_OF_TIME,
}


def _solve_direct(sub, read_back, engine: Engine, deadline: float, improve, grounder, messages, phases):
    """Ground the compiled task with the loop's grounder, or translate it (one task alone, or one
    outside the grounder's fragment), then run the engine's searches. Returns (outcome, steps,
    when the first plan came (a time.perf_counter() time, or None), how many plans came)."""
    t0 = time.perf_counter()
    grounded, why = None, ""
    if grounder is not None:
        try:
            grounded = grounder.ground(sub.domain, sub.problem, deadline)
        except grounding.OutsideFragment as outside:
            why = f"translated by Fast Downward ({outside})"
        except grounding.OutOfTime:
            _add(phases, "ground", time.perf_counter() - t0)
            messages.append("the first-plan limit ran out while grounding")
            return Outcome.OUT_OF_TIME, None, None, 0
    t1 = time.perf_counter()
    if grounder is not None:
        _add(phases, "ground", t1 - t0)
    if grounded is not None:
        if grounded.unsolvable:
            return Outcome.UNSOLVABLE, None, None, 0
        if not grounded.goal:
            return Outcome.SOLVED, [], None, 1  # the goal holds already: the empty plan
        sas = grounding.sas(grounded)
        _add(phases, "sas", time.perf_counter() - t1)
    else:
        try:
            sas = translator.translate(domain_text(sub.domain), problem_text(sub.problem), deadline)
        except translator.OutOfTime:
            _add(phases, "translate", time.perf_counter() - t1)
            messages.append("the first-plan limit ran out while Fast Downward's translator ran")
            return Outcome.OUT_OF_TIME, None, None, 0
        _add(phases, "translate", time.perf_counter() - t1)
        if why and why not in messages:
            messages.append(why)
    t2 = time.perf_counter()
    result = fastdownward.search(sas, engine.searches, deadline, *improve)
    if result.ending is fastdownward.Ending.UNSUPPORTED and engine.fallback:
        messages.append(
            f"{engine.about.split(':')[0]} refused the task ({result.message}); used {engine.fallback}"
        )
        result = fastdownward.search(sas, ENGINES[engine.fallback].searches, deadline, *improve)
    _add(phases, "search", time.perf_counter() - t2)
    found = (result.first_plan_at, result.plans_found)
    if result.plan is not None:
        return Outcome.SOLVED, read_back(result.plan.actions), *found
    if result.ending in _ENDINGS:
        return _ENDINGS[result.ending], None, *found
    messages.append(result.message)
    return Outcome.ERROR, None, *found


def _solve_up(sub, read_back, engine: Engine, deadline: float, messages, phases):
    """Any other engine, through unified-planning, one-shot until the deadline."""
    from unified_planning.engines import PlanGenerationResultStatus as UpStatus

    from tidyplan.pddl.to_up import to_up

    t0 = time.perf_counter()
    up_task = to_up(sub.domain, sub.problem)
    _add(phases, "to_up", time.perf_counter() - t0)
    t1 = time.perf_counter()
    result = run(up_task, engine, max(0.0, deadline - t1))
    _add(phases, "search", time.perf_counter() - t1)
    if result.plan is not None:  # an empty plan too: the goal holds already
        names = [
            (ai.action.name, *(p.object().name for p in ai.actual_parameters)) for ai in result.plan.actions
        ]
        return Outcome.SOLVED, read_back(names), None, 1
    if result.status == UpStatus.UNSOLVABLE_PROVEN:
        return Outcome.UNSOLVABLE, None, None, 0
    if result.status in (UpStatus.TIMEOUT, UpStatus.MEMOUT) or time.perf_counter() >= deadline:
        return Outcome.OUT_OF_TIME, None, None, 0
    if result.status == UpStatus.UNSOLVABLE_INCOMPLETELY:
        return Outcome.GAVE_UP, None, None, 0  # an incomplete search that found nothing proves nothing
    log = " ".join(lm.message for lm in result.log_messages or [] if lm.message)
    messages.append(f"{engine.up_name} ended with {result.status.name}: {log.strip()[-300:]}")
    return Outcome.ERROR, None, None, 0


def _steps(actions, task: CompiledTask) -> list[Step]:
    """Plan steps ``(name, arg, ...)`` in the compiled task's names (or lower-cased, as Fast
    Downward's translator writes them) as the file's own actions."""
    names = {n: n for n in task.info} | {n.lower(): n for n in task.info}
    objects = {o.name: o.name for o in (*task.problem.all_objects, *task.domain.constants)}
    lowered = {o.lower(): o for o in objects}
    steps = []
    for action in actions:
        try:
            name = names[action[0]]
            args = tuple(objects.get(a) or lowered[a] for a in action[1:])
        except KeyError:
            raise PlannerError(
                f"the planner's plan names what the task does not: ({' '.join(action)})"
            ) from None
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
