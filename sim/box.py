"""A footprint on the floor plan: what the grid inflates into obstacles.

Imports: none (the bottom of sim).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned footprint: centre (cx, cy) and size (sx, sy) along x and y, in metres.

    Height is left out on purpose: the grid is the floor plan of the base, and anything the
    base cannot pass under is an obstacle whatever its height. ``name`` is for people only.
    """

    cx: float
    cy: float
    sx: float
    sy: float
    name: str = ""

    def clearance(self, x: float, y: float) -> float:
        """Distance from (x, y) to the footprint (0 inside)."""
        dx = max(abs(x - self.cx) - self.sx / 2, 0.0)
        dy = max(abs(y - self.cy) - self.sy / 2, 0.0)
        return math.hypot(dx, dy)
