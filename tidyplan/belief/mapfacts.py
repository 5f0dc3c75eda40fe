"""What the map says, as data: the items placed on it (``Placed``), the facts a placement gives
(``MapFacts``: waypoints, paths, what blocks them, pose adjustments; the problem writer's input)
and the waypoints' names. ``tidyplan.belief.geometry.RoomMap`` works the facts out."""

from __future__ import annotations

from dataclasses import dataclass, field

from sim.grid import Box

Point = tuple[float, float]
ENTRANCE = "wp-entrance"


@dataclass(frozen=True, slots=True)
class Placed:
    """An item where someone (the belief or the truth) has it: on the floor or on furniture."""

    name: str
    category: str
    x: float
    y: float
    on: str = "floor"
    sx: float = 0.08
    sy: float = 0.08
    # Fell where no look has found it yet: (x, y) is only where the robot stood, so it is no
    # obstacle on the map (put there it shut the robot in on every side, and no plan could start).
    loose: bool = False
    # Put down by the robot out of the way (``put_down``: where it leaves every way open): not
    # one of the items a pair no single item frees waits for (``RoomMap._find_blockers``).
    aside: bool = False

    @property
    def xy(self) -> Point:
        return (self.x, self.y)

    @property
    def on_floor(self) -> bool:
        """On the floor where the map knows it: an obstacle to the base."""
        return self.on == "floor" and not self.loose

    def box(self) -> Box:
        return Box(self.x, self.y, self.sx, self.sy, self.name)


@dataclass(slots=True)
class MapFacts:
    """What the grid says for one set of placed items; the problem writer's input.

    ``points`` maps every waypoint name to (x, y); ``kind`` to one of entrance, viewpoint,
    deposit, grasp, adjust, robot. Pairs are ordered (from, to). A pair is in at most one of
    ``path`` (drivable now) and ``blocked`` (drivable once its blockers are taken).
    """

    points: dict[str, Point] = field(default_factory=dict)
    kind: dict[str, str] = field(default_factory=dict)
    grasp: dict[str, str] = field(default_factory=dict)  # item -> its grasp waypoint
    unreachable: list[str] = field(default_factory=list)  # items with no grasp pose at all
    path: dict[tuple[str, str], float] = field(default_factory=dict)
    blocked: dict[tuple[str, str], float] = field(default_factory=dict)
    blocks: set[tuple[str, str, str]] = field(default_factory=set)  # (item, from, to)
    adjust: dict[tuple[str, str], float] = field(default_factory=dict)
    reach_blockers: dict[str, tuple[str, ...]] = field(default_factory=dict)  # grasp wp -> items
    # How the pairs were put together, for readers that need what changed, not the whole room
    # (the monitor's state after every action): ``shared`` holds pairs of a floor's fixed
    # waypoints, kept by the RoomMap and shared by every answer on that floor; ``own`` the rest
    # (the robot's pairs, the grasp poses' adjustments); ``dropped`` the pairs taken out of
    # ``path`` and ``adjust`` since. The tables above are always whole: shared + own - dropped.
    shared: MapFacts | None = None
    own: MapFacts | None = None
    dropped: set[tuple[str, str]] = field(default_factory=set)

    def add_poses(self, other: MapFacts) -> None:
        """Take ``other``'s waypoints and grasp facts, no pair: one item's choice into a floor's,
        a floor's into an answer."""
        self.points.update(other.points)
        self.kind.update(other.kind)
        self.grasp.update(other.grasp)
        self.unreachable.extend(other.unreachable)
        self.adjust.update(other.adjust)
        self.reach_blockers.update(other.reach_blockers)

    def add_pairs(self, other: MapFacts) -> None:
        """Take ``other``'s pairs: paths, blocked paths and their blockers, pose adjustments."""
        self.path.update(other.path)
        self.blocked.update(other.blocked)
        self.blocks.update(other.blocks)
        self.adjust.update(other.adjust)

    def distance(self, a: str, b: str) -> float | None:
        for table in (self.path, self.blocked, self.adjust):
            if (a, b) in table:
                return table[(a, b)]
        return None


def grasp_waypoint(item: str) -> str:
    return f"wp-{item}"


def deposit_waypoint(deposit: str) -> str:
    return f"wp-{deposit}"
