"""Scenario files: the tidy-up room, its furniture, deposits, items and viewpoints, in TOML.

Why a file format of our own: the symbolic world (planning, visibility, path lengths) and the
pybullet world must be built from one description, so that a case built to hide or block an
object does so in both. The layout is documented in docs/scenario.md; this module holds the
values, ``sim/scenario/read.py`` reads and checks files into them (``load``, ``loads``).

Item heights are not stored on the item: an item's base is the floor or the top of the
furniture it stands on, so ``Scenario.item_base_z`` resolves it and one source of truth remains.
Likewise a drawer's place in its carcass is not written in the file but follows from the deposit
and the furniture (``drawer_layout``): both worlds and the file's checks read it from there.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass, replace

from sim.grid import Box

SCHEMA = 1
NAME_RE = re.compile(r"[a-z][a-z0-9_-]*")
ITEM_SIZE = (0.08, 0.08, 0.10)  # m: a WRS-sized small object when the file gives no size
FLOOR = "floor"
# What the detector reports an unknown object as (WRS Task 1: one per category, no recognition
# data): the deposits for it accept this category (bin B); its true category only the referee holds
UNKNOWN = "unknown"
# The deposits' category for orientation items (WRS Task 1's container B: the markers tip down, the
# fork and the spoon handle up): an item with an ``orientation`` may go there whatever its
# category, and stands the right way when its axis is within STAND_DEG of straight down
ORIENTATION = "orientation"
STAND_DEG = 30.0
# A drawer (the WRS stairs-like drawer's): 12 mm boards for its bottom, sides, back and front; 5 mm
# of play around it in its slot; the grip of the WRS suction handle, 3.5 cm out from the front,
# 6 cm across, 3 cm high (RoboCup 2021 DSPL rules: a grip of about 6 x 3.5 x 3 cm)
BOARD, PLAY = 0.012, 0.005
HANDLE = (0.035, 0.06, 0.03)


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
class DrawerSpec:
    """A drawer the deposit's objects go into, as the file gives it: closed at the start or fully
    out, how far it slides out (m), its inside width across the slide and the height of its sides
    above its floor (m), and the handle's height above the room's floor (None: the middle of its
    front). Where it is follows from the deposit and its carcass: ``drawer_layout``."""

    closed: bool = True
    travel: float = 0.25
    width: float = 0.40
    rim: float = 0.10
    handle_height: float | None = None


@dataclass(frozen=True, slots=True)
class Deposit:
    """Where objects of ``category`` go: the place (x, y, z), and where the robot stands to put
    them there (``approach``; None lets the caller find a free cell near the place). With a
    ``drawer`` the place is the centre of the open drawer's floor, and the robot pulls the
    handle from the approach too. With a ``container`` (its outer x, y and height, m) the deposit
    is an open box of that size standing on the surface at the place (WRS containers A and B);
    without either it is a tray there, or the inside of a bin whose rim is at the place."""

    name: str
    category: str
    x: float
    y: float
    z: float
    approach: tuple[float, float] | None = None
    drawer: DrawerSpec | None = None
    container: tuple[float, float, float] | None = None

    def takes(self, item: Item) -> bool:
        """Is ``item`` put away here, by the rulebook: a deposit of its label's category, or one for
        orientation items where it is one (in its category's deposit it scores the category too)."""
        return self.category == item.label or (self.category == ORIENTATION and item.orientation is not None)


@dataclass(frozen=True, slots=True)
class Orientation:
    """How an orientation item stands the right way: ``axis`` in the item's own frame (the axes
    of its ``size``), pointing to the end that goes down, which ``down`` names ("tip" for a
    marker; a fork stands handle up, so its "tines" go down)."""

    axis: tuple[float, float, float]
    down: str


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
    unknown: bool = False  # an unknown object: seen as UNKNOWN, its category the referee's alone
    orientation: Orientation | None = None  # an orientation item: which way it must stand

    @property
    def label(self) -> str:
        """The category the detector reports and the deposits go by: UNKNOWN for an unknown object."""
        return UNKNOWN if self.unknown else self.category

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
    # Atoms of a domain's own predicates true at the start (``facts = ["(name arg ...)"]``), each
    # as (name, arg, ...): what no sensor reports and the problem writer does not fill.
    facts: tuple[tuple[str, ...], ...] = ()
    # The referee's clock, simulated seconds (the WRS Task 1's 15 minutes): where a scenario gives
    # one, a mission plans for the most score within it (docs/loop.md, "Against the clock")
    time_limit_s: float | None = None

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


@dataclass(frozen=True, slots=True)
class DrawerLayout:
    """A deposit's drawer placed in its carcass (the furniture piece it slides out of).

    It slides along the room's axis ``k`` (0: x, 1: y) out of the carcass's face towards the
    approach (``sign``: +1 or -1 along that axis); ``front`` is that face's coordinate. Closed,
    the drawer's front is flush with the face, so its depth (outside, front to back) is twice the
    distance from the closed drawer's middle to the face: the file gives the open drawer's middle
    and the travel, and the depth follows. Positions along the slide are "out" coordinates: metres
    out of the front face (negative inside the carcass)."""

    carcass: Furniture
    k: int
    sign: float
    front: float
    across: float  # the drawer's middle across the slide (y when it slides along x)
    depth: float
    floor_z: float  # the top of its bottom board: where objects stand in it
    spec: DrawerSpec

    @property
    def start(self) -> float:
        """How far it is out at the start."""
        return 0.0 if self.spec.closed else self.spec.travel

    @property
    def handle_z(self) -> float:
        if self.spec.handle_height is not None:
            return self.spec.handle_height
        return self.floor_z + (self.spec.rim - BOARD) / 2  # the front runs from under the floor to the rim

    def point(self, out: float, across: float | None = None) -> tuple[float, float]:
        """The room's (x, y) of a point ``out`` m out of the front face (on the drawer's middle line)."""
        along = self.front + self.sign * out
        side = self.across if across is None else across
        return (along, side) if self.k == 0 else (side, along)

    def out(self, xy: tuple[float, float]) -> float:
        """How far a point of the room is out of the front face, along the slide."""
        return self.sign * (xy[self.k] - self.front)

    def rect(self, out0: float, out1: float, half_width: float) -> tuple[float, float, float, float]:
        """(x0, x1, y0, y1) of the band ``out0`` to ``out1`` out of the face, ``half_width`` either side."""
        a, b = sorted((self.front + self.sign * out0, self.front + self.sign * out1))
        c, d = self.across - half_width, self.across + half_width
        return (a, b, c, d) if self.k == 0 else (c, d, a, b)

    def inside_span(self, opening: float) -> tuple[float, float]:
        """(back, front) of the drawer's inside, out of the face, open by ``opening``."""
        return opening - self.depth + BOARD, opening - BOARD

    def interior(self, opening: float) -> tuple[float, float, float, float]:
        """The drawer's inside open by ``opening``: what holds its objects, out or in the carcass."""
        return self.rect(*self.inside_span(opening), self.spec.width / 2)

    def exposed_depth(self, opening: float) -> float:
        """How much of its inside (along the slide) is out of the carcass: where objects go in."""
        back, front = self.inside_span(opening)
        return max(0.0, front - max(back, 0.0))

    def exposed(self, opening: float) -> tuple[float, float, float, float]:
        """The part of its inside out of the carcass, open by ``opening`` (none closed)."""
        back, front = self.inside_span(opening)
        return self.rect(max(back, min(front, 0.0)), front, self.spec.width / 2)

    def takes(self, opening: float, footprint: tuple[float, float]) -> bool:
        """Is it open far enough for an object of ``footprint`` (its sides) to be put in, 1 cm
        of room on either side along the slide?"""
        return min(footprint) + 0.02 <= self.exposed_depth(opening) and max(footprint) < self.spec.width

    def out_box(self, opening: float, name: str = "") -> Box | None:
        """The floor the drawer takes out of its carcass, open by ``opening``, its side boards and
        handle with it: what the base must keep clear of (None closed). The base cannot pass
        under it: a drawer's front reaches down below its floor, and the torso stands above."""
        if opening <= 0.0:
            return None
        x0, x1, y0, y1 = self.rect(0.0, opening + HANDLE[0], self.spec.width / 2 + BOARD)
        return Box((x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0, name)

    def handle(self, opening: float) -> tuple[float, float, float]:
        """The middle of the handle's grip, open by ``opening``: where the hand closes on it."""
        return (*self.point(opening + HANDLE[0] / 2), self.handle_z)

    def slot(self) -> tuple[float, float, float, float]:
        """(across0, across1, z0, z1) of the drawer's slot in the carcass: the drawer with its
        boards and the play around them. Two drawers of one carcass must not share any of it."""
        half = self.spec.width / 2 + BOARD + PLAY
        return (
            self.across - half,
            self.across + half,
            self.floor_z - BOARD - PLAY,
            self.floor_z + self.spec.rim + PLAY,
        )

    def holds_height(self, z: float) -> bool:
        """Does an object whose bottom is at ``z`` rest in this drawer (on its floor, below its
        rim), rather than in a drawer above or below it in the same carcass?"""
        return self.floor_z - 0.02 <= z <= self.floor_z + self.spec.rim


def drawer_layout(furniture: Iterable[Furniture], deposit: Deposit) -> DrawerLayout | None:
    """Where ``deposit``'s drawer is: None without a drawer, an approach, or a carcass (the piece
    whose footprint holds the closed drawer's middle). It slides along the room's axis nearest
    the line from its place to the approach."""
    spec, approach = deposit.drawer, deposit.approach
    if spec is None or approach is None:
        return None
    dx, dy = approach[0] - deposit.x, approach[1] - deposit.y
    k = 0 if abs(dx) >= abs(dy) else 1
    sign = 1.0 if (dx, dy)[k] >= 0 else -1.0
    place = (deposit.x, deposit.y)
    closed = list(place)
    closed[k] -= sign * spec.travel
    for f in furniture:
        if f.box().clearance(*closed) == 0.0:
            front = (f.cx, f.cy)[k] + sign * (f.sx, f.sy)[k] / 2
            out = sign * (closed[k] - front)  # the closed drawer's middle: half its depth inside
            return DrawerLayout(f, k, sign, front, place[1 - k], -2 * out, deposit.z, spec)
    return None


def out_boxes(layouts: dict[str, DrawerLayout], openings: dict[str, float]) -> list[Box]:
    """The open drawers' boxes out of their carcasses (``DrawerLayout.out_box``), named by
    deposit, each out by ``openings[name]``: furniture for the base as long as they are out."""
    boxes = (x.out_box(openings[n], n) for n, x in sorted(layouts.items()))
    return [b for b in boxes if b is not None]


def shared_carcass_problems(a: DrawerLayout, b: DrawerLayout) -> str | None:
    """Why two drawers of one carcass cannot both be built: they must slide out of the same face
    (the carcass is one body with its slots in that face) and their slots must not overlap."""
    if (a.k, a.sign) != (b.k, b.sign):
        return f"slides out of another face of {a.carcass.name!r} than its other drawers"
    a0, a1, az0, az1 = a.slot()
    b0, b1, bz0, bz1 = b.slot()
    if a0 < b1 and b0 < a1 and az0 < bz1 and bz0 < az1:
        return "overlaps"
    return None


def drawer_problems(
    layout: DrawerLayout, approach: tuple[float, float], radius: float
) -> list[tuple[str, str]]:
    """What keeps a drawer from being built or used, as (key, what) pairs: it must fit its slot in
    the carcass with the play around it, its handle be on its front, and the open drawer with its
    handle stay clear of the robot's base (``radius``) at the approach."""
    f, s, z = layout.carcass, layout.spec, layout.floor_z
    out = []
    if layout.depth < 2 * BOARD + 0.02:
        why = "its place must be less than the travel out of the carcass"
        out.append(
            ("position", f"closed, the drawer would be {layout.depth:.3g} m deep in {f.name!r}: {why}")
        )
    elif layout.depth + PLAY > (f.sx, f.sy)[layout.k]:
        out.append(
            ("position", f"closed, the drawer ({layout.depth:.3g} m deep) would not fit in {f.name!r}")
        )
    middle, size = (f.cy, f.sy) if layout.k == 0 else (f.cx, f.sx)
    if abs(layout.across - middle) + s.width / 2 + BOARD + PLAY > size / 2:
        out.append(("drawer.width", f"the drawer ({s.width:g} m inside) does not fit across {f.name!r}"))
    if z - BOARD - PLAY < 0 or z + s.rim + PLAY > f.height:
        out.append(
            ("position", f"z: a drawer floor at {z:g} m leaves it outside {f.name!r} (0 to {f.height:g} m)")
        )
    grip = (layout.handle_z - HANDLE[2] / 2, layout.handle_z + HANDLE[2] / 2)
    if not (z - BOARD <= grip[0] and grip[1] <= z + s.rim):
        out.append(
            ("drawer.handle_height", f"the handle at {layout.handle_z:g} m is not on the drawer's front")
        )
    reach = s.travel + HANDLE[0]
    if layout.out(approach) - radius < reach:
        why = f"the base ({radius:g} m) at the approach would touch them"
        out.append(
            ("approach", f"the open drawer and its handle reach {reach:.3g} m out of {f.name!r}: {why}")
        )
    return out
