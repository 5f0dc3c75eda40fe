"""Symbolic actions as the behaviour units their domain declares (``:units``), run with recovery.

Each action of a runnable domain names its units, its parameters by name (docs/dialect.md):

    (:action take_object :parameters (?o - item ?w - waypoint)
      :units ((adjust_base ?o) (grasp ?o)) ...)

The executor binds the step's arguments to those names, builds each unit from the catalogue
(``tidyplan.exec.catalogue``; ``BUILD`` below is its one table of constructors), runs them under
layered recovery, and looks from where the robot ends up. The domain was checked before the
mission started (``tidyplan.exec.binding_check``): no binding is found missing mid-mission.

When the error layer gives up, the unit that failed tells the belief what the failure showed
(a way that is blocked, an item that is not where it was believed: ``Unit.learn``) and the loop
replans: "recovery exhausted". Assumptions never reach this module: the loop checks them
against observations.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace

from tidyplan.belief.problem import Snapshot, robot_waypoint
from tidyplan.belief.state import Belief
from tidyplan.errors import PlannerError
from tidyplan.exec import catalogue as cat
from tidyplan.exec.context import Context, Point
from tidyplan.exec.drawer_units import PullHandle
from tidyplan.exec.put_down import PutDown
from tidyplan.exec.units import AdjustBase, AlignAtDeposit, Grasp, Look, Navigate, Place
from tidyplan.monitor.recovery import RecoveryConfig, Runner
from tidyplan.monitor.unit import Unit
from tidyplan.pddl import model as m
from tidyplan.planning.planner import Step


@dataclass(slots=True)
class Report:
    """What executing one action gave: success or the failure recovery could not mend, what the
    looks on the way brought, and where the robot stands afterwards."""

    ok: bool
    failure: str | None = None
    seconds: float = 0.0
    metres: float = 0.0
    new: list[str] = field(default_factory=list)  # items seen for the first time
    recovery_exhausted: bool = False
    waypoint: str | None = None
    recoveries: int = 0
    failure_class: str | None = None
    units: tuple[str, ...] = ()  # the units the action ran (counting reads them)
    delivered: str | None = None  # the item its place unit put into a deposit
    path: list[list[float]] = field(default_factory=list)  # the track driven (Odometer.path_since)


class MonitoredExecutor:
    """The loop's one door to the robot: runs each symbolic action as its declared behaviour
    units under layered recovery (tidyplan.monitor) and reports what it did, the track driven
    included; takes the looks the loop makes outside any action. ``bind`` gives it the domain
    the mission plans with. The world's referee is not reached through it."""

    def __init__(
        self, world, emit=None, config: RecoveryConfig | None = None, domain: m.Domain | None = None
    ):
        self.world = world
        self.emit = emit or (lambda kind, **fields: None)
        self.config = config or RecoveryConfig()
        self.domain = domain

    def bind(self, domain: m.Domain) -> None:
        self.domain = domain

    def execute(self, step: Step, snapshot: Snapshot, belief: Belief, observe) -> Report:
        return self.run(step.text, self.units(step, snapshot, Context(self.world, belief, observe)), snapshot)

    def drive(self, to: str, snapshot: Snapshot, belief: Belief, observe) -> Report:
        """A move the loop makes outside any plan (to look): the navigate unit alone."""
        ctx = Context(self.world, belief, observe, start=belief.robot)
        return self.run(
            f"(move {belief.robot_wp} {to})", [Navigate(ctx, snapshot.facts.points[to], to)], snapshot
        )

    def look(self) -> list:
        """A look around from where the robot stands: the detections (``Skills.look``)."""
        return self.world.look()

    def look_into(self, deposit: str) -> list:
        """A close look into a deposit: the detections of what lies in it."""
        return self.world.look_into(deposit)

    def run(self, text: str, units: list[Unit], snapshot: Snapshot) -> Report:
        ctx = units[0].ctx
        clock = self.world.odometer
        t0, d0, mark = clock.sim_time_s, clock.distance_m, len(clock.track)

        def emit(kind, **fields):
            self.emit(kind, action=text, **fields)

        held = ctx.belief.holding
        result = Runner(self.config, emit).run(list(units))
        failed_at = None
        if not result.ok and result.where is not None:
            # at an item the belief holds; a virtual object's look from here is all around:
            # the plan's assumption about it is judged by a look from this waypoint
            if isinstance(result.where, AdjustBase | Grasp) and result.where.item in ctx.belief.items:
                failed_at = result.where.item
            result.where.learn(result.failure)
        here = _waypoint_at(ctx.points or snapshot.facts.points, ctx.belief)
        took = ctx.belief.holding if ctx.belief.holding != held else None
        look = Look(ctx, here, after_failure=not result.ok, took=took, failed_at=failed_at)
        Runner(self.config, emit).run([look])
        return Report(
            result.ok,
            None if result.ok else result.failure.what,
            clock.sim_time_s - t0,
            clock.distance_m - d0,
            ctx.new,
            not result.ok,
            here,
            result.recoveries,
            None if result.ok else result.failure.klass.value,
            tuple(u.name for u in units),
            next((u.item for u in units if isinstance(u, Place)), None) if result.ok else None,
            clock.path_since(mark),
        )

    def units(self, step: Step, snapshot: Snapshot, ctx: Context) -> list[Unit]:
        """The units the domain declares for ``step``, its arguments bound by parameter name."""
        action = self.domain.action(step.name) if self.domain is not None else None
        if action is None or action.units is None:  # checked before the mission: ours if it happens
            raise PlannerError(f"{step.text}: the domain binds no units to {step.name!r}")
        binding = dict(zip((p.name for p in action.parameters), step.args, strict=True))
        # each waypoint where the belief has it now: a grasp pose chosen anew since the plan (the
        # old one no longer usable, an item seen on it) is the one the monitor checked the plan
        # against. The plan's own point, no longer free, had no path to it: 28 s of looks and a
        # replan, about once a mission (a fifth of the replans of 18 rooms, symbolic)
        points = ctx.points = {**snapshot.facts.points, **ctx.belief.poses().points}
        # where the planner has the robot when the step starts (its robot-at): a way learnt
        # blocked is blocked from there
        ctx.start = points[robot_waypoint(replace(snapshot.facts, points=points), ctx.belief)]
        return [BUILD[c.unit](ctx, points, *(binding.get(a, a) for a in c.args)) for c in action.units]


