"""The behaviour unit of Yamazaki et al. (Section VII-A): check, plan, do.

A unit is the smallest piece of behaviour: ``check`` finds the target and verifies what must
hold (where the object is relative to the robot, that the hand holds what it should), ``plan``
computes the motion (a path, a base pose, a grasp pose), ``do`` executes it while a state monitor
runs alongside and may interrupt. Each function returns ``None`` for success or a ``Failure``
that carries its class (Section VII-B):

(A) observed before manipulation: while approaching, or at check/plan of a manipulation (the
    target is not where it should be, no pose or path can be planned);
(B) observed after manipulation with the target almost unchanged (the grasp closed on nothing,
    the placement did not let go): doing the same units again can work;
(C) the manipulation condition changed significantly (the object fell while carried): another
    unit must run first (pick it up), then the original one again.

Units of the tidy domain are in ``tidyplan.exec.units``; the layered recovery that runs them is
``tidyplan.monitor.recovery``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from enum import StrEnum

PHASES = ("check", "plan", "do")


class FailureClass(StrEnum):
    A = "A"  # before manipulation
    B = "B"  # after manipulation, target almost unchanged
    C = "C"  # manipulation condition changed significantly


@dataclass(frozen=True, slots=True)
class Failure:
    """What went wrong in one function of one unit."""

    klass: FailureClass
    what: str  # e.g. not_found, grasp_fail, grasp_drop, place_fail, path_blocked, no_path
    detail: str = ""
    interrupted: bool = False  # the state monitor stopped ``do`` part-way


@dataclass(slots=True)
class StateMonitor:
    """Conditions that must hold while a unit's ``do`` runs (Yamazaki's "state monitoring &
    error handling" layer). The world polls it at every step of a motion; the first condition
    that no longer holds interrupts the motion at once and becomes a failure of its class."""

    conditions: list[tuple[str, FailureClass, Callable[[], bool]]] = field(default_factory=list)
    fired: Failure | None = None

    def watch(self, what: str, klass: FailureClass, holds: Callable[[], bool]) -> None:
        self.conditions.append((what, klass, holds))

    def poll(self) -> bool:
        """True to go on; False once a condition failed (``fired`` says which)."""
        if self.fired is not None:
            return False
        for what, klass, holds in self.conditions:
            if not holds():
                self.fired = Failure(klass, what, "seen by the state monitor", interrupted=True)
                return False
        return True


class Unit:
    """One behaviour unit. Subclasses override the three functions; ``phase`` is the action's
    phase the unit belongs to (approach or manipulation, or observe for a look).

    ``earlier`` names a unit of the same action to run again when this one keeps failing
    (e.g. the grasp re-runs the base adjustment: "approach from another base pose");
    ``insert_for`` gives the units to run first for a class (C) failure."""

    name = "unit"
    phase = "approach"
    earlier: str | None = None

    def check(self) -> Failure | None:
        return None

    def plan(self) -> Failure | None:
        return None

    def do(self, monitor: StateMonitor) -> Failure | None:
        return None

    def insert_for(self, failure: Failure) -> list[Unit]:
        """Units that restore the condition a class (C) failure changed; none by default."""
        return []

    def learn(self, failure: Failure) -> None:
        """Called when the error layer gave up on this unit: tell the belief what ``failure``
        showed, for the planner's next problem (a way that is blocked). Nothing by default."""

    def again_differently(self) -> None:
        """Called before the unit is re-run as the earlier unit of a failing one: choose
        differently this time (another base pose). Nothing by default."""
