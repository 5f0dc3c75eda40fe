"""The loop's calls to the planner: the goals to try, each written as a problem from the
belief, planned, and recorded in the trace with its commitment's probability. A collaborator of
the loop (``tidyplan.loop.loop.Mission`` adopts what it plans), kept apart from the monitoring:
this is where a replan's cost and its record are.
"""

from __future__ import annotations

import time
from dataclasses import replace

from tidyplan.belief.problem import Snapshot, write
from tidyplan.errors import PlannerError
from tidyplan.loop.deadline import deadline
from tidyplan.loop.goals import HORIZON, goals
from tidyplan.pddl import model as m
from tidyplan.pddl.check import check_problem
from tidyplan.pddl.simulate import Simulator
from tidyplan.planning import commitment
from tidyplan.planning.planner import PlanResult, Status
from tidyplan.planning.strata import transition, unproven_below


class Replanner:
    """Plans for the mission: ``planner(domain, problem, max_stratum) -> PlanResult``, on the
    ``belief``, recorded in ``trace`` and counted in ``count``; ``plain_domain`` is the trace's
    copy of the domain the plan events name."""

    def __init__(
        self,
        domain: m.Domain,
        belief,
        planner,
        max_stratum,
        trace,
        count,
        min_probability: float,
        plain_domain,
        clock=lambda: 0.0,
        deadline_s: float | None = None,
    ) -> None:
        self.domain, self.belief, self.planner, self.max_stratum = domain, belief, planner, max_stratum
        self.trace, self.count, self.min_probability, self.plain_domain = (
            trace,
            count,
            min_probability,
            plain_domain,
        )
        self._facts_s = 0.0  # seconds the last goals() spent on the map's facts
        self._facts = None
        self._seen: list[str] = []
        self.clock, self.deadline_s = clock, deadline_s  # the simulated clock; the limit planned against

    def goals(self):
        """The goals to try in turn (``tidyplan.loop.goals``), the items given up left out, the
        last one ``feasible`` (worked out only when reached: its goal is None)."""
        t0 = time.perf_counter()
        facts = self.belief.facts()
        self._facts_s = time.perf_counter() - t0  # the map's facts for this replan (cached since)
        against = None
        if self.deadline_s is not None and (left := self.deadline_s - self.clock()) > 0:
            against = deadline(self.belief, facts, left)
            if against is not None:
                self.trace.emit(
                    "deadline",
                    left_s=round(against.left_s, 1),
                    everything_s=round(against.everything_s, 1),
                    seconds=round(against.seconds, 1),
                    points=against.points,
                    route=list(against.route),
                    drawers=list(against.drawers),
                    put_off=list(against.put_off),
                    why=against.why(),
                )
        out = [(label, [g for g in goal if g not in self.belief.undeliverable], virtual)
               for label, goal, virtual in goals(self.belief, facts, against)]  # fmt: skip
        self._facts, self._seen = facts, out[-1][1]
        return out[:-1] + [("feasible", None, [])]

    def plan(
        self, goal, virtual, cause, why, label, previous: int | None
    ) -> tuple[PlanResult, Snapshot | None, m.Problem | None, float]:
        """One goal planned and recorded: the result, the snapshot and problem it was planned
        on, and its commitment's probability. ``previous``: the stratum of the plan it replaces."""
        if goal is None:  # the items that have a plan alone, nearest first, a horizon's worth
            goal = []  # (a planner call each: not one for every item of a 96-item room)
            for g in self._seen:
                if len(goal) == HORIZON:
                    break
                if self._alone(g):
                    goal.append(g)
            if not goal:
                nothing = PlanResult(Status.NO_PLAN, (), None, None, (), 0.0, "", "nothing feasible")
                return nothing, None, None, 0.0
        n = self.count.replans
        name = f"tidy-replan-{n:03d}"
        t0 = time.perf_counter()
        facts = self.belief.facts()
        t1 = time.perf_counter()
        facts_s, self._facts_s = t1 - t0 + self._facts_s, 0.0  # the first goal tried pays for them
        focused = label in ("horizon", "deadline")  # a part of the room: the map for its items
        snap = write(self.belief, facts, goal, virtual, name, focused, self.domain)
        problem = self._problem(snap, f"replan-{n:03d}.pddl")
        t2 = time.perf_counter()
        result = self.planner(self.domain, problem, self.max_stratum)
        t3 = time.perf_counter()
        p_commit = 0.0
        if result.status is Status.SOLVED:
            sim = Simulator(self.domain, problem)
            committed = commitment.commitment(result.steps, sim, sim.initial_state(problem), problem.goal)
            p_commit = commitment.probability(committed)
        t4 = time.perf_counter()
        seconds = facts_s + t4 - t1  # the replan: the map's facts, the problem, the planner, the check
        self.count.plan_times.append(seconds)
        base = f"replan-{n:03d}" + ("" if label == "all" else f"-{label}")
        paths = {
            "domain": self.plain_domain,
            **self.trace.save_replan(base, snap.text, self.domain, problem, result.task),
        }
        phases = {"map_facts": facts_s, "problem": t2 - t1, **result.phases, "commitment": t4 - t3}
        phases["saved"] = time.perf_counter() - t4  # the trace's copies (not part of the replan)
        self.trace.emit(
            "plan",
            replan=n,
            cause=cause.value,
            why=why,
            goal_kind=label,
            goal=list(goal),
            status=result.status.value,
            planning_time_s=round(seconds, 3),
            phases={k: round(v, 4) for k, v in phases.items()},
            plans_found=result.plans_found,
            stratum=result.stratum,
            transition=transition(previous, result.stratum) if result.stratum else None,
            attempts=[[a.stratum, a.outcome.value, round(a.seconds, 3)] for a in result.attempts],
            unproven_below=unproven_below(result.attempts),
            cost=result.score.cost if result.score else None,
            probability=round(result.score.probability, 6) if result.score else None,
            commitment_probability=round(p_commit, 6) if result.score else None,
            adopted=result.status is Status.SOLVED and p_commit >= self.min_probability,
            plan=[s.text for s in result.steps],
            assumptions=sum(s.assumption for s in result.steps),
            message=result.message,
            **paths,
        )
        return result, snap, problem, p_commit

    def _problem(self, snap: Snapshot, name: str) -> m.Problem:
        """Check a problem the writer made, as the model holds it (nothing parsed back); an error
        here is ours, not the user's: the domain's words were checked before the mission."""
        problem = replace(snap.problem, path=name)
        errors = [d for d in check_problem(problem, self.domain) if not d.warning]
        if errors:
            raise PlannerError(f"tidyplan wrote a bad problem {name}: " + "; ".join(map(str, errors)))
        return problem

    def _alone(self, item: str) -> bool:
        snap = write(self.belief, self._facts, [item], [], "tidy-alone", domain=self.domain)
        problem = self._problem(snap, "alone.pddl")
        return self.planner(self.domain, problem, self.max_stratum).status is Status.SOLVED
