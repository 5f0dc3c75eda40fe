"""Algorithm 1's removal as a behaviour unit (Yan et al.): put the held item down next to the
robot, out of the way (``drop_object``'s unit, and the put-down before a regrasp)."""

from __future__ import annotations

import math

from sim.grid import Box
from tidyplan.belief.geometry import free_spots
from tidyplan.exec.catalogue import PUT_DOWN
from tidyplan.exec.context import Context, Point
from tidyplan.monitor.unit import Failure, FailureClass, StateMonitor, Unit

A, B = FailureClass.A, FailureClass.B


class PutDown(Unit):
    """drop_object: put the held item on free floor next to the robot where it closes no way the
    robot has now, towards the walls (out of the way: Algorithm 1's "drop it in a free space
    nearby"); another spot after a failure."""

    name, phase = PUT_DOWN, "manipulation"

    def __init__(self, ctx: Context, item: str) -> None:
        self.ctx, self.item = ctx, item
        self.spot: Point | None = None
        self.tried: list[Point] = []

    def check(self):
        return None if self.ctx.world.holds() else Failure(A, "hand_empty")

    def plan(self):
        belief = self.ctx.belief
        x0, x1, y0, y1 = belief.scenario.bounds
        centre = ((x0 + x1) / 2, (y0 + y1) / 2)
        occupied = [p.xy for p in belief.placed()] + self.tried
        item = belief.items[self.item]
        if item.on == "floor":
            # not back where it was taken from: there it closes again what taking it opened (one
            # room of 96 items: taken to open a way and put back on its spot, 9 times in a row)
            occupied.append((item.x, item.y))
        # where the arm puts it down upright (a tall box held level by its side, 0.62 m out: at
        # 0.45 m the level hand was too close, the box let go tilted and toppled), and far enough
        # out that the item, turned any way, leaves the robot's own cell free: a long box (a
        # toolbox lying, 0.45 m) put down 0.45 m out shut the robot in beside it
        reach = self.ctx.world.grasp_distances(item.sz)[1]
        out = max(reach, belief.room.nav_radius + math.hypot(item.sx, item.sy) / 2 + 0.02)
        spots = free_spots(belief.scenario, self.ctx.world.pose(), occupied, (out, out))
        if not spots:
            return Failure(A, "no_spot", "no free floor next to the robot")
        # Out of the way: where it leaves every waypoint the robot reaches now reachable (it must
        # go back, and on), or else the most of them (the farthest from the centre among spots
        # that each shut some way, four in a row shut the robot in by the entrance: 96 items),
        # then the farthest from the room's centre, towards the walls.
        pose = self.ctx.world.pose()
        grid = belief.room.grid(self.ctx.floor(without=self.item))
        points = list(belief.facts().points.values())
        needed = [q for q, n in zip(points, grid.lengths_from(pose, points), strict=True) if n is not None]
        self.spot = max(
            spots,
            key=lambda p: (
                grid.reaches_with(Box(p[0], p[1], item.sx, item.sy), pose, needed),
                math.dist(p, centre),
                p,
            ),
        )
        return None

    def do(self, monitor: StateMonitor):
        out = self.ctx.world.put_down(self.spot)
        if not out.ok:
            self.tried.append(self.spot)
            return Failure(B, out.failure or "place_fail")
        self.ctx.belief.put(self.item, *self.spot, aside=True)
        return None
