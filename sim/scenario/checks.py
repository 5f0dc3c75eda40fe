"""Small pieces of reading a scenario file (``sim.scenario.read``): where TOML's own syntax
error is, the checks on numbers, and how a key and a vector are written in a message."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from sim.grid import Box


def syntax_message(path: str, text: str, message: str) -> str:
    """``path:line:col: what`` from tomllib's "what (at line L, column C)"."""
    m = re.fullmatch(r"(.*) \(at line (\d+), column (\d+)\)", message, re.S)
    if m:
        return f"{path}:{m[2]}:{m[3]}: {m[1]}"
    m = re.fullmatch(r"(.*) \(at end of document\)", message, re.S)
    if m:  # point just past the last character
        line, col = text.count("\n") + 1, len(text) - text.rfind("\n")
        return f"{path}:{line}:{col}: {m[1]} (at end of document)"
    return f"{path}: {message}"


REQUIRED: Any = object()
Check = Callable[[float], str | None]


def number_range(lo: float, hi: float = math.inf, *, open_lo: bool = True, what: str = "") -> Check:
    """A check that a number lies in (lo, hi] (or [lo, hi] when not ``open_lo``)."""
    text = what or (
        f"must be {'>' if open_lo else '>='} {lo:g}"
        if hi == math.inf
        else f"must be in {'(' if open_lo else '['}{lo:g}, {hi:g}]"
    )
    return lambda v: None if (lo < v if open_lo else lo <= v) and v <= hi else text


def is_number(v: Any) -> bool:
    """int or float, finite; TOML's true/false are not numbers here."""
    return not isinstance(v, bool) and isinstance(v, int | float) and math.isfinite(v)


def key_path(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def fmt(p: tuple[float, ...]) -> str:
    return "(" + ", ".join(f"{v:g}" for v in p) + ")"


positive, non_negative = number_range(0), number_range(0, open_lo=False)
probability = number_range(0, 1, open_lo=False, what="must be a probability in [0, 1]")
ROBOT_CHECKS = {"radius": positive, "nav_margin": non_negative, "speed": positive}
SENSING_CHECKS = {
    "range_min": non_negative,
    "range_max": positive,
    "fov_h_deg": number_range(0, 360),
    "fov_v_deg": number_range(0, 180),
    "false_negative": probability,
    "false_positive": probability,
    "camera_height": positive,
    "look_down_deg": number_range(0, 90),
}
DRAWER_CHECKS = {"travel": positive, "width": positive, "rim": positive, "handle_height": positive}


def overlap(a: Box, b: Box) -> bool:
    """Whether two footprints share area (touching edges do not count)."""
    return abs(a.cx - b.cx) < (a.sx + b.sx) / 2 and abs(a.cy - b.cy) < (a.sy + b.sy) / 2
