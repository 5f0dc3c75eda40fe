"""The WRS Tidy Up score of a mission, counted from its trace events as the RoboCup 2021 DSPL
rulebook (written with the WRS committee; docs/sources.md) counts a run of Task 1:

- 10 points per object inside a deposit, +10 when the deposit is of the object's category (an
  orientation item's category, or the deposit for orientation items), +10 for an orientation
  item standing the right way in the deposit for them (the referee's ``standing``);
- +50 when every object is put away within the time limit (15 minutes; a delivery after it
  scores nothing: the referee has stopped the run);
- +50 for opening every drawer of the room without help (by the robot, within the time limit);
- a drop halves the points of the *next* object deposited, unless that is the object dropped
  (the robot picked it up again);
- no points until one object is in a deposit; arriving at a deposit with nothing in hand
  scores nothing (neither happens as a deduction).

docs/trace.md has a worked example.

One tally reads the events as they happen (the mission's summary) or from a trace file
(``tidyplan.trace.read.summarise``, a killed run too), so the two figures agree by construction.
"""

from __future__ import annotations

from tidyplan.exec.catalogue import PULL_HANDLE
from tidyplan.trace.events import delivers

TIME_LIMIT_S = 15 * 60.0  # WRS 2020 / RoboCup 2021 DSPL rulebook: task 1 (tidy up) has 15 minutes
DEPOSIT_POINTS = 10.0
CATEGORY_POINTS = 10.0
ORIENTATION_POINTS = 10.0
ALL_PUT_AWAY_POINTS = 50.0
DRAWERS_POINTS = 50.0


class WrsTally:
    """Feed it each event (``see``); ``score()`` at any time is the score so far.

    Drops are ``recovery`` events of a ``grasp_drop`` failure (the monitor saw the held object
    fall). The object in the hand then is the one the last successful grasping action took; the
    next object deposited after a drop has its points halved, unless it is the one that fell.
    Whether a deposit is of the right category is the referee's verdict in the ``end`` event
    (``misplaced``: tidied into another category's deposit), since the belief's name of a
    delivered object does not say which true object it was; so is the orientation (``standing``),
    at most one per object deposited in time. The room's drawers are the ``start``
    event's ``drawers``; a drawer is opened by an action that ran the ``pull_handle`` unit."""

    def __init__(self, time_limit_s: float = TIME_LIMIT_S) -> None:
        self.time_limit_s = time_limit_s
        self.held: str | None = None
        self.dropped: list[str] = []  # objects dropped since the last deposit
        self.in_time: list[float] = []  # the points of each object deposited within the limit
        self.objects: int | None = None
        self.drawers: set[str] = set()
        self.opened: set[str] = set()  # drawers the robot opened within the limit
        self.misplaced = 0
        self.standing = 0
        self.ended_well = False

    def see(self, e: dict) -> None:
        kind = e.get("kind")
        in_time = e.get("sim_s", 0.0) <= self.time_limit_s
        if kind == "start":
            self.objects = sum((e.get("expected") or {}).values()) or None
            self.drawers = set(e.get("drawers") or ())
        elif kind == "action" and e.get("ok"):
            units = e.get("units") or []
            if delivers(e):
                item = e.get("delivered") or self.held or "?"
                if in_time:
                    halved = bool(self.dropped) and item not in self.dropped
                    self.in_time.append((DEPOSIT_POINTS + CATEGORY_POINTS) / (2 if halved else 1))
                self.held, self.dropped = None, []
            elif "grasp" in units:
                self.held = _arg(e.get("action", ""), 1)
            elif PULL_HANDLE in units and in_time:
                self.opened.add(_arg(e.get("action", ""), 1) or "?")
        elif kind == "recovery" and e.get("failure") == "grasp_drop" and e.get("layer") != "error_layer":
            if self.held is not None:
                self.dropped.append(self.held)
        elif kind == "end":
            self.objects = len(e.get("items") or {}) or self.objects
            self.misplaced = len(e.get("misplaced") or [])
            self.standing = len(e.get("standing") or [])
            self.ended_well = bool(e.get("success"))

    def score(self) -> float:
        if not self.in_time:
            return 0.0  # no points until one object is in a deposit
        points = sum(self.in_time) - CATEGORY_POINTS * min(self.misplaced, len(self.in_time))
        points += ORIENTATION_POINTS * min(self.standing, len(self.in_time))
        everything = self.objects is not None and len(self.in_time) >= self.objects
        if self.ended_well and everything and not self.misplaced:
            points += ALL_PUT_AWAY_POINTS
        if self.drawers and self.drawers <= self.opened:
            points += DRAWERS_POINTS
        return round(points, 2)


def wrs_score(events, time_limit_s: float = TIME_LIMIT_S) -> float:
    tally = WrsTally(time_limit_s)
    for e in events:
        tally.see(e)
    return tally.score()


def _arg(step: str, i: int) -> str | None:
    parts = step.strip("()").split()
    return parts[i] if len(parts) > i else None
