"""What a mission counts, as the papers count it: actions the way Yan et al. count them (the
approach move is part of take_object), deliveries by the highest O-FSM stratum used since the
last delivery, replans by their cause (Goebelbecker's monitoring triggers), recoveries, and the
planning times. An action is known by the units it ran (``tidyplan.exec.catalogue``), not by
its name, so a domain of one's own is counted the same way. The loop adds to it; the summary
and the trace reader report it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from statistics import median

from tidyplan.exec.catalogue import DELIVERS, MOVES, REMOVES
from tidyplan.planning.planner import Step


@dataclass(slots=True)
class Counters:
    actions: int = 0
    replans: int = 0
    replans_avoided: int = 0
    recoveries: int = 0
    causes: dict[str, int] = field(default_factory=dict)
    plan_times: list[float] = field(default_factory=list)
    strata: dict[str, int] = field(default_factory=lambda: {"P1": 0, "P2": 0, "P3": 0})
    paper_actions: int = 0  # Yan et al.'s count: the approach move is part of take_object
    segment: int = 1  # highest stratum used since the last delivery
    # deliveries (counted in ``strata`` too) whose stratum was reached with a lower one only out
    # of time, not proven to have no plan: Table II keeps them apart
    unproven: int = 0
    segment_unproven: bool = False
    after_removal: bool = False  # the last action done put an item aside (Algorithm 1)

    def action(self, step: Step, report, carrying: bool) -> None:
        """One executed action, ``carrying`` as the belief has it after it: a bare move counts for
        Yan et al. only when it carries an item or is the move back after a removal."""
        self.actions += 1
        self.recoveries += report.recoveries
        self.segment = max(self.segment, step.stratum)
        bare_move = set(report.units) <= set(MOVES)
        if report.ok and (not bare_move or carrying or self.after_removal):
            self.paper_actions += 1
        if report.ok:
            self.after_removal = REMOVES in report.units
        if report.ok and DELIVERS in report.units:
            self.strata[f"P{self.segment}"] += 1
            self.unproven += self.segment_unproven
            self.segment, self.segment_unproven = 1, False

    def plan_time_summary(self) -> dict:
        t = self.plan_times
        return {"median": round(median(t), 3), "max": round(max(t), 3)} if t else {"median": 0.0, "max": 0.0}
