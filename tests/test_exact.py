"""The exact criterion optimum, against which the −ln p compilation is measured."""

from pathlib import Path

import pytest

from tidyplan.pddl.reader import read
from tidyplan.planning.exact import exact_optimum
from tidyplan.planning.planner import plan

DATA = Path(__file__).parent / "data"


@pytest.mark.slow
def test_exact_optimum_finds_the_plan_the_surrogate_misses():
    domain, problem = read(DATA / "gap-domain.pddl", DATA / "gap-problem.pddl")
    surrogate_plan = plan(domain, problem, planner="optimal")
    exact = exact_optimum(domain, problem)
    assert [s.name for s in surrogate_plan.steps] == ["safer"]
    assert [s.name for s in exact.steps] == ["long-shot"]
    assert exact.score.criterion == pytest.approx(950)
    assert surrogate_plan.score.criterion == pytest.approx(960)


@pytest.mark.slow
def test_exact_optimum_agrees_where_the_surrogate_is_right():
    domain, problem = read(DATA / "routes-domain.pddl", DATA / "routes-r1000.pddl")
    exact = exact_optimum(domain, problem)
    assert [s.name for s in exact.steps] == ["safe-1", "safe-2"]
    assert exact.score.criterion == pytest.approx(32 + 1000 * (1 - 0.138))
    assert len(exact.vertices) == 2  # the cheap risky route is the other hull vertex
