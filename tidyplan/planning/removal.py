"""Algorithm 1 of Yan et al.: the waypoint where a blocking object is put down.

O-FSM's plan P3 removes an object that blocks the way: "the robot should grasp
the closest object and take it to the nearest waypoint and drop it in a free
space nearby, while this waypoint needs to be previously reached and is neither
used for grasping nor for delivery (see Fig. 3)". Algorithm 1 prints this as

    repeat  w ← findTheNearestWP(W, p_r)
            if isForGrasping(w) or isForDelivery(w) or yetReached(w): w ← NULL
    until w ≠ NULL

Read literally, the loop asks for the same nearest waypoint forever, and it
rejects a waypoint already reached where the text requires one. We follow the
text, as the issue asks: waypoints in order of distance from the robot, the
first that is not for grasping, not for delivery, and already reached. Ties go
to the name, so the choice is reproducible.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Waypoint:
    name: str
    x: float
    y: float
    for_grasping: bool = False  # a pose from which an object is grasped
    for_delivery: bool = False  # a pose from which a deposit is served
    reached: bool = False  # the robot has been there in this mission


Point = tuple[float, float]


def euclidean(a: Point, b: Point) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def removal_waypoint(
    waypoints: Iterable[Waypoint],
    robot: Point,
    distance: Callable[[Point, Point], float | None] = euclidean,
) -> Waypoint | None:
    """The nearest eligible waypoint, or None when no waypoint is eligible.

    `distance` may be a path length (k(x, y) of the paper's Eq. 4); a waypoint
    it cannot reach (None) is not eligible.
    """
    eligible = []
    for w in waypoints:
        if w.for_grasping or w.for_delivery or not w.reached:
            continue
        d = distance(robot, (w.x, w.y))
        if d is not None:
            eligible.append((d, w.name, w))
    return min(eligible, key=lambda t: (t[0], t[1]))[2] if eligible else None
