"""What the behaviour units of one action share (``tidyplan.exec.units``): the world they act
in, the belief they read and write, and how a look is reported to the loop."""

from __future__ import annotations

from dataclasses import dataclass, field

from tidyplan.belief.state import Belief
from tidyplan.worlds.contract import Skills

Point = tuple[float, float]
AT_POSE = 0.03  # m: the robot stands at a pose when this close


@dataclass(slots=True)
class Context:
    """What the units of one action share: the world, the belief, and how to report a look."""

    world: Skills
    belief: Belief
    # observe(detections, waypoint, why, frames=None, stops=None) -> names of new items (the loop's)
    observe: object
    new: list[str] = field(default_factory=list)
    start: Point | None = None  # the waypoint the action starts from, where the map has it
    points: dict[str, Point] = field(default_factory=dict)  # the action's waypoints, where it began
    # item -> (the base's pose, where a close look from there found it, the reach for its height):
    # a grasp from the pose an adjustment's close look was made from needs no look of its own
    located: dict[str, tuple[Point, Point, tuple[float, float, float]]] = field(default_factory=dict)

    def look(
        self, waypoint: str | None = None, why: str = "", stops: tuple[float, ...] | None = None
    ) -> None:
        """A head sweep from where the robot stands (all around, or the pan ``stops`` only,
        headings in the room's frame); ``why`` it was taken, for the trace."""
        # an item first seen by an earlier look of this action may be forgotten by this one (a
        # false detection the next looks did not confirm): it is no longer new
        seen = self.observe(self.world.look(stops), waypoint, why, stops=stops)
        self.new = [n for n in self.new + seen if n in self.belief.items]

    def glance(self, why: str) -> None:
        """The frames the camera took on the way and one from here (``Skills.glance``): no time
        of their own; ``why``, for the trace."""
        seen = self.observe([], None, why, frames=self.world.glance())
        self.new = [n for n in self.new + seen if n in self.belief.items]

    def floor(self, without: str | None = None):
        """What the base must keep clear of beyond the furniture: the floor items (but
        ``without``) and the open drawers."""
        items = [p.box() for p in self.belief.placed() if p.on_floor and p.name != without]
        return items + self.belief.drawers_out()
