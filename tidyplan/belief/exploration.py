"""Where the items nobody has seen may be, and where to look for them: the exploration half of
the belief (a mixin of ``tidyplan.belief.state.Belief``).

The room's placement points (floor and table tops) are seen or not yet seen; a viewpoint nobody
has looked from reveals an unseen item with the share of unseen points it shows (Goebelbecker
et al.'s assumption probability under a uniform prior). Viewpoints are generated from the map
where the scenario's do not cover the room, and closer ones in each new round when expected
items were not found; a lost item's surroundings are marked unseen so it is looked for there.
"""

from __future__ import annotations

import numpy as np

from sim.visibility import visible_points
from tidyplan.belief import viewpoints
from tidyplan.belief.geometry import MapFacts

Point = tuple[float, float]

UNEXPLORED_SHARE = 0.02  # a viewpoint that would reveal less of the unseen space is explored
LOST_RADIUS = 1.0  # m around where a lost item was (fell, knocked, not found) it is looked for again
EXPLORATION_ROUNDS = 3  # rounds of exploration after the first, each from closer viewpoints
ROUND_STEP = 0.6  # m: each new round's viewpoints see this much less far (at least 1.5 m)


class Exploration:
    """Uses the belief's ``scenario``, ``room``, ``points``, ``seen``, ``looked_from``,
    ``rounds``, ``_targets``, ``_support``, ``_occluders`` and ``_view_cache``; clears its
    ``_facts`` when viewpoints are added."""

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
            share = float((self._view(facts.points[name]) & unseen).sum()) / total
            if share >= UNEXPLORED_SHARE:
                out[name] = round(share, 4)
        return out

    def reset_exploration(self) -> None:
        """Forget what was seen: the floor changed, so views that were blocked may be open now."""
        self.seen[:] = False
        self.looked_from.clear()
        self.scene_changed = False

    def explore_again(self) -> list[str] | None:
        """A new round of exploration, when the prior names items nobody has found and the whole
        room has been seen: look again from everywhere (a look misses a visible item at the
        false-negative rate), and from new viewpoints that see less far, so closer to every
        place. Returns the viewpoints added, None when the rounds are used up."""
        if self.rounds >= EXPLORATION_ROUNDS:
            return None
        self.rounds += 1
        self.reset_exploration()
        s = self.scenario.sensing
        return self._add_viewpoints(max(s.range_min + 0.7, s.range_max - ROUND_STEP * self.rounds))

    def _add_viewpoints(self, reach: float) -> list[str]:
        """Viewpoints from the map for what the existing ones (and the entrance) do not show
        within ``reach`` m; registered with the room map so that the planner sees them."""
        kinds = self.room.fixed_kind
        fixed = [q for n, q in self.room.fixed.items() if kinds[n] in ("viewpoint", "entrance")]
        covered = np.zeros(len(self.points), dtype=bool)
        for q in fixed:
            covered |= self._view(q, reach)
        cells = self.room.grid(()).free_cells(reachable_from=self.room.entrance)
        new = viewpoints.cover(viewpoints.lattice(cells), lambda q: self._view(q, reach), covered)
        names = []
        for q in new:
            name = f"vp-map-{sum(k == 'viewpoint' for k in self.room.fixed_kind.values()) + 1}"
            self.room.add_viewpoint(name, q)
            names.append(name)
        self._facts = None
        return names

    def unsee(self, near: Point, radius: float = LOST_RADIUS) -> None:
        """Mark the placement points within ``radius`` of ``near`` unseen, and reopen the viewpoints
        that show them: an item was lost there (it fell, was knocked, or was not where believed),
        so that is where it is looked for."""
        pts = self._targets[:, :2]
        region = np.hypot(pts[:, 0] - near[0], pts[:, 1] - near[1]) <= radius
        if not region.any():
            return
        self.seen &= ~region
        for name in list(self.looked_from):
            if name in self.room.fixed and (self._view(self.room.fixed[name]) & region).any():
                self.looked_from.discard(name)

    def _camera(self, p: Point) -> tuple[float, float, float]:
        return (p[0], p[1], self.scenario.sensing.camera_height)

    def _view(self, p: Point, reach: float | None = None) -> np.ndarray:
        """Placement points in line of sight and range (at most ``reach`` m, default the camera's
        range) from p (furniture occludes, items do not: the belief cannot know what unseen items
        hide)."""
        s = self.scenario.sensing
        reach = s.range_max if reach is None else reach
        key = (round(p[0], 3), round(p[1], 3), reach)
        if key not in self._view_cache:
            self._view_cache[key] = visible_points(
                self._camera(p), self._targets, self._occluders, self._support,
                range_min=s.range_min, range_max=reach,
            )  # fmt: skip
        return self._view_cache[key]
