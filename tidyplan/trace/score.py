"""The WRS Tidy Up score of a mission (docs/sources.md, "Scoring"), counted from its trace events.

10 points per object deposited, +10 when the deposit is of the object's category, a drop halving
that object's points, +50 when every object is put away within the time limit (the rulebook's
15 minutes of task 1; a delivery after it scores nothing: the referee has stopped the run).
The orientation bonus is not counted: no world models an object's orientation.

One tally reads the events as they happen (the mission's summary) or from a trace file
(``tidyplan.trace.read.summarise``, a killed run too), so the two figures agree by construction.
"""

from __future__ import annotations

from tidyplan.trace.events import delivers

TIME_LIMIT_S = 15 * 60.0  # WRS 2020 / RoboCup 2021 DSPL rulebook: task 1 (tidy up) has 15 minutes
DEPOSIT_POINTS = 10.0
CATEGORY_POINTS = 10.0
ALL_PUT_AWAY_POINTS = 50.0


class WrsTally:
    """Feed it each event (``see``); ``score()`` at any time is the score so far.

    Drops are ``recovery`` events of a ``grasp_drop`` failure (the monitor saw the held object
    fall); each is charged to the object the last successful grasping action took, the one in
    the hand. Whether a deposit is of the right category is the referee's verdict in the
    ``end`` event (``misplaced``: tidied into another category's deposit), since the belief's
    name of a delivered object does not say which true object it was."""

    def __init__(self, time_limit_s: float = TIME_LIMIT_S) -> None:
        self.time_limit_s = time_limit_s
        self.held: str | None = None
        self.drops: dict[str, int] = {}
        self.in_time: list[float] = []  # the points of each object deposited within the limit
        self.objects: int | None = None
        self.misplaced = 0
        self.ended_well = False

    def see(self, e: dict) -> None:
        kind = e.get("kind")
        if kind == "start":
            self.objects = sum((e.get("expected") or {}).values()) or None
        elif kind == "action" and e.get("ok"):
            if delivers(e):
                item = e.get("delivered") or self.held or "?"
                if e.get("sim_s", 0.0) <= self.time_limit_s:
                    points = DEPOSIT_POINTS + CATEGORY_POINTS
                    self.in_time.append(points / 2 ** self.drops.get(item, 0))
                self.held = None
            elif "grasp" in (e.get("units") or []):
                self.held = _arg(e.get("action", ""), 1)
        elif kind == "recovery" and e.get("failure") == "grasp_drop" and e.get("layer") != "error_layer":
            if self.held is not None:
                self.drops[self.held] = self.drops.get(self.held, 0) + 1
        elif kind == "end":
            self.objects = len(e.get("items") or {}) or self.objects
            self.misplaced = len(e.get("misplaced") or [])
            self.ended_well = bool(e.get("success"))

    def score(self) -> float:
        points = sum(self.in_time) - CATEGORY_POINTS * min(self.misplaced, len(self.in_time))
        everything = self.objects is not None and len(self.in_time) >= self.objects
        if self.ended_well and everything and not self.misplaced:
            points += ALL_PUT_AWAY_POINTS
        return round(points, 2)


def wrs_score(events, time_limit_s: float = TIME_LIMIT_S) -> float:
    tally = WrsTally(time_limit_s)
    for e in events:
        tally.see(e)
    return tally.score()


def _arg(step: str, i: int) -> str | None:
    parts = step.strip("()").split()
    return parts[i] if len(parts) > i else None
