"""Exploration: the room's space nobody has seen yet, and the viewpoints to see it from.

Goebelbecker et al. bridge what is not known with assumptions over virtual objects; an unseen
item may lie at any of the room's placement points (floor and table tops) nobody has seen, and a
viewpoint nobody has looked from reveals one with the share of those points it shows (the
assumption's probability under a uniform prior, ``p_item_near``). Viewpoints are generated from
the map where the scenario's do not cover the room (``tidyplan.belief.viewpoints``), and closer
ones in each new round when expected items were not found; a lost item's surroundings are marked
unseen so that it is looked for there.

The belief (``tidyplan.belief.state.Belief``) owns one and tells it what each look showed; what
is believed of the items is the belief's, what is known of the space is this. Line of sight is
against furniture only: the robot cannot know what unseen items hide.
"""

from __future__ import annotations

import math

import numpy as np

from sim.scenario.model import Scenario
from sim.visibility import Box3, in_frame, visible_points
from tidyplan.belief import viewpoints
from tidyplan.belief.geometry import RoomMap
from tidyplan.belief.mapfacts import MapFacts
from tidyplan.belief.percepts import SWEEP_STOPS, Frame, in_stops

Point = tuple[float, float]

POINT_SPACING = 0.10  # m between placement points
UNEXPLORED_SHARE = 0.02  # a viewpoint that would reveal less of the unseen space is explored
LOST_RADIUS = 1.0  # m around where a lost item was (fell, knocked, not found) it is looked for again
EXPLORATION_ROUNDS = 3  # rounds of exploration after the first, each from closer viewpoints
ROUND_STEP = 0.6  # m: each new round's viewpoints see this much less far (at least 1.5 m)
# the chance a viewpoint at a forgotten item's place reveals it: seen there, then not (no figure
# measured; above any share of the room's unseen space a viewpoint holds after a round's reset)
P_AT_FORGOTTEN = 0.5


