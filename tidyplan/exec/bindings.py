"""Symbolic actions of ``domains/tidy.pddl`` as sequences of behaviour units, run with recovery.

Each action is its approach phase then its manipulation phase (Yamazaki et al., VII-A), and a
look from where the robot ends up:

    move, move_back              navigate                          + look
    possible_ego_pose_adjustment navigate (careful)                + look
    take_object ?o ?w            adjust_base, grasp                + look
    deliver_it ?o ?d ?w          approach_deposit, place           + look
    drop_object ?o ?w            put_down                          + look

The world is injected (the symbolic one now, the pybullet one later). When the error layer
gives up, the belief learns what the failure showed (a way that is blocked, an item that is not
where it was believed) and the loop replans: "recovery exhausted". Assumptions never reach
this module: the loop checks them against observations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from tidyplan.belief import Belief
from tidyplan.exec.units import AdjustBase, AlignAtDeposit, Context, Grasp, Look, Navigate, Place, PutDown
from tidyplan.monitor.recovery import RecoveryConfig, Runner
from tidyplan.monitor.unit import Unit
from tidyplan.planner import Step
from tidyplan.problem import Snapshot

MOVES = ("move", "move_back")
BUMP_RADIUS = 0.6  # m around the robot a close look searches after the base was stopped


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


class MonitoredExecutor:
    """Runs each symbolic action as behaviour units under layered recovery (tidyplan.monitor)."""

    def __init__(self, world, emit=None, config: RecoveryConfig | None = None) -> None:
        self.world = world
        self.emit = emit or (lambda kind, **fields: None)
        self.config = config or RecoveryConfig()

    def execute(self, step: Step, snapshot: Snapshot, belief: Belief, observe) -> Report:
        ctx = Context(self.world, belief, observe)
        text = step.text
        clock = self.world.odometer
        t0, d0 = clock.sim_time_s, clock.distance_m

        def emit(kind, **fields):
            self.emit(kind, action=text, **fields)

        runner = Runner(self.config, emit)
        result = runner.run(self.units(step, snapshot, ctx))
        if result.ok and step.name == "move_back":
            belief.must_move_back = False  # the domain's effect: back where the item was taken
        if not result.ok:
            self._learn(step, snapshot, belief, result.failure.what)
            if (
                step.name in MOVES + ("possible_ego_pose_adjustment",)
                and result.failure.what == "path_blocked"
            ):
                # what stopped the base may lie too close for the head camera: look around it
                found = self.world.locate(belief.robot, BUMP_RADIUS)
                new = belief.bumped(found) if found is not None else None
                if new is not None:
                    ctx.new.append(new)
        here = _waypoint_at(snapshot, belief)
        Runner(self.config, emit).run([Look(ctx, here)])
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
        )

    def units(self, step: Step, snapshot: Snapshot, ctx: Context) -> list[Unit]:
        points = snapshot.facts.points
        name, args = step.name, step.args
        if name in MOVES:
            return [Navigate(ctx, points[args[1]], args[1])]
        if name == "possible_ego_pose_adjustment":
            return [Navigate(ctx, points[args[1]], args[1], careful=True)]
        if name == "take_object":
            return [AdjustBase(ctx, args[0]), Grasp(ctx, args[0])]
        if name == "deliver_it":
            approach = points[args[2]]
            return [AlignAtDeposit(ctx, approach, args[2]), Place(ctx, args[0], args[1], approach)]
        if name == "drop_object":
            return [PutDown(ctx, args[0])]
        raise ValueError(f"no binding for action {name!r}")

    @staticmethod
    def _learn(step: Step, snapshot: Snapshot, belief: Belief, failure: str) -> None:
        """What an exhausted recovery tells the planner through the belief."""
        points = snapshot.facts.points
        if step.name in MOVES + ("possible_ego_pose_adjustment",) and failure in ("path_blocked", "no_path"):
            to = points[step.args[1]]
            belief.blocked_moves.add((points[step.args[0]], to))
            belief.blocked_moves.add((belief.robot, to))  # from where it stopped, too
        elif step.name == "take_object" and failure == "not_found":
            belief.lost(step.args[0])  # nothing there: a false detection, or it rolled away


def _waypoint_at(snapshot: Snapshot, belief: Belief) -> str | None:
    for n, p in snapshot.facts.points.items():
        if math.dist(p, belief.robot) < 0.03:
            return n
    return None
