"""The contract between the planner's side and a world: what the behaviour units and the loop may
call (``Skills``), what only the world knows and is asked for the verdict (``Referee``), and
the plain values they exchange. The symbolic and the pybullet worlds (``tidyplan.exec``)
implement it; the monitor sees a world only through it. Worlds are made by name
(``tidyplan.worlds.registry``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

from sim.scenario.model import Orientation
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.percepts import Detection, Frame

Point = tuple[float, float]
_PLACED_EDITS = [0]  # changes to items in place, in any world: what a world's view of them is kept by


def placed_edits() -> int:
    """How many times an item in place has changed (a field of it set, or any item's state):
    the same count, the same items in the same places."""
    return _PLACED_EDITS[0]


@dataclass(slots=True)
class TrueItem:
    """An item as it really is (the referee's): where, on what, its size as it lies, its state."""

    name: str
    category: str
    x: float
    y: float
    on: str
    sx: float
    sy: float
    sz: float
    state: str = "placed"  # placed, held, tidied
    deposit: str | None = None
    label: str = ""  # what the detector reports and the deposits go by (UNKNOWN for an unknown
    # object, whose category only the referee holds); its category where not given
    orientation: Orientation | None = None  # an orientation item's axis (its own frame) and down end
    stands: bool | None = None  # put into an orientation deposit: standing the right way there

    def __post_init__(self) -> None:
        self.label = self.label or self.category

    def __setattr__(self, name: str, value) -> None:
        # an item in the hand moves with the robot at every step: no change to what is in place
        if name == "state" or getattr(self, "state", "placed") == "placed":
            _PLACED_EDITS[0] += 1
        object.__setattr__(self, name, value)

    def seen(self, x: float, y: float, axis: tuple[float, float, float] | None = None) -> Detection:
        """What the detector reports of it, seen at (x, y): its label, its box, and an orientation
        item's axis to its down end in the room's frame (``axis``; as it lies in its own frame,
        axis-aligned, where not given)."""
        if self.orientation is not None and axis is None:
            axis = self.orientation.axis
        down = None if self.orientation is None else tuple(round(v, 3) for v in axis)
        return Detection(self.label, x, y, self.on, self.sx, self.sy, self.sz, down)


@dataclass(frozen=True, slots=True)
class Outcome:
    """What the world says about one action: success, or a named failure, and its cost."""

    ok: bool
    failure: str | None = None
    seconds: float = 0.0
    metres: float = 0.0
    # where an item was put down (drop); where the base touched what stopped it (path_blocked:
    # the bumper's side, a point on the base's edge)
    at: Point | None = None


@dataclass(slots=True)
class Odometer:
    """The simulated clock, the distance driven and the driven track (the base's poses)."""

    sim_time_s: float = 0.0
    distance_m: float = 0.0
    track: list[Point] = field(default_factory=list)

    def path_since(self, mark: int, step: float = 0.1) -> list[list[float]]:
        """The track driven since ``len(track)`` was ``mark``, as a trace stores it: points at
        least ``step`` metres apart (the last always kept), each [x, y] rounded to 3 decimals;
        enough to draw, small enough to write."""
        out: list[list[float]] = []
        points = self.track[mark:]
        for i, (x, y) in enumerate(points):
            last = i == len(points) - 1
            if not out or last or math.dist(out[-1], (x, y)) >= step:
                out.append([round(x, 3), round(y, 3)])
        return out


@runtime_checkable
class Skills(Protocol):
    """What the behaviour units and the loop call on a world: the robot's senses, its motions and
    its manipulation, each answering with what the robot itself would know. ``odometer`` keeps
    the simulated clock, the distance and the driven track."""

    odometer: Odometer

    def pose(self) -> Point: ...

    def holds(self) -> bool: ...

    def follow(
        self, path: list[Point], monitor=None, *, careful: bool = False, face: Point | None = None
    ) -> Outcome: ...

    def grasp(self, target: Point) -> Outcome: ...

    def place(self, deposit: str, approach: Point) -> Outcome: ...

    def put_down(self, spot: Point) -> Outcome: ...

    def look(self, stops: tuple[float, ...] | None = None) -> list[Detection]:
        """A head sweep from where the robot stands: all around, or the pan ``stops`` only
        (headings in the room's frame, each frame at both tilts)."""
        ...

    def glance(self) -> list[Frame]:
        """The frames the camera took on the way since the last glance, and one from here as the
        head looks now: no time of their own (the camera runs while the robot moves)."""
        ...

    def look_into(self, deposit: str) -> list[Detection]: ...

    def locate(self, near: Point, radius: float, category: str | None = None) -> Detection | None: ...

    def grasp_distances(self, height: float) -> tuple[float, float, float]: ...

    def drawer_opening(self, deposit: str) -> float:
        """How far the deposit's drawer is out (m, 0.0 closed), as the robot sees it."""
        ...

    def pull_handle(self, deposit: str) -> Outcome:
        """From the deposit's approach, with the hand empty: grip the drawer's handle, pull it out."""
        ...

    def push_drawer(self, deposit: str) -> Outcome:
        """From the deposit's approach, with the hand empty: push its drawer back closed (frees a jam)."""
        ...


@runtime_checkable
class Referee(Protocol):
    """What only the world knows, asked for the verdict and the trace's end state, never to
    decide: which items are not tidied, where each really is, which left the room; ``items``
    is the truth itself (name -> ``TrueItem``), for the count of lost objects."""

    items: dict[str, TrueItem]

    def untidied(self) -> list[str]: ...

    def where(self, name: str) -> tuple[str, Point]: ...

    def escaped(self) -> list[str]: ...

    def standing(self) -> list[str]:
        """Orientation items standing the right way in a deposit for orientation items."""
        ...

    def close(self) -> None: ...


@runtime_checkable
class World(Skills, Referee, Protocol):
    """A world the mission runs in: the skills for the robot, the referee for the verdict, and
    ``room``, the map the robot is given (in pybullet, read back from the built scene)."""

    room: RoomMap


def referee_view(world: Referee) -> tuple[dict[str, list], list[str]]:
    """Where the world holds each item at the end, for a reader to draw: name -> [state, x, y],
    state ``placed``, ``held`` or ``tidied:<deposit>``; and the items tidied into a deposit of
    another category (they earn no category points in the WRS score, tidyplan.trace.score)."""
    found = {name: world.where(name) for name in sorted(world.items)}
    places = {n: [state, round(x, 3), round(y, 3)] for n, (state, (x, y)) in found.items()}
    return places, [n for n in world.untidied() if places[n][0].startswith("tidied")]
