"""Moving the HSR in the pybullet scene: collision checks for the kinematic base, and physics
steps for what must really fall or settle.

The base is moved kinematically along a path (as other pybullet HSR simulations do); before
each step the base's own collision shape (a cylinder 430 mm across) is tested against the
scene, so a path through an object on the floor, a piece of furniture or a wall stops short.
Physics is stepped only when an object is let go or slips: it falls, tips and comes to rest.
"""

from __future__ import annotations

from collections.abc import Iterable

import pybullet as p

from sim.robot import HSR

TIME_STEP = 1.0 / 240.0  # pybullet's default step


TOUCH = 0.005  # m of penetration below which a contact is a graze, not a collision


def base_contacts(robot: HSR, ignore: Iterable[int] = ()) -> dict[int, float]:
    """Bodies the base's collision shape penetrates, the floor and ``ignore`` aside: body ->
    depth in metres (positive)."""
    return _penetrated(robot.client, robot.body, robot.base_link, set(ignore) | {robot.body})


def contacts(client: int, body: int, ignore: Iterable[int] = ()) -> dict[int, float]:
    """Bodies that ``body`` (an item) penetrates, ``ignore`` aside: body -> depth in metres. What
    the hand must not let go of: physics would throw an item out of what it is inside of, to
    whichever side is nearest, through a wall too."""
    return _penetrated(client, body, -1, set(ignore) | {body})


def _penetrated(client: int, body: int, link: int, skip: set[int]) -> dict[int, float]:
    (x0, y0, z0), (x1, y1, z1) = p.getAABB(body, link, physicsClientId=client)
    near = p.getOverlappingObjects((x0, y0, z0 + 0.005), (x1, y1, z1), physicsClientId=client) or []
    out = {}
    for other in sorted({b for b, _ in near} - skip):
        points = p.getClosestPoints(body, other, 0.0, linkIndexA=link, physicsClientId=client)
        depth = max((-q[8] for q in points), default=0.0)
        if depth > 0.0:
            out[other] = depth
    return out


def blocked(now: dict[int, float], before: dict[int, float]) -> list[int]:
    """Bodies a step runs into: penetrated deeper than a graze, and deeper than before the motion
    began (an object that fell against the base must not pin the robot where it stands)."""
    return sorted(b for b, d in now.items() if d > TOUCH and d > before.get(b, 0.0) + TOUCH)


REST_SPEED = 0.002  # m/s (and rad/s over ten): a body slower than this has come to rest
REST_CHECK = 12  # steps between two looks at the bodies' speeds (20 per simulated second)
REST_AFTER = 0.3  # s stepped at least: a box tipping off a balance starts slowly


def settle(robot: HSR, seconds: float, bodies: Iterable[int] = ()) -> float:
    """Step the physics for ``seconds`` with the robot holding its posture, or until every one of
    ``bodies`` has come to rest (after REST_AFTER, three looks in a row 0.05 s apart, all slower
    than REST_SPEED): stepping on would move nothing. The simulated seconds stepped."""
    robot.hold_still()
    watched = list(bodies)
    steps, still = round(seconds / TIME_STEP), 0
    for i in range(1, steps + 1):
        p.stepSimulation(physicsClientId=robot.client)
        if watched and i % REST_CHECK == 0:
            still = still + 1 if all(_at_rest(robot.client, b) for b in watched) else 0
            if still >= 3 and i * TIME_STEP >= REST_AFTER:
                return i * TIME_STEP
    return steps * TIME_STEP


def _at_rest(client: int, body: int) -> bool:
    linear, angular = p.getBaseVelocity(body, physicsClientId=client)
    return max(map(abs, linear)) < REST_SPEED and max(map(abs, angular)) < 10 * REST_SPEED