class Exploration:
    """What of the room's placement points has been seen, the viewpoints looked from, and the
    rounds of exploration. Mutable: updated by the belief after every look. ``generated`` names
    the viewpoints added from the map at the start."""

    def __init__(self, scenario: Scenario, room: RoomMap, occluders: list[Box3]) -> None:
        self.sensing = scenario.sensing
        self.room = room
        self.occluders = occluders
        self.points, self.support = viewpoints.placement_points(scenario, POINT_SPACING)
        self.targets = np.array(self.points, dtype=float).reshape(-1, 3)
        self.seen = np.zeros(len(self.points), dtype=bool)
        self.looked_from: set[str] = set()
        self.rounds = 0  # rounds of exploration after the first
        self.at_forgotten: dict[str, str] = {}  # viewpoint -> the forgotten item it was placed for
        self.scene_changed = False  # an item left the floor since exploration was last reset
        self._view_cache: dict[tuple, np.ndarray] = {}
        # a frame's placement points in sight, by where the lens stood, its heading and tilt: the
        # robot drives the same cells between the same places, and half of a 96-object mission's
        # frames were taken again exactly (the furniture alone occludes, so the answer stays)
        self._frames: dict[tuple, np.ndarray] = {}
        self.generated: list[str] = self.add_viewpoints(self.sensing.range_max)

    # ------------------------------------------------------------------ what a look showed
    def looked(self, at: Point, frame: Frame | None, stops: tuple[float, ...] | None) -> None:
        """Mark seen what a look from ``at`` showed: a sweep of some pan ``stops`` (their frames,
        at both tilts), one ``frame`` on the way, or a whole sweep (neither)."""
        if stops is not None:
            self.seen |= self.view(at) & in_stops(at, stops, self.targets[:, :2], self.sensing.fov_h_deg)
        elif frame is None or frame.heading is None:
            self.seen |= self.view(at)
        else:
            key = (at[0], at[1], frame.heading, frame.tilt_deg)
            sight = self._frames.get(key)
            if sight is None:
                field = in_frame(
                    at, frame.heading, self.targets[:, :2], self.targets[:, 2], self.sensing, 1.0, 0.0,
                    frame.tilt_deg,
                )  # fmt: skip
                sight = self._in_sight(at, np.flatnonzero(field))
                if len(self._frames) > 4096:  # a mission's frames, a few thousand at 96 objects
                    self._frames.clear()
                self._frames[key] = sight
            self.seen[sight] = True

    def _in_sight(self, at: Point, idx: np.ndarray) -> np.ndarray:
        """Of the placement points ``idx`` (indices), those in range and line of sight from
        ``at`` (each point's sight is its own: a few need not cost the whole view)."""
        s = self.sensing
        sight = visible_points(
            self.camera(at), self.targets[idx], self.occluders, [self.support[n] for n in idx],
            range_min=s.range_min, range_max=s.range_max,
        )  # fmt: skip
        return idx[sight]

    # ------------------------------------------------------------------ where to look
    def p_item_near(self, facts: MapFacts) -> dict[str, float]:
        """For each viewpoint nobody looked from: the chance that an unseen item is revealed from
        it, the share of unseen placement points in its view."""
        unseen = ~self.seen
        total = int(unseen.sum())
        out: dict[str, float] = {}
        if total == 0:
            return out
        for name, kind in sorted(facts.kind.items()):
            if kind != "viewpoint" or name in self.looked_from:
                continue
            share = float((self.view(facts.points[name]) & unseen).sum()) / total
            if name in self.at_forgotten:  # where a missing item was seen: likelier than anywhere
                share = max(share, P_AT_FORGOTTEN)
            if share >= UNEXPLORED_SHARE:
                out[name] = round(share, 4)
        return out

    def unseen_share(self, at: Point) -> float:
        """The share of the unseen placement points a sweep from ``at`` shows (0 when none is)."""
        unseen = ~self.seen
        total = int(unseen.sum())
        return 0.0 if total == 0 else len(self._unseen_in_view(at, unseen)) / total

    def stop_shares(self, at: Point) -> list[tuple[float, float]]:
        """For each of a sweep's stops (SWEEP_STOPS): its heading and the share of the unseen points
        in the part of the view nearer that stop's heading than any other's (they add up to
        ``unseen_share``)."""
        unseen = ~self.seen
        total = int(unseen.sum())
        if total == 0:
            return [(h, 0.0) for h in SWEEP_STOPS]
        xy = self.targets[self._unseen_in_view(at, unseen), :2]
        bearing = np.arctan2(xy[:, 1] - at[1], xy[:, 0] - at[0]) % (2 * math.pi)
        nearest = np.rint(bearing / (2 * math.pi / len(SWEEP_STOPS))).astype(int) % len(SWEEP_STOPS)
        per_stop = np.bincount(nearest, minlength=len(SWEEP_STOPS))
        return [(h, float(per_stop[i]) / total) for i, h in enumerate(SWEEP_STOPS)]

    def _unseen_in_view(self, at: Point, unseen: np.ndarray) -> np.ndarray:
        """The unseen placement points (indices) in line of sight and range from ``at``: the view
        kept where there is one, else the line of sight to the unseen points only (a whole view,
        for the points seen too, was 2.5 ms of a turn at a pose met for the first time, most of
        the room seen by then)."""
        key = _view_key(at, self.sensing.range_max)
        if key in self._view_cache:
            return np.flatnonzero(self._view_cache[key] & unseen)
        return self._in_sight(at, np.flatnonzero(unseen))

    # ------------------------------------------------------------------ rounds and viewpoints
    def reset(self) -> None:
        """Forget what was seen: the floor changed, so views that were blocked may be open now."""
        self.seen[:] = False
        self.looked_from.clear()
        self.scene_changed = False

    def new_round(self) -> list[str] | None:
        """A new round of exploration: look again from everywhere (a look misses a visible item at
        the false-negative rate), and from new viewpoints that see less far, so closer to every
        place. Returns the viewpoints added, None when the rounds are used up."""
        if self.rounds >= EXPLORATION_ROUNDS:
            return None
        self.rounds += 1
        self.reset()
        s = self.sensing
        return self.add_viewpoints(max(s.range_min + 0.7, s.range_max - ROUND_STEP * self.rounds))

    def add_viewpoints(self, reach: float) -> list[str]:
        """Viewpoints from the map for what the existing ones (and the entrance) do not show
        within ``reach`` m; registered with the room map so that the planner sees them."""
        covered = np.zeros(len(self.points), dtype=bool)
        for q in self.taken():
            covered |= self.view(q, reach)
        cells = self.room.grid(()).free_cells(reachable_from=self.room.entrance)
        new = viewpoints.cover(viewpoints.lattice(cells), lambda q: self.view(q, reach), covered)
        return [self.add_viewpoint(q) for q in new]

    def add_viewpoint(self, at: Point, forgotten: str | None = None) -> str:
        """A viewpoint at ``at``, registered with the room map; ``forgotten``: the item it is placed
        to look for (``p_item_near`` holds it likelier)."""
        name = f"vp-map-{sum(k == 'viewpoint' for k in self.room.fixed_kind.values()) + 1}"
        self.room.add_viewpoint(name, at)
        if forgotten is not None:
            self.at_forgotten[name] = forgotten
        return name

    def taken(self) -> list[Point]:
        """Where the viewpoints and the entrance stand."""
        kinds = self.room.fixed_kind
        return [q for n, q in self.room.fixed.items() if kinds[n] in ("viewpoint", "entrance")]

    def unsee(self, near: Point, radius: float = LOST_RADIUS) -> None:
        """Mark the placement points within ``radius`` of ``near`` unseen, and reopen the viewpoints
        that show them: an item was lost there (it fell, was knocked, or was not where believed),
        so that is where it is looked for."""
        pts = self.targets[:, :2]
        region = np.hypot(pts[:, 0] - near[0], pts[:, 1] - near[1]) <= radius
        if not region.any():
            return
        self.seen &= ~region
        for name in list(self.looked_from):
            if name in self.room.fixed and (self.view(self.room.fixed[name]) & region).any():
                self.looked_from.discard(name)

    # ------------------------------------------------------------------ line of sight
    def camera(self, p: Point) -> tuple[float, float, float]:
        return (p[0], p[1], self.sensing.camera_height)

    def view(self, p: Point, reach: float | None = None) -> np.ndarray:
        """Placement points in line of sight and range (at most ``reach`` m, default the camera's
        range) from p (furniture occludes, items do not: the belief cannot know what unseen items
        hide)."""
        s = self.sensing
        reach = s.range_max if reach is None else reach
        key = _view_key(p, reach)
        if key not in self._view_cache:
            self._view_cache[key] = visible_points(
                self.camera(p), self.targets, self.occluders, self.support,
                range_min=s.range_min, range_max=reach,
            )  # fmt: skip
        return self._view_cache[key]


def _view_key(p: Point, reach: float) -> tuple:
    """A view's key: its point to the millimetre and its reach."""
    return (round(p[0], 3), round(p[1], 3), reach)
