"""The plan criterion of Göbelbecker et al., Sec. 2, and its compilation to costs.

    π* = argmin_π  c(π) + R · (1 − p(π)),   p(π) = Π p(a),  c(π) = Σ c(a)

Fast Downward minimises a sum of non-negative integer costs, so each action
gets the additive cost

    cost(a) = round(S · (c(a) + R · (−ln p(a))))

Minimising Σ −ln p(a) is maximising p(π) exactly ("exact in the product").
For the criterion it is an upper bound: 1 − p ≤ −ln p, with equality as p → 1,
so plans that all succeed with high probability are ranked as the criterion
ranks them, while for risky plans the surrogate overweights risk. The distance
between the two is measured by `bench/criterion_gap.py` against the exact
optimum that `tidyplan.planning.exact` finds (see docs/criterion.md).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

DEFAULT_REWARD = 1000.0  # R when the problem gives no (:goal-reward ...)
FINE_SCALE = 100  # S for real-valued costs or probabilities: centi-units
MAX_COST = 10**8  # FD sums costs in 32-bit integers; stay well clear


@dataclass(frozen=True, slots=True)
class Score:
    """A plan's cost, success probability and criterion value."""

    cost: float
    probability: float
    reward: float

    @property
    def criterion(self) -> float:
        return self.cost + self.reward * (1.0 - self.probability)


def score(costs: Iterable[float], probabilities: Iterable[float], reward: float) -> Score:
    return Score(sum(costs), math.prod(probabilities), reward)


def surrogate(cost: float, probability: float, reward: float) -> float:
    """The additive stand-in for one action: c(a) + R · (−ln p(a))."""
    if not 0.0 < probability <= 1.0:
        raise ValueError(f"probability {probability} outside (0, 1]")
    return cost + reward * -math.log(probability)


def integer_cost(cost: float, probability: float, reward: float, scale: float) -> int:
    """The surrogate scaled and rounded for Fast Downward (integer costs only)."""
    return min(MAX_COST, round(scale * surrogate(cost, probability, reward)))


def choose_scale(costs: Iterable[float], probabilities: Iterable[float]) -> int:
    """1 when every cost is whole and every action certain; else FINE_SCALE.

    Keeping S = 1 for plain integer-cost domains means compiled PDDL has the
    same costs as the original, so plans from the corpus keep their costs.
    """
    if all(p == 1.0 for p in probabilities) and all(float(c).is_integer() for c in costs):
        return 1
    return FINE_SCALE
