"""Symbolic actions of ``domains/tidy.pddl`` bound to what the world does, and to the belief.

Each action becomes calls on the injected world (symbolic now, pybullet later) followed by a
look from where the robot ends up; the outcome is written into the belief here, because only
this layer knows what a ``take_object`` means physically. Assumptions never reach this module:
the loop checks them against observations instead.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from tidyplan.belief import Belief, Detection
from tidyplan.planner import Step
from tidyplan.problem import Snapshot

MOVES = ("move", "move_back")


@dataclass(slots=True)
class Report:
    """What executing one action gave: success or a named failure, and what was seen after."""

    ok: bool
    failure: str | None = None
    seconds: float = 0.0
    metres: float = 0.0
    detections: list[Detection] = field(default_factory=list)
    recovery_exhausted: bool = False
    waypoint: str | None = None  # where the robot stands afterwards, when it is a waypoint


class DirectExecutor:
    """One world call per action, no recovery (the execution monitor adds that)."""

    def __init__(self, world) -> None:
        self.world = world

    def execute(self, step: Step, snapshot: Snapshot, belief: Belief) -> Report:
        points = snapshot.facts.points
        name, args = step.name, step.args
        if name in MOVES or name == "possible_ego_pose_adjustment":
            target = args[1]
            out = self.world.move(points[target], adjust=name == "possible_ego_pose_adjustment")
            if out.ok:
                belief.at(points[target], target)
                here = target
                if name == "move_back":
                    belief.must_move_back = False
            elif out.failure == "path_blocked":
                belief.blocked_moves.add((points[args[0]], points[target]))
        elif name == "take_object":
            item = belief.items[args[0]]
            out = self.world.take((item.x, item.y))
            if out.ok:
                belief.taken(args[0])
            elif out.failure == "not_found":
                belief.forget(args[0])  # nothing there: a false detection, or it moved
        elif name == "deliver_it":
            out = self.world.deliver(args[1], points[args[2]])
            if out.ok:
                belief.delivered(args[0], args[1])
        elif name == "drop_object":
            out = self.world.drop()
            if out.ok:
                belief.put(args[0], *out.at)
                belief.must_move_back = True
        else:
            raise ValueError(f"no binding for action {name!r}")
        here = self._waypoint_at(snapshot, belief)
        detections = self.world.look()
        return Report(out.ok, out.failure, out.seconds, out.metres, detections, False, here)

    @staticmethod
    def _waypoint_at(snapshot: Snapshot, belief: Belief) -> str | None:
        for n, p in snapshot.facts.points.items():
            if abs(p[0] - belief.robot[0]) < 0.03 and abs(p[1] - belief.robot[1]) < 0.03:
                return n
        return None
