"""Göbelbecker et al., Sec. 2: π* = argmin c(π) + R(1 − p(π)), and its compilation."""

import math
from pathlib import Path

import pytest

from tidyplan.pddl.compile import compile_task
from tidyplan.pddl.criterion import choose_scale, integer_cost, score, surrogate
from tidyplan.pddl.reader import read
from tidyplan.planning.planner import Status, plan

DATA = Path(__file__).parent / "data"


def test_criterion_prefers_p_0138_with_12_more_cost_at_r_1000():
    """The paper's numbers: 12 more cost buys p 0.138 instead of 0.096."""
    safe = score([32], [0.46, 0.3], reward=1000)
    risky = score([20], [0.32, 0.3], reward=1000)
    assert safe.cost - risky.cost == 12
    assert safe.probability == pytest.approx(0.138)
    assert risky.probability == pytest.approx(0.096)
    assert safe.criterion == pytest.approx(32 + 862)
    assert risky.criterion == pytest.approx(20 + 904)
    assert safe.criterion < risky.criterion


def test_surrogate_is_exact_in_the_product_and_bounds_the_criterion():
    # −ln is additive over the plan, so Σ −ln p(a) = −ln Π p(a).
    ps = [0.9, 0.5, 0.77]
    total = sum(surrogate(0, p, 1.0) for p in ps)
    assert total == pytest.approx(-math.log(math.prod(ps)))
    # 1 − p ≤ −ln p: the surrogate never ranks a plan better than the criterion does.
    for p in (0.01, 0.1, 0.5, 0.9, 0.999, 1.0):
        assert 1 - p <= -math.log(p) + 1e-12


def test_integer_costs_scale_and_round():
    assert integer_cost(2.345, 1.0, 1000, 100) == 234 or integer_cost(2.345, 1.0, 1000, 100) == 235
    assert integer_cost(3, 1.0, 1000, 1) == 3
    assert integer_cost(0, 0.5, 1000, 1) == round(1000 * math.log(2))
    assert choose_scale([1, 2, 5], [1.0, 1.0]) == 1
    assert choose_scale([1.5], [1.0]) == 100
    assert choose_scale([1], [0.9]) == 100


def test_probability_changes_the_chosen_plan_at_r_1000():
    domain, problem = read(DATA / "routes-domain.pddl", DATA / "routes-r1000.pddl")
    result = plan(domain, problem, planner="optimal")
    assert result.status is Status.SOLVED
    assert [s.name for s in result.steps] == ["safe-1", "safe-2"]
    assert result.score.cost == 32
    assert result.score.probability == pytest.approx(0.138)


def test_without_reward_at_stake_cost_decides():
    domain, problem = read(DATA / "routes-domain.pddl", DATA / "routes-r1.pddl")
    result = plan(domain, problem, planner="optimal")
    assert [s.name for s in result.steps] == ["risky-1", "risky-2"]
    assert result.score.reward == 1


def test_default_reward_is_1000_and_costs_are_compiled_per_action():
    domain, problem = read(DATA / "routes-domain.pddl", DATA / "routes-r1000.pddl")
    task = compile_task(domain, problem)
    assert task.reward == 1000
    costs = {a.name: a.effect.parts[-1].amount for a in task.domain.actions}
    assert costs["safe-1"] == integer_cost(16, 0.46, 1000, task.scale)
    assert costs["risky-2"] == integer_cost(10, 0.3, 1000, task.scale)
