"""Scenario files: the tidy-up room, its furniture, deposits, items and viewpoints, in TOML.

Why a file format of our own: the symbolic world (planning, visibility, path lengths) and the
pybullet world must be built from one description, so that a case built to hide or block an
object does so in both. The layout is documented in docs/scenario.md; this module holds the
values, ``sim/scenario_file.py`` reads and checks files into them (``load``, ``loads``).

Item heights are not stored on the item: an item's base is the floor or the top of the
furniture it stands on, so ``Scenario.item_base_z`` resolves it and one source of truth remains.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

from sim.grid import Box

SCHEMA = 1
NAME_RE = re.compile(r"[a-z][a-z0-9_-]*")
ITEM_SIZE = (0.08, 0.08, 0.10)  # m: a WRS-sized small object when the file gives no size
FLOOR = "floor"


class ScenarioError(Exception):
    """Everything wrong with one scenario file; ``messages`` holds one line per problem."""

    def __init__(self, messages: list[str]) -> None:
        self.messages: list[str] = list(messages)
        super().__init__("\n".join(self.messages))


@dataclass(frozen=True, slots=True)
class Furniture:
    """An axis-aligned box standing on the floor, z from 0 to ``height``; ``kind`` is free text
    ("table", "shelf", "bin", ...) for the pybullet world to choose a look by."""

    name: str
    cx: float
    cy: float
    sx: float
    sy: float
    height: float
    kind: str

    def box(self) -> Box:
        """The footprint, for the occupancy grid."""
        return Box(self.cx, self.cy, self.sx, self.sy, self.name)


@dataclass(frozen=True, slots=True)
class Deposit:
    """Where objects of ``category`` go: the place (x, y, z), and where the robot stands to put
    them there (``approach``; None lets the caller find a free cell near the place)."""

    name: str
    category: str
    x: float
    y: float
    z: float
    approach: tuple[float, float] | None = None


@dataclass(frozen=True, slots=True)
class Item:
    """An object to tidy, centred at (x, y), standing ``on`` the floor or a named furniture piece;
    its base height depends on that piece, see ``Scenario.item_base_z``."""

    name: str
    category: str
    x: float
    y: float
    on: str = FLOOR
    sx: float = ITEM_SIZE[0]
    sy: float = ITEM_SIZE[1]
    sz: float = ITEM_SIZE[2]

    def box(self) -> Box:
        """The footprint: an obstacle for the base when the item lies on the floor."""
        return Box(self.x, self.y, self.sx, self.sy, self.name)


@dataclass(frozen=True, slots=True)
class Viewpoint:
    """A place the robot may look from while exploring."""

    name: str
    x: float
    y: float


@dataclass(frozen=True, slots=True)
class Sensing:
    """The head camera and the detector: range in metres, fields of view in degrees, error rates
    as probabilities per look, camera height above the floor in metres. ``look_down_deg`` is how
    far below the horizon the lowest frame of a sweep sees (the HSR's lowest tilt, 37 degrees, plus
    half the vertical field of view is 59.7; 55 leaves room for the lens sitting off the pan axis):
    the floor nearer the robot than that is not seen."""

    range_min: float = 0.8
    range_max: float = 3.5
    fov_h_deg: float = 58.0
    fov_v_deg: float = 45.0
    false_negative: float = 0.2
    false_positive: float = 0.05
    camera_height: float = 1.0
    look_down_deg: float = 55.0  # the steepest a head sweep looks below the horizon (floor nearer is blind)


@dataclass(frozen=True, slots=True)
class Robot:
    """The base as a disc (radius, extra clearance kept when navigating, in metres) and its
    speed in m/s (0.8 km/h, the HSR's cautious indoor speed)."""

    radius: float = 0.22
    nav_margin: float = 0.05
    speed: float = 0.22


@dataclass(frozen=True, slots=True)
class Expect:
    """Names of what the case is built to hide or block, for tests to check the geometry does."""

    unobservable_items: tuple[str, ...] = ()
    unreachable_items: tuple[str, ...] = ()
    unobservable_deposits: tuple[str, ...] = ()
    unreachable_deposits: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Scenario:
    """One room to tidy, as read from ``path``; bounds are (x0, x1, y0, y1), the walls."""

    name: str
    title: str
    description: str
    bounds: tuple[float, float, float, float]
    entrance: tuple[float, float]
    heading_deg: float
    robot: Robot
    sensing: Sensing
    furniture: tuple[Furniture, ...]
    deposits: tuple[Deposit, ...]
    items: tuple[Item, ...]
    viewpoints: tuple[Viewpoint, ...]
    expect: Expect
    path: str
    # What the robot is told about the items: (category, count) pairs, or None when it is told
    # nothing and must explore. Never derived from ``items``: those are the truth.
    prior: tuple[tuple[str, int], ...] | None = None

    def prior_counts(self) -> dict[str, int] | None:
        """The declared prior as category -> count, or None when the scenario declares none."""
        return None if self.prior is None else dict(self.prior)

    def without_items(self) -> Scenario:
        """The scenario as the robot may know it: the static room and the prior, no true items."""
        return replace(self, items=(), expect=Expect())

    def furniture_named(self, name: str) -> Furniture:
        """The furniture piece called ``name``; KeyError if there is none."""
        for f in self.furniture:
            if f.name == name:
                return f
        raise KeyError(f"no furniture named {name!r} in {self.path}")

    def item_base_z(self, item: Item) -> float:
        """Height of the item's base: 0 on the floor, else the top of what it stands on."""
        return 0.0 if item.on == FLOOR else self.furniture_named(item.on).height

    def categories(self) -> list[str]:
        """The item categories, sorted."""
        return sorted({i.category for i in self.items})

    def static_boxes(self) -> list[Box]:
        """The furniture footprints, in file order: the static map's obstacles."""
        return [f.box() for f in self.furniture]
