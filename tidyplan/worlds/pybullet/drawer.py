"""The WRS drawer in the pybullet world: reading how far it is out, pulling it open by its handle,
pushing it closed, and putting objects into it. A mixin of ``BulletWorld``
(``tidyplan.worlds.pybullet.world``), before ``Hand`` so that ``place`` and the put-in search see a
drawer's inside where the drawer is now.

How the HSR opens a drawer here (the whole-body way: its level hand reaches 0.45-0.70 m out, a
drawer slides 0.25 m): the hand, held level and pointing into the carcass, closes on the
handle's grip, and the base backs off along the slide with the arm held, the drawer coming with
the hand; it lets go, stows the arm and drives back in to the approach. A drawer already part-way
out is gripped from as far off as a closed one is: the base first backs off by the opening. A
push is the same the other way. The drawer (``sim.drawer``) moves kinematically with the hand, the
objects in it with it. Faults (``WorldReferee._pull_faults``, four numbers drawn every pull): the
handle slips out of the hand part-way (``handle_slip``), the drawer sticks at 30-70 % of its
travel (``drawer_jammed``: it goes no farther out until pushed back closed).
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as p

from sim.motion import base_contacts, blocked
from sim.robot import GRIPPER_OPEN, REACHED, STOW, hand_level
from sim.scenario.model import HANDLE
from tidyplan.worlds.base import PULL_SPEED, Outcome

Point = tuple[float, float]

OPENING_S = 1.0  # s: a look at the drawer's front tells how far it is out
BEFORE_HANDLE = 0.05  # m: the hand comes onto the handle from this far out of it
HAUL_STEP = 0.01  # m of the drawer's way between the base's collision checks while it pulls
SLIDE_STEP = 0.05  # m between the base's collision checks when it backs off or closes in


class Drawers:
    """The drawer skills for ``BulletWorld``: ``drawer_opening``, ``pull_handle``, ``push_drawer``,
    and ``place`` into a drawer. Uses the world's ``scene`` (its ``drawers``), ``hsr``, ``robot``,
    ``holding``, ``items``, ``bodies``, ``openings``, ``odometer``, ``scenario``, the hand's
    ``_held_as``, ``_whole_body_reach`` and ``_free_spots``, and ``_place_base``, ``_ignored``,
    ``_sync``, ``_pull_faults``, ``_spend`` and ``_fail``."""

    def drawer_opening(self, deposit: str) -> float:
        """How far the deposit's drawer is out (m; 0.0 closed): a look at its front, 1 s."""
        self._spend(OPENING_S)
        return round(self.scene.drawers[deposit].opening(), 3)

    def pull_handle(self, deposit: str) -> Outcome:
        """Pull the drawer out by its travel from the approach, with the hand empty:
        ``handle_unreached`` where the hand cannot get to the handle, ``handle_slip`` (it stays
        where it got, free) and ``drawer_jammed`` (stuck at 30-70 %) at their rates."""
        drawer = self.scene.drawers[deposit]
        opening = drawer.opening()
        stop, failure, jammed = self._pull_faults(drawer.jammed, opening, drawer.travel)
        refused = self._refused(deposit)
        if refused is not None:
            return refused
        if stop - opening < 1e-3 and failure is None:
            return self._spend(OPENING_S)  # out already
        if jammed is not None:
            drawer.jam(jammed)
        return self._by_handle(deposit, stop, failure)

    def push_drawer(self, deposit: str) -> Outcome:
        """Push the drawer back closed from the approach, with the hand empty: free again."""
        refused = self._refused(deposit)
        if refused is not None:
            return refused
        drawer = self.scene.drawers[deposit]
        if drawer.opening() < 1e-3:
            drawer.drive(0.0)
            return self._spend(OPENING_S)
        return self._by_handle(deposit, 0.0, None)

    def place(self, deposit: str, approach: Point) -> Outcome:
        """Into a drawer: only where it is out far enough for what the hand holds
        (``deposit_closed`` otherwise: the hand stays where it is, holding it); then as into a
        tray, at spots of its inside out of the carcass."""
        drawer = self.scene.drawers.get(deposit)
        if drawer is not None and self.holding is not None and math.dist(self.robot, approach) <= 0.1:
            if not drawer.layout.takes(drawer.opening(), self._held_as.footprint):
                return self._fail("deposit_closed", OPENING_S)
            self.openings[deposit] = drawer.interior()
        return super().place(deposit, approach)

    def _free_spots(self, deposit):
        """A drawer's spots are in its inside out of the carcass; what it holds is all of it."""
        drawer = self.scene.drawers.get(deposit.name)
        if drawer is None:
            return super()._free_spots(deposit)
        self.openings[deposit.name] = drawer.exposed()
        try:
            return super()._free_spots(deposit)
        finally:
            self.openings[deposit.name] = drawer.interior()

    # ------------------------------------------------------------------ the handle
    def _by_handle(self, deposit: str, to: float, failure: str | None) -> Outcome:
        """Back off by the opening, grip the handle (the level hand, pointing into the carcass),
        take the drawer to ``to`` m out with the base, let go, stow, drive back to where the robot
        stood. ``failure`` is what to report when all that went as planned."""
        drawer = self.scene.drawers[deposit]
        layout = drawer.layout
        start = self.robot
        careful = self.scenario.robot.speed / 2
        metres, ok = self._slide_base(_out(layout, start, drawer.opening()))
        seconds = metres / careful
        if not ok:
            return self._after(deposit, start, seconds, metres, "path_blocked")
        self.robot = tuple(self.hsr.base()[:2])  # where the whole-body reach starts from
        grip = drawer.handle()
        seconds += self.hsr.turn_to(*grip[:2])
        into = (-layout.sign, 0.0) if layout.k == 0 else (0.0, -layout.sign)
        level = hand_level(math.atan2(into[1], into[0]))
        pose, err, shift = self._whole_body_reach(grip, level, grip[:2], turns=(0.0,))
        seconds, metres = seconds + abs(shift) / careful, metres + abs(shift)
        if err > REACHED:
            seconds += self._arm(STOW)
            return self._after(deposit, start, seconds, metres, "handle_unreached")
        before = (grip[0] - into[0] * BEFORE_HANDLE, grip[1] - into[1] * BEFORE_HANDLE, grip[2])
        pre, err_pre = self.hsr.reach(before, level, strict=True, turns=(0.0,))
        pre = pre if err_pre <= REACHED else pose
        seconds += self._arm(pre) + self.hsr.set_joints(pose)
        seconds += self.hsr.set_gripper(HANDLE[2] / 2)  # the fingers close on the 3 cm grip
        hauled, ok = self._haul(drawer, to)
        seconds, metres = seconds + hauled / PULL_SPEED, metres + hauled
        # let go, the hand back off the handle (the arm as it came: the base moved with the handle)
        seconds += self.hsr.set_gripper(GRIPPER_OPEN) + self.hsr.set_joints(pre) + self.hsr.set_joints(STOW)
        return self._after(deposit, start, seconds, metres, failure if ok else "path_blocked")

    def _haul(self, drawer, to: float) -> tuple[float, bool]:
        """The base backs off (or closes in) along the slide with the arm held, the drawer and
        the objects in it coming with the hand, in steps of HAUL_STEP to ``to`` m out; it stops
        where the base would run into something. Returns (m hauled, whether it got there)."""
        layout = drawer.layout
        riders = self._riders(drawer)
        base = np.asarray(self.hsr.base()[:2])
        along = np.zeros(2)
        along[layout.k] = layout.sign
        before = base_contacts(self.hsr, self._ignored())
        start = now = drawer.opening()
        steps = max(1, math.ceil(abs(to - start) / HAUL_STEP))
        for i in range(1, steps + 1):
            want = start + (to - start) * i / steps
            self._place_base(tuple(base + along * (want - start)))
            if blocked(base_contacts(self.hsr, self._ignored()), before):
                self._place_base(tuple(base + along * (now - start)))
                return abs(now - start), False
            got = drawer.drive(want)
            self._carry_riders(riders, along * (got - now))
            now = got
        for name in riders:
            self._sync(name)
        return abs(now - start), True

    def _riders(self, drawer) -> list[str]:
        """The objects resting in the drawer: inside it, their bottom on its floor and below its
        rim (not in a drawer above it in the same carcass)."""
        x0, x1, y0, y1 = drawer.interior()
        out = []
        for name, item in self.items.items():
            if item.state == "held":
                continue
            (ax, ay, az), (bx, by, _) = p.getAABB(self.bodies[name], physicsClientId=self.client)
            cx, cy = (ax + bx) / 2, (ay + by) / 2
            if x0 <= cx <= x1 and y0 <= cy <= y1 and drawer.layout.holds_height(az):
                out.append(name)
        return out

    def _carry_riders(self, riders: list[str], step) -> None:
        for name in riders:
            body = self.bodies[name]
            pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
            moved = (pos[0] + step[0], pos[1] + step[1], pos[2])
            p.resetBasePositionAndOrientation(body, moved, orn, physicsClientId=self.client)

    def _after(
        self, deposit: str, start: Point, seconds: float, metres: float, failure: str | None
    ) -> Outcome:
        """Drive back to ``start`` (carefully), and account for the whole skill."""
        careful = self.scenario.robot.speed / 2
        back, ok = self._slide_base(start)
        seconds, metres = seconds + back / careful, metres + back
        failure = failure or (None if ok else "path_blocked")
        x, y, _ = self.hsr.base()
        self.robot = start if ok else (x, y)  # the approach exactly, as the units check it
        self.odometer.distance_m += metres
        if math.dist(self.odometer.track[-1], self.robot) >= 0.1:
            self.odometer.track.append(self.robot)
        self.openings[deposit] = self.scene.drawers[deposit].interior()
        self.odometer.sim_time_s += seconds
        return Outcome(failure is None, failure, seconds, metres)

    # ------------------------------------------------------------------ the base
    def _slide_base(self, to: Point) -> tuple[float, bool]:
        """Move the base straight to ``to`` (as it stands, the arm as it is), checking its collision
        shape every SLIDE_STEP; stopped short of a contact. Returns (m moved, whether it got there)."""
        a = np.asarray(self.hsr.base()[:2])
        d = math.dist(a, to)
        if d < 1e-6:
            return 0.0, True
        before = base_contacts(self.hsr, self._ignored())
        steps = max(1, math.ceil(d / SLIDE_STEP))
        last = a
        for s in range(1, steps + 1):
            q = a + (np.asarray(to) - a) * s / steps
            self._place_base(tuple(q))
            if blocked(base_contacts(self.hsr, self._ignored()), before):
                self._place_base(tuple(last))
                return float(math.dist(a, last)), False
            last = q
        return d, True


def _out(layout, at: Point, by: float) -> Point:
    """``at`` moved ``by`` m along the drawer's slide, outwards."""
    return (at[0] + layout.sign * by, at[1]) if layout.k == 0 else (at[0], at[1] + layout.sign * by)
