"""The HSR's head camera (an Xtion RGB-D): what it sees is decided by its field of view, its range
and ray tests against the pybullet scene, so furniture and other objects occlude.

An object is seen when one of its sample points (on its axis: top, centre, foot) lies inside
the 58 x 45 degree frustum, between 0.8 and 3.5 m from the lens, and the ray from the lens to it
hits the object before anything else. Detection errors (false negatives and positives) are the
caller's: this module says what the sensor could see.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as p

Vec = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Camera:
    fov_h_deg: float = 58.0
    fov_v_deg: float = 45.0
    range_min: float = 0.8
    range_max: float = 3.5

    def in_view(self, eye: Vec, forward: Vec, up: Vec, point: Vec) -> bool:
        """Inside the frustum and the range (3-D distance from the lens)."""
        d = np.subtract(point, eye)
        dist = float(np.linalg.norm(d))
        if not self.range_min <= dist <= self.range_max:
            return False
        f, u = np.asarray(forward), np.asarray(up)
        right = np.cross(f, u)
        z, x, y = float(d @ f), float(d @ right), float(d @ u)
        if z <= 0:
            return False
        return (
            abs(math.degrees(math.atan2(x, z))) <= self.fov_h_deg / 2
            and abs(math.degrees(math.atan2(y, z))) <= self.fov_v_deg / 2
        )

    def seen(
        self,
        client: int,
        eye: Vec,
        forward: Vec,
        up: Vec,
        targets: Mapping[str, tuple[int, Sequence[Vec]]],
        housing: tuple[int, Sequence[int]] | None = None,
    ) -> set[str]:
        """Names of ``targets`` (name -> (body, sample points)) the camera sees from this pose.
        ``housing`` = (body, links): the parts the camera sits in, which a ray passes through
        (the lens looks out of them); any other part of the robot occludes like the room does."""
        rays: list[tuple[str, int, Vec]] = []
        for name, (body, points) in targets.items():
            rays += [(name, body, q) for q in points if self.in_view(eye, forward, up, q)]
        out: set[str] = set()
        starts = [tuple(eye)] * len(rays)
        pending = list(range(len(rays)))
        for _ in range(3):  # at most twice through the housing
            if not pending:
                break
            ends = [_along(eye, rays[k][2], past=0.05) for k in pending]  # end inside the object
            hits = p.rayTestBatch([starts[k] for k in pending], ends, physicsClientId=client)
            again = []
            for k, hit in zip(pending, hits, strict=True):
                if hit[0] == rays[k][1]:
                    out.add(rays[k][0])
                elif housing is not None and hit[0] == housing[0] and hit[1] in housing[1]:
                    starts[k] = _along(hit[3], rays[k][2], past=0.002 - math.dist(hit[3], rays[k][2]))
                    again.append(k)
            pending = again
        return out


def _along(start: Vec, point: Vec, past: float) -> Vec:
    """The point ``past`` m beyond ``point`` on the ray from ``start`` through it (negative:
    short of it)."""
    d = np.subtract(point, start)
    n = float(np.linalg.norm(d)) or 1.0
    return tuple(np.asarray(point) + d / n * past)


def sample_points(client: int, body: int) -> list[Vec]:
    """Where the camera looks for an object: on its vertical axis, 1 cm below the top, the centre,
    and 1 cm above the bottom (so a tall box close to the robot, its top nearer the lens than
    the minimum range, is still seen at its foot)."""
    (x0, y0, z0), (x1, y1, z1) = p.getAABB(body, physicsClientId=client)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    return [(cx, cy, z1 - 0.01), (cx, cy, (z0 + z1) / 2), (cx, cy, z0 + 0.01)]
