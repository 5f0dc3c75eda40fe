"""One mission of a sweep's grid (``MissionConfig``): everything that decides what it does, so
the key of its row in the table, and the options record it runs with.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, fields
from pathlib import Path

from tidyplan.loop.options import DEFAULTS, Settings
from tidyplan.worlds.rates import Rates


@dataclass(frozen=True, slots=True)
class MissionConfig:
    """One mission of the grid: everything that decides what it does (and so the row's key)."""

    scenario_file: str  # absolute path: the same sweep run from another folder finds its rows
    seed: int
    strategy: str = DEFAULTS.strategy
    faults: str = ""  # canonical ``K=V,...`` (sorted); "" for the world's baseline
    planner: str = DEFAULTS.planner
    world: str = DEFAULTS.world
    time_limit: float | None = DEFAULTS.time_limit  # the referee's seconds (None: the scenario's)
    after_limit: str = DEFAULTS.after_limit
    time_budget: float = DEFAULTS.time_budget
    patience: float = DEFAULTS.patience  # 0: improve for the whole time budget

    @property
    def key(self) -> str:
        return json.dumps(asdict(self), sort_keys=True)

    @property
    def condition(self) -> tuple:
        """Everything but the seed: the missions a summary line pools."""
        return tuple(getattr(self, f.name) for f in fields(self) if f.name != "seed")

    def settings(self) -> Settings:
        """The mission's options record, checked (an ``OptionError`` names a bad field)."""
        return Settings(
            self.strategy,
            self.seed,
            planner=self.planner,
            time_budget=self.time_budget,
            patience=self.patience,
            rates=Rates.parse(self.faults),
            world=self.world,
            time_limit=self.time_limit,
            after_limit=self.after_limit,
        )

    @classmethod
    def from_row(cls, row: dict) -> MissionConfig:
        # a row of a table made before a field was added has that field's default
        return cls(**{f.name: row[f.name] for f in fields(cls) if f.name in row})

    def trace_stem(self) -> str:
        """A readable, unique file stem: the scenario, strategy and planner, a hash of the rest of
        the condition (the same for every seed of it), the seed."""
        digest = hashlib.sha1(repr(self.condition).encode()).hexdigest()[:8]
        return f"{Path(self.scenario_file).stem}-{self.strategy}-{self.planner}-{digest}-s{self.seed}"
