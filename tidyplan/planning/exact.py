"""The exact optimum of the criterion c(π) + R(1 − p(π)), for measuring.

The default compilation plans with c + R·L, where L = Σ −ln p(a) (see
`tidyplan.pddl.criterion`). The criterion itself is f(c, L) = c + R(1 − e^(−L)):
linear in c and concave in L. A concave function over a finite set of points
is smallest at a vertex of their convex hull, and each lower-left hull vertex
is the optimum of some weighted sum c + λ·L. So the exact optimum is found by
a dichotomic search over λ with an optimal planner: start from λ = 0 (cheapest
plan) and λ = R (the surrogate's own weight; no vertex beyond it can be better,
because e^(−L) is 1-Lipschitz), and split at the λ where two known vertices
tie until no new vertex appears. Each step is one optimal planner call, so this
is for measurement on small problems, not for the robot's loop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from tidyplan.errors import PlannerError
from tidyplan.pddl import model as m
from tidyplan.pddl.criterion import DEFAULT_REWARD, Score, score
from tidyplan.planning.planner import Status, Step, plan

_EPS = 1e-6


@dataclass(frozen=True)
class Vertex:
    steps: tuple[Step, ...]
    cost: float
    risk: float  # L = Σ −ln p(a)

    def criterion(self, reward: float) -> float:
        return self.cost + reward * (1.0 - math.exp(-self.risk))


@dataclass(frozen=True)
class ExactResult:
    steps: tuple[Step, ...]
    score: Score
    stratum: int
    vertices: tuple[Vertex, ...]  # the hull vertices visited
    planner_calls: int


def _vertex(steps) -> Vertex:
    return Vertex(tuple(steps), sum(s.cost for s in steps), sum(-math.log(s.probability) for s in steps))


def exact_optimum(domain: m.Domain, problem: m.Problem, time_budget: float = 120.0) -> ExactResult | None:
    """The criterion-optimal plan within the stratum the O-FSM ranking selects."""
    reward = problem.goal_reward if problem.goal_reward is not None else DEFAULT_REWARD
    first = plan(domain, problem, planner="optimal", time_budget=time_budget)
    if first.status is not Status.SOLVED:
        return None
    stratum = first.stratum or 1
    calls = len(first.attempts)

    def solve(weight: float) -> Vertex:
        nonlocal calls
        calls += 1
        weighted = replace(problem, goal_reward=max(weight, 1e-9))
        r = plan(
            domain, weighted, planner="optimal", time_budget=time_budget, max_stratum=stratum, strata=False
        )
        if r.status is not Status.SOLVED:
            raise PlannerError(f"optimal planner gave {r.status.value} at weight {weight}")
        return _vertex(r.steps)

    cheapest, safest = solve(0.0), _vertex(first.steps)
    vertices = {(_key(cheapest)): cheapest, _key(safest): safest}
    todo = [(cheapest, safest)]
    while todo:
        a, b = todo.pop()
        if a.risk - b.risk <= _EPS or b.cost - a.cost <= _EPS:
            continue
        weight = (b.cost - a.cost) / (a.risk - b.risk)
        c = solve(weight)
        below = (c.cost + weight * c.risk) < (a.cost + weight * a.risk) - 1e-6 * max(1.0, a.cost)
        if below and _key(c) not in vertices:
            vertices[_key(c)] = c
            todo += [(a, c), (c, b)]
    best = min(vertices.values(), key=lambda v: v.criterion(reward))
    best_score = score((s.cost for s in best.steps), (s.probability for s in best.steps), reward)
    return ExactResult(best.steps, best_score, stratum, tuple(vertices.values()), calls)


def _key(v: Vertex) -> tuple[float, float]:
    return (round(v.cost, 6), round(v.risk, 6))
