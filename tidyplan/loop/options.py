"""The options of a mission, in one record: every default written once, every value checked
once, whoever builds it (``tidyplan.run``, ``tidyplan run``, a sweep's mission, a test).

A bad value is an ``OptionError`` that names the option by its field (``time_budget: ...``);
each caller spells it in its own words (``OptionError.spelled``: ``--time-budget`` on the
command line). ``DEFAULTS`` is the record with every default, for the signatures and the help
texts that show them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from tidyplan.errors import InputError, PlannerError
from tidyplan.planning.engines import (
    DEFAULT_FIRST_PLAN_LIMIT,
    DEFAULT_TIME_BUDGET,
    MISSION_ENGINE,
    MISSION_PATIENCE,
    check_name,
)
from tidyplan.planning.strata import STRATEGIES
from tidyplan.trace.score import TIME_LIMIT_S
from tidyplan.worlds.rates import Rates
from tidyplan.worlds.registry import WORLDS

AFTER_LIMIT = ("continue", "stop")  # what the robot does once the time limit has passed


class OptionError(InputError):
    """One option's value refused: ``option`` is its field's name, ``problem`` what is wrong."""

    def __init__(self, option: str, problem: str) -> None:
        self.option, self.problem = option, problem
        super().__init__(f"{option}: {problem}")

    def spelled(self, spell) -> InputError:
        """The same refusal with the option named by ``spell(field_name)``."""
        return InputError(f"{spell(self.option)}: {self.problem}")


def cli_spelling(option: str) -> str:
    return "--" + option.replace("_", "-")


@dataclass(frozen=True, slots=True)
class Settings:
    strategy: str = "ofsm"
    seed: int = 0
    planner: str = MISSION_ENGINE
    time_budget: float = DEFAULT_TIME_BUDGET  # seconds LAMA improves each first plan, at most
    # ... ending once no cheaper plan came for so long (0: never, the whole budget; docs/planner.md)
    patience: float = MISSION_PATIENCE
    first_plan_limit: float = DEFAULT_FIRST_PLAN_LIMIT  # seconds to find it
    # a plan is adopted only when its commitment (tidyplan.planning.commitment) is at least this likely
    min_probability: float = 1e-4
    rates: Rates = field(default_factory=Rates)
    max_recovery: int = 3  # recovery iterations per failing unit before the planner reworks the task
    world: str = "pybullet"  # or "symbolic" (tidyplan.worlds.registry)
    gui: bool = False  # pybullet only: open the window and follow the robot
    # simulated seconds the WRS referee allows: the score counts what is put away within them, and
    # the robot plans for the most score in them (docs/loop.md, "Against the clock"). None: the
    # scenario's time_limit_s (WRS Task 1's 900); where it gives none, TIME_LIMIT_S for the score
    # alone, the robot planning to tidy everything
    time_limit: float | None = None
    after_limit: str = "continue"  # at the limit: "continue" tidying everything, or "stop"

    def __post_init__(self) -> None:
        if self.world not in WORLDS:
            raise OptionError("world", f"{self.world!r} is not one of {', '.join(WORLDS)}")
        if self.strategy not in STRATEGIES:
            raise OptionError("strategy", f"{self.strategy!r} is not one of {', '.join(STRATEGIES)}")
        if self.gui and self.world != "pybullet":
            raise OptionError("gui", "only the pybullet world has a window")
        for key in ("time_budget", "first_plan_limit", "time_limit"):
            value = getattr(self, key)
            if value is not None or key != "time_limit":
                if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                    raise OptionError(key, f"{value} is not a positive number of seconds")
        if self.after_limit not in AFTER_LIMIT:
            raise OptionError("after_limit", f"{self.after_limit!r} is not one of {', '.join(AFTER_LIMIT)}")
        if self.max_recovery < 0:
            raise OptionError("max_recovery", f"{self.max_recovery} is negative")
        if not 0 <= self.patience < math.inf:
            raise OptionError("patience", f"{self.patience} is not a number of seconds >= 0")
        if not 0 <= self.min_probability <= 1:
            raise OptionError("min_probability", f"{self.min_probability} is not a probability")
        try:
            check_name(self.planner)
        except PlannerError as err:  # it names the engines there are
            raise OptionError("planner", str(err)) from None

    def clock(self, scenario) -> tuple[float, float | None]:
        """(the score's time limit, the one the robot plans against: None where it plans to tidy
        everything): the option's, else the scenario's ``time_limit_s``, else the rulebook's 15
        minutes for the score alone."""
        given = self.time_limit if self.time_limit is not None else scenario.time_limit_s
        return (given if given is not None else TIME_LIMIT_S), given

    @property
    def improvement_patience(self) -> float | None:
        """The planner's patience: None where the whole budget is used (0)."""
        return self.patience or None


DEFAULTS = Settings()
