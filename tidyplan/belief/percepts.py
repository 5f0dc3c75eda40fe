"""What the camera reports to the belief: a detection, a frame taken on the way, and the fields a
sweep's stops and a frame show, as the belief counts them. The worlds make these, the belief
(``tidyplan.belief.state``) takes them in."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sim.visibility import GLANCE_TILT_DEG

Point = tuple[float, float]


@dataclass(frozen=True, slots=True)
class Detection:
    """One object the camera reports: its category, where it appears to be, and its footprint
    (an RGB-D detection gives the object's bounding box)."""

    category: str
    x: float
    y: float
    on: str = "floor"
    sx: float = 0.08
    sy: float = 0.08
    sz: float = 0.10
    # an orientation item (WRS Task 1's markers, fork and spoon): the direction, in the room, of
    # the end that must go down; None for any other object
    down: tuple[float, float, float] | None = None


@dataclass(frozen=True, slots=True)
class Frame:
    """One camera frame the robot took on its way (driving, or at work), at no cost in time: the
    camera runs while the robot moves. Where the lens stood (x, y), which way it looked (rad, the
    room's frame), how far down it was tilted (degrees; the driving tilt by default, a head aimed
    at the robot's work lower), what the detector reported."""

    at: Point
    heading: float | None  # None: a camera that sees all around (a fake world's)
    detections: list[Detection]
    tilt_deg: float = GLANCE_TILT_DEG


# Of a frame's field, the part where a miss counts (its edges cut objects, and the head's pan
# lags the base's turn): the central share of the width, and this many degrees inside its top and foot
MISS_WIDTH, MISS_EDGE_DEG = 0.8, 3.0
# A sweep's stops as the belief chooses them: headings in the room's frame this far apart (360/7 deg,
# under the camera's 58 deg width, so that the stops' frames overlap), each frame at both tilts (the
# floor from the robot's feet to table tops, as a whole sweep's)
SWEEP_STOPS = tuple(2 * math.pi * k / 7 for k in range(7))


def in_stops(at: Point, stops, xy: np.ndarray, fov_h_deg: float, width: float = 1.0) -> np.ndarray:
    """Which points ``xy`` lie within ``width`` of the camera's width of one of the ``stops``'
    headings from ``at`` (a stop's frames at both tilts hold the floor and the table tops)."""
    bearing = np.arctan2(xy[:, 1] - at[1], xy[:, 0] - at[0])
    half = math.radians(width * fov_h_deg / 2)
    inside = np.zeros(len(xy), dtype=bool)
    for h in stops:
        inside |= np.abs((bearing - h + math.pi) % (2 * math.pi) - math.pi) <= half
    return inside