# One constructor per catalogue unit: (context, waypoint points, arguments) -> unit
BUILD: dict[str, Callable[..., Unit]] = {
    cat.NAVIGATE: lambda ctx, pts, to: Navigate(ctx, pts[to], to),
    cat.ADJUST_POSE: lambda ctx, pts, to: Navigate(ctx, pts[to], to, careful=True),
    cat.ADJUST_BASE: lambda ctx, pts, item: AdjustBase(ctx, item),
    cat.GRASP: lambda ctx, pts, item: Grasp(ctx, item),
    cat.APPROACH_DEPOSIT: lambda ctx, pts, at: AlignAtDeposit(ctx, pts[at], at),
    cat.PLACE: lambda ctx, pts, item, deposit, at: Place(ctx, item, deposit, pts[at]),
    cat.PUT_DOWN: lambda ctx, pts, item: PutDown(ctx, item),
    cat.APPROACH_HANDLE: lambda ctx, pts, at: AlignAtDeposit(ctx, pts[at], at, hand_empty=True),
    cat.PULL_HANDLE: lambda ctx, pts, deposit: PullHandle(ctx, deposit),
}


def _waypoint_at(points: dict[str, Point], belief: Belief) -> str | None:
    """The waypoint the robot stands on, of the action's (``Context.points``)."""
    for n, p in points.items():
        if math.dist(p, belief.robot) < 0.03:
            return n
    return None
