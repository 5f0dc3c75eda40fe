"""Line of sight in 3-D against axis-aligned boxes: which items the head camera can see from where.

Why boxes and segments: the scenarios hide items behind or under furniture on purpose, and the
symbolic world must agree with the pybullet one on what a look can reveal. Furniture and items
are boxes there too, so a segment from the camera to a point on the target, tested against every
other box, is the same geometry without a renderer. It is deliberately coarse: one point per
target (the centre of its top), no partial visibility, no detector noise (that is the sensing
model's false negatives, applied by the caller).

Conventions relied on by callers:
- a box is closed: a segment that only grazes a face or an edge is blocked, so a target exactly
  level with a table top behind it is not seen;
- the head pans, so ``visible`` ignores the horizontal field of view; ``in_field_of_view`` is
  there for callers that fix the heading;
- results depend on the inputs alone: names come back in the scenario's item order.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Protocol

import numpy as np

from sim.scenario.model import Furniture, Item, Scenario

Point3 = tuple[float, float, float]

# The head's tilt while the robot drives and works (sim.robot.CAMERA_TILT, -0.35 rad): a frame
# taken then shows from this many degrees below the horizon, give or take half the vertical field
GLANCE_TILT_DEG = math.degrees(0.35)


@dataclass(frozen=True, slots=True)
class Box3:
    """An axis-aligned box [x0, x1] × [y0, y1] × [z0, z1] in metres; ``name`` is for people."""

    x0: float
    x1: float
    y0: float
    y1: float
    z0: float
    z1: float
    name: str = ""

    @classmethod
    def from_furniture(cls, f: Furniture) -> Box3:
        """A furniture piece standing on the floor: z from 0 to its height."""
        return cls(f.cx - f.sx / 2, f.cx + f.sx / 2, f.cy - f.sy / 2, f.cy + f.sy / 2, 0.0, f.height, f.name)

    @classmethod
    def from_item(cls, item: Item | Solid, base_z: float) -> Box3:
        """An item whose base is at ``base_z`` (``Scenario.item_base_z``, or where it was moved):
        a scenario item, or anything shaped like one (the world's truth, the belief's items)."""
        hx, hy = item.sx / 2, item.sy / 2
        return cls(item.x - hx, item.x + hx, item.y - hy, item.y + hy, base_z, base_z + item.sz, item.name)


class Solid(Protocol):
    """What a box needs of an item: a name, the centre of its footprint, and its size."""

    name: str
    x: float
    y: float
    sx: float
    sy: float
    sz: float


def segment_hits_box(p: Sequence[float], q: Sequence[float], box: Box3) -> bool:
    """Whether the segment p→q meets the closed box (slab test; touching counts as a hit).

    Plain floats, not numpy: a handful of boxes per ray, and no rounding differences between
    a scalar and a vector path to make two runs disagree.
    """
    t0, t1 = 0.0, 1.0
    for a, b, lo, hi in zip(p, q, (box.x0, box.y0, box.z0), (box.x1, box.y1, box.z1), strict=True):
        d = b - a
        if d == 0.0:
            if a < lo or a > hi:  # parallel to this slab and outside it
                return False
            continue
        ta, tb = (lo - a) / d, (hi - a) / d
        if ta > tb:
            ta, tb = tb, ta
        t0, t1 = max(t0, ta), min(t1, tb)
        if t0 > t1:
            return False
    return True


class BoxTable(list):
    """``(owner, Box3)`` pairs, and ``fixed`` boxes beside them (the furniture, which occludes
    for every target), with all their extents as one array: which of many boxes may meet a
    segment is one array test (``near_segment``), not a slab test per box (a miss in a
    96-object room tested the furniture and every believed item against each line of sight)."""

    def __init__(self, pairs: Iterable[tuple[object, Box3]] = (), fixed: Sequence[Box3] = ()) -> None:
        super().__init__(pairs)
        self.fixed = list(fixed)
        boxes = [*self.fixed, *(b for _, b in self)]
        self.extents = np.array([(b.x0, b.x1, b.y0, b.y1, b.z0, b.z1) for b in boxes], dtype=float).reshape(
            -1, 6
        )

    def near_segment(
        self, p: Sequence[float], q: Sequence[float]
    ) -> tuple[list[Box3], list[tuple[object, Box3]]]:
        """The fixed boxes and the pairs whose box meets the segment p-q's bounding box (1e-9 m
        to spare). A box beyond it on some axis is one ``segment_hits_box`` misses (its slab's
        interval then lies wholly outside [0, 1]), so these alone decide ``visible``."""
        e, lo, hi = self.extents, np.minimum(p, q) - 1e-9, np.maximum(p, q) + 1e-9
        near = (e[:, 0] <= hi[0]) & (e[:, 1] >= lo[0]) & (e[:, 2] <= hi[1]) & (e[:, 3] >= lo[1])
        near &= (e[:, 4] <= hi[2]) & (e[:, 5] >= lo[2])
        n, ks = len(self.fixed), np.flatnonzero(near).tolist()
        return [self.fixed[k] for k in ks if k < n], [self[k - n] for k in ks if k >= n]


def visible(
    camera: Point3, target: Point3, occluders: Sequence[Box3], *, range_min: float, range_max: float
) -> bool:
    """Whether ``target`` lies within [range_min, range_max] of ``camera`` (3-D distance) with no
    occluder on the segment between them. The caller leaves out the target's own box and the box
    it stands on: the segment ends on them."""
    if not range_min <= math.dist(camera, target) <= range_max:
        return False
    return not any(segment_hits_box(camera, target, b) for b in occluders)


def visible_points(
    camera: Point3,
    targets: np.ndarray,
    occluders: Sequence[Box3],
    support: Sequence[str],
    *,
    range_min: float,
    range_max: float,
) -> np.ndarray:
    """``visible`` for many targets at once (an (N, 3) array): a boolean array, True where the
    target is in range and no occluder meets the segment from the camera. ``support[n]`` names the
    box target n stands on, which does not occlude it. The same slab test as
    ``segment_hits_box``, on arrays: the belief asks it of a thousand placement points per pose
    (21 ms a pose in plain floats, for case I's 1201 points)."""
    p = np.asarray(camera, dtype=float)
    d = targets - p  # (N, 3)
    dist = np.linalg.norm(d, axis=1)
    seen = (dist >= range_min) & (dist <= range_max)
    # the occluders are tested on the targets in range only (in a long room most are not)
    (within,) = np.nonzero(seen)
    if not len(within):
        return seen
    # and only against the occluders that meet the box around the camera and those targets: one
    # beyond it on some axis (1e-9 m to spare) meets no segment (its slab's interval then lies
    # wholly outside [0, 1]); a frame's field holds a part of the room, and 6 in 10 of the
    # furniture's boxes lie beyond it
    ends = targets[within]
    x0, y0, z0 = (np.minimum(ends.min(axis=0), p) - 1e-9).tolist()
    x1, y1, z1 = (np.maximum(ends.max(axis=0), p) + 1e-9).tolist()
    near = [
        b
        for b in occluders
        if b.x0 <= x1 and b.x1 >= x0 and b.y0 <= y1 and b.y1 >= y0 and b.z0 <= z1 and b.z1 >= z0
    ]
    seen[within] = _unoccluded(p, d[within], near, np.asarray(support, dtype=object)[within])
    return seen


def _unoccluded(p: np.ndarray, d: np.ndarray, occluders: Sequence[Box3], names: np.ndarray) -> np.ndarray:
    """For each segment p -> p + d[n]: whether no occluder but the one named names[n] meets it."""
    seen = np.ones(len(d), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / d
    parallel = d == 0.0
    for box in occluders:
        lo = np.array((box.x0, box.y0, box.z0)) - p
        hi = np.array((box.x1, box.y1, box.z1)) - p
        with np.errstate(invalid="ignore"):
            ta, tb = lo * inv, hi * inv
        t_near = np.where(parallel, -np.inf, np.minimum(ta, tb))
        t_far = np.where(parallel, np.inf, np.maximum(ta, tb))
        outside = parallel & ((lo > 0.0) | (hi < 0.0))  # parallel to a slab and outside it
        t0 = np.maximum(t_near.max(axis=1), 0.0)
        t1 = np.minimum(t_far.min(axis=1), 1.0)
        hit = (t0 <= t1) & ~outside.any(axis=1) & (names != box.name)
        seen &= ~hit
    return seen


def in_field_of_view(
    camera_xy: tuple[float, float], heading_rad: float, target_xy: tuple[float, float], fov_h_deg: float
) -> bool:
    """Whether the bearing to ``target_xy`` is within half the horizontal field of view of the
    heading (edges included); a target at the camera's own (x, y) counts as in view."""
    dx, dy = target_xy[0] - camera_xy[0], target_xy[1] - camera_xy[1]
    if dx == 0.0 and dy == 0.0:
        return True
    off = (math.atan2(dy, dx) - heading_rad + math.pi) % (2 * math.pi) - math.pi
    return abs(off) <= math.radians(fov_h_deg) / 2


def in_frame(
    camera_xy: tuple[float, float],
    heading_rad: float,
    xy: np.ndarray,
    z: np.ndarray,
    sensing,
    width: float = 1.0,
    edge_deg: float = 0.0,
    tilt_deg: float = GLANCE_TILT_DEG,
) -> np.ndarray:
    """Which points (``xy`` (N, 2), heights ``z``) lie in the field of one frame from a lens at
    ``camera_xy`` (``sensing.camera_height`` up) looking along ``heading_rad``, tilted
    ``tilt_deg`` down (the driving tilt by default): range and occlusion aside. ``width`` keeps
    that share of the field's width, ``edge_deg`` stays that far inside its top and foot."""
    dx, dy = xy[:, 0] - camera_xy[0], xy[:, 1] - camera_xy[1]
    bearing = np.degrees((np.arctan2(dy, dx) - heading_rad + math.pi) % (2 * math.pi) - math.pi)
    down = np.degrees(np.arctan2(sensing.camera_height - z, np.hypot(dx, dy)))
    lo = tilt_deg - sensing.fov_v_deg / 2 + edge_deg
    hi = tilt_deg + sensing.fov_v_deg / 2 - edge_deg
    return (np.abs(bearing) <= width * sensing.fov_h_deg / 2) & (down >= lo) & (down <= hi)


def visible_items(
    scenario: Scenario,
    camera_xy: tuple[float, float],
    items: Iterable[str] | None = None,
    moved: Mapping[str, Point3 | None] | None = None,
) -> list[str]:
    """Names of the items seen from a camera at (x, y, sensing.camera_height), in scenario order.

    ``items`` restricts which items are tested (default all); every item still occludes the
    others. ``moved`` maps an item's name to where its base centre now is, (x, y, base_z), or to
    None when it is out of the room's geometry (held by the robot): then it is neither tested nor
    an occluder. Each target is the centre of the item's top; occluders are all furniture and all
    other items, except the furniture whose top the item stands on (its footprint holds the
    item's (x, y) and its height is the item's base_z). Unknown names raise KeyError.
    """
    moved = moved or {}
    names = [i.name for i in scenario.items]
    wanted = set(names) if items is None else set(items)
    unknown = sorted((wanted | set(moved)) - set(names))
    if unknown:
        raise KeyError(f"no item named {', '.join(map(repr, unknown))} in {scenario.path}")
    placed: dict[str, tuple[Item, float]] = {}  # name -> (item at its current x, y; base_z)
    for item in scenario.items:
        if item.name not in moved:
            placed[item.name] = (item, scenario.item_base_z(item))
        elif (where := moved[item.name]) is not None:
            placed[item.name] = (replace(item, x=where[0], y=where[1]), where[2])
    furniture = [Box3.from_furniture(f) for f in scenario.furniture]
    item_boxes = {n: Box3.from_item(i, z) for n, (i, z) in placed.items()}
    s = scenario.sensing
    camera = (camera_xy[0], camera_xy[1], s.camera_height)
    seen = []
    for name, (item, base_z) in placed.items():
        if name not in wanted:
            continue
        occluders = [b for b in furniture if not _stands_on(item, base_z, b)]
        occluders += [b for n, b in item_boxes.items() if n != name]
        target = (item.x, item.y, base_z + item.sz)
        if visible(camera, target, occluders, range_min=s.range_min, range_max=s.range_max):
            seen.append(name)
    return seen


def _stands_on(item: Item, base_z: float, box: Box3) -> bool:
    """Whether the item's base centre lies on the box's top face."""
    return abs(box.z1 - base_z) < 1e-9 and box.x0 <= item.x <= box.x1 and box.y0 <= item.y <= box.y1
