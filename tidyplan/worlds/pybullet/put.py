"""Where the HSR's hand lets go of what it holds in a deposit: the spots of a tray or a bin
from the back, each checked for contact, the height a bin is filled from, and the arm poses
that put the object there upright (or tilted, where upright is out of reach). A mixin of
``Hand`` (``tidyplan.worlds.pybullet.hand``), kept apart because it is a search of its own: spots
times base shifts times the hand's turns, each solved and checked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import pybullet as p

from sim.motion import TOUCH, contacts
from sim.robot import REACHED
from sim.room import BIN_WALL, CONTAINER_WALL, TRAY, holder, inside

Point = tuple[float, float]

ROOM = 0.03  # m between an object put into a tray and what the tray holds already
QUARTER_TURNS = (0.0, math.pi / 2, -math.pi / 2, math.pi)  # rad about the vertical
SUNK = 0.05  # m: how far into a surface's top the held object may dip and still be lifted clear
# m between a bin's rim and the hand lowering an object into it: the fingers and the wrist stay
# above the sides, which the kinematic arm would otherwise pass through
ABOVE_RIM = 0.05
# m between the rim and an object's side at the spots nearest it: the hand keeps an object square
# within a few degrees, and a 0.19 m box turned 3 degrees is 1 cm wider
RIM_GAP = 0.015


class HeldAs(NamedTuple):
    """How the hand holds what it holds, to put it down so: the hand's orientation at the let-go
    (as it closed on the object, or turned to stand a lying box up), the object's centre and the
    hand above the object's bottom (m), its sides' heading (rad) and its sides along the floor
    (m), both as it will stand."""

    hand: tuple[float, float, float, float]
    centre_height: float
    hand_height: float
    heading: float
    footprint: tuple[float, float]


def held_as(hand_at, hand_orn, centre, orientation, size) -> HeldAs:
    """``HeldAs`` for a box of ``size`` (its own axes) at ``centre`` turned by ``orientation``,
    the hand at ``hand_at`` turned by ``hand_orn``, standing as it stands now."""
    m = p.getMatrixFromQuaternion(orientation)
    up = max(range(3), key=lambda k: abs(m[6 + k]))  # the box's axis nearest the vertical
    half_height = sum(abs(m[6 + k]) * size[k] for k in range(3)) / 2
    a, b = (size[k] for k in range(3) if k != up)
    return HeldAs(
        tuple(hand_orn),
        half_height,
        float(half_height + hand_at[2] - centre[2]),
        heading(orientation),
        (a, b),
    )


def stood_up(hand_at, hand_orn, centre, orientation, size, down=None) -> HeldAs | None:
    """``HeldAs`` with a lying box stood on its end: the hand turned a quarter about the level
    line across the box's long side (a top grasp on a lying crate becomes the side grasp of the
    standing crate); with ``down`` (a direction in the box's own frame: an orientation item's
    axis) the turn that puts that end down. None where the long side (or ``down``) is not lying."""
    m = np.reshape(p.getMatrixFromQuaternion(orientation), (3, 3))
    if down is None:
        k = max(range(3), key=lambda i: size[i])
        u = m[:, k]  # the long side's direction, turned up
    else:
        u = -(m @ np.asarray(down, dtype=float))  # the end that goes down, turned down
    if abs(u[2]) > 0.3:
        return None
    across = np.cross((0.0, 0.0, 1.0), u)
    turn = p.getQuaternionFromAxisAngle(across / np.linalg.norm(across), -math.pi / 2)  # u to up
    hand_pos = p.multiplyTransforms((0, 0, 0), turn, np.subtract(hand_at, centre), (0, 0, 0, 1))[0]
    stood = p.multiplyTransforms((0, 0, 0), turn, (0, 0, 0), orientation)[1]
    hand = p.multiplyTransforms((0, 0, 0), turn, (0, 0, 0), hand_orn)[1]
    return held_as(np.add(centre, hand_pos), hand, centre, stood, size)


def fits(footprint: tuple[float, float], held_in: tuple[float, float, float, float]) -> bool:
    """Does a box of ``footprint``, turned square, fit inside ``held_in`` (x0, x1, y0, y1)?"""
    x0, x1, y0, y1 = held_in
    a, b = sorted(footprint)
    c, d = sorted((x1 - x0, y1 - y0))
    return a < c and b < d


def heading(orientation) -> float:
    """The heading (rad) of a box's sides: of one of its axes other than the one nearest the
    vertical (a box on its side turns about another axis than one standing up)."""
    m = p.getMatrixFromQuaternion(orientation)
    up = max(range(3), key=lambda k: abs(m[6 + k]))
    k = 0 if up else 1
    return math.atan2(m[3 + k], m[k])


@dataclass(frozen=True)
class Spots:
    """Where in a deposit the held object may go (``PutIn._free_spots``): where it may be let go
    if it lands clear, best first; where it may be let fall onto what the deposit holds, best
    first; the footprints (x0, y0, x1, y1, top) of what the deposit holds."""

    clear: list[Point]
    fall_onto: list[Point]
    holds: list[tuple[float, float, float, float, float]] = field(default_factory=list)


class PutIn:
    """The search for where and how to let go, for ``Hand``: ``_free_spots``, ``_let_go_z``,
    ``_pose_to_let_go``. Uses the world's ``hsr``, ``client``, ``scene``, ``bodies``, ``items``,
    ``scenario``, ``openings``, ``robot``, ``holding`` and the hand's ``_held_as``,
    ``_grip_offset``, ``_whole_body_reach``, ``_place_base`` and ``_carry_along``."""

    def _let_go_z(self, deposit) -> float:
        """The surface the held object is let go 1.5 cm above, in ``deposit``: a tray's top; in a
        bin, as low as the hand can take it with the hand ABOVE_RIM over the rim. A tall box let go
        above a 0.33 m bin's rim falls 0.35 m and may tip across the bin; lowered until the hand
        nears the rim, it falls 0.15 m and stands in the corner it was put in."""
        tray_top = deposit.z + 0.01
        hand_height = self._held_as.hand_height  # above the object's bottom
        if deposit.container is not None:  # an open box on the surface: its rim `height` above it
            floor, rim = deposit.z + CONTAINER_WALL, deposit.z + deposit.container[2]
            return max(floor, rim + ABOVE_RIM - hand_height - 0.015)
        if holder(self.scenario, deposit) is None:
            return tray_top
        return min(tray_top, max(BIN_WALL, deposit.z + ABOVE_RIM - hand_height - 0.015))

    def _pose_to_let_go(self, spots: Spots, surface_z: float) -> tuple[dict, float] | None:
        """(arm pose, base shift) that put the held object at one of ``spots``, the base left at
        the shift; None where none will do. In this order:

        1. upright, held as ``_held_as`` says (as it stood at the grasp, or stood on its end;
           the base backing off or sliding in a little where the arm alone cannot), at the
           first of ``spots.clear`` where it lands clear
           (``_lands_clear``: it touches nothing and nothing the deposit holds is under it);
           then at the first of ``spots.fall_onto`` (at most 4) held just above what it would
           be inside of (``_clear``), to fall onto it. Tried only where the arm holds it upright
           over the middle of the spots at all (not on the drawer's 0.94 m top);
        2. in any orientation (a small object may tilt, the rim holds it), from where the base
           stands: at the first of ``spots.fall_onto`` where it lands clear, else at the first
           one held above what it would be inside of.

        Every spot is tried landing clear before any is tried on top of what the deposit holds:
        on top of a tall box, an object topples off, out of a tray or a bin."""
        # the hand as it holds the object (turned about the vertical by a quarter turn or more:
        # four tries, where the IK may turn it a little more), the object's centre on the spot
        fall_onto, holds = spots.fall_onto, spots.holds
        hand_orn, centre_height = self._held_as.hand, self._held_as.centre_height
        carried = self._grip_offset[0]  # the object's centre in the hand's frame
        held = {"turns": self._square_turns(), "carried": carried}
        upright = {"strict": True, **held}
        start = self.robot

        def centre_at(at: Point) -> tuple[float, float, float]:
            return at[0], at[1], surface_z + 0.015 + centre_height  # the object's bottom 1.5 cm above

        middle = tuple(np.mean(spots.clear, axis=0))
        err, shift = 0.0, 0.0
        if len(spots.clear) > 1:
            _, err, shift = self._whole_body_reach(centre_at(middle), hand_orn, middle, **held)
        if err <= REACHED:
            # a failure farther than the middle was reached from is for being too far; nearer, a
            # level hand (a side grasp, 0.55 m out at least) may be too close
            reached, unreached = {}, Unreached(beyond=math.dist(start, middle) - shift)
            for at in spots.clear:
                pose, err, shift = self._whole_body_reach(centre_at(at), hand_orn, at, unreached, **held)
                if err > REACHED:
                    continue
                if self._lands_clear(pose, holds):
                    return pose, shift
                reached[at] = (pose, shift)
            for at in [q for q in fall_onto if q in reached][:4]:
                pose, shift = reached[at]
                d = np.subtract(at, start)
                self._place_base(tuple(np.asarray(start) + d / (np.linalg.norm(d) or 1.0) * shift))
                pose = self._clear(pose, centre_at(at), hand_orn, upright)
                if pose is not None:
                    return pose, shift
        self._place_base(start)  # upright out of reach: any orientation
        tilted = {"carried": carried}
        for at in fall_onto:
            pose, err = self.hsr.reach(centre_at(at), hand_orn, **tilted)
            if err <= REACHED and self._lands_clear(pose, holds):
                return pose, 0.0
        pose, err = self.hsr.reach(centre_at(fall_onto[0]), hand_orn, **tilted)
        pose = self._clear(pose, centre_at(fall_onto[0]), hand_orn, tilted) if err <= REACHED else None
        return None if pose is None else (pose, 0.0)

    def _square_turns(self) -> tuple[float, ...]:
        """Turns of the hand about the vertical, from its orientation at the grasp, to try, best
        first: the quarter turns that put the held object's sides along the room's axes, a
        tray's and a bin's too (a box turned 45 degrees takes 0.27 m of a 0.38 m tray, square
        0.19 m). Reckoned from the object's heading at the grasp, as the turns are from the
        hand's then. The solver keeps the hand upright, not its turn exactly: each pose is
        checked for contact as it comes out."""
        off = (self._held_as.heading + math.pi / 4) % (math.pi / 2) - math.pi / 4  # in [-45, 45) deg
        return tuple(t - off for t in QUARTER_TURNS)

    def _clear(self, pose: dict, centre: tuple, orientation, how: dict) -> dict | None:
        """``pose`` if the held object there is inside nothing (a graze aside): let go inside
        another object or a tray's rim, physics would throw both apart, over a wall too. Else
        the pose (``how``: as ``HSR.reach`` takes it) that holds it just above what it would be
        inside of, so that it falls onto them (an object put on top of another one topples
        both); None where that is out of reach, or a wall or a piece of furniture is in the way."""
        lift = self._lift_to_clear(pose)
        if lift is None or lift == 0.0:
            return pose if lift == 0.0 else None
        raised, err = self.hsr.reach((centre[0], centre[1], centre[2] + lift), orientation, **how)
        return raised if err <= REACHED and self._lift_to_clear(raised) == 0.0 else None

    def _lands_clear(self, pose: dict, holds) -> bool:
        """Does the held object, let go with the arm at ``pose``, touch nothing and have none of
        ``holds`` (footprints) under it? Let go over what a bin holds, 0.2 m above it, it falls
        onto it and may bounce over the rim. The arm is left as it was."""
        if self._lift_to_clear(pose) != 0.0:
            return False
        saved = {name: self.hsr.q(name) for name in pose}
        self.hsr.set_joints(pose)
        self._carry_along()
        (ax, ay, _), (bx, by, _) = p.getAABB(self.bodies[self.holding], physicsClientId=self.client)
        self.hsr.set_joints(saved)
        self._carry_along()
        return not any(ax < x1 and x0 < bx and ay < y1 and y0 < by for x0, y0, x1, y1, _ in holds)

    def _lift_to_clear(self, pose: dict) -> float | None:
        """How far the held object, with the arm at ``pose``, must go up to be inside nothing (the
        floor too): 0.0 where it is clear, None where a wall or a piece of furniture is in the way beside it
        (up is no way out of that; out of a surface it dipped into by SUNK at most, it is). The
        arm is left as it was."""
        saved = {name: self.hsr.q(name) for name in pose}
        self.hsr.set_joints(pose)
        self._carry_along()
        held = self.bodies[self.holding]
        bottom = p.getAABB(held, physicsClientId=self.client)[0][2]
        touching = contacts(self.client, held, [self.hsr.body, self.scene.floor])
        sunk_into = [b for b, d in touching.items() if d > TOUCH]
        self.hsr.set_joints(saved)
        self._carry_along()
        tops = {b: p.getAABB(b, physicsClientId=self.client)[1][2] for b in sunk_into}
        for b, top in tops.items():
            loose = b in self.bodies.values() or b in self.scene.deposits.values()
            # a wall or furniture beside the object is in the way; one whose top the object only
            # dips into (the IK a few cm short at the drawer's 0.94 m) is left by going up
            if not loose and top - bottom > SUNK:
                return None
        if bottom < -TOUCH:  # a tilted box's corner in the floor: physics would throw it up
            tops[self.scene.floor] = 0.0
        return max((top + 0.015 - bottom for top in tops.values()), default=0.0)

    def _free_spots(self, deposit) -> Spots:
        """Where in the deposit the held object may go if it lands clear there, best first,
        and where it may be let fall onto what the deposit holds, onto the lowest of it first.
        Spots of two 5 x 5 grids of
        the opening (a tray's, a bin's): one that keeps the circle around the object (the hand
        may turn it) inside the rim, one for its half-width, nearer the rim, where its square
        footprint fits though its circle does not. Those with 3 cm of room from what the deposit
        holds already come first, the farthest from the middle first (a corner before a side,
        the farther from the robot first: the deposit is filled from the back, and what comes
        next, a tall box say, finds room), then the others, the roomiest first. Only the first
        grid's spots are for letting it fall, onto the lowest first: by the rim, or from a tall
        box's top, it would fall over the rim. The robot sees the tray from its approach pose."""
        sx, sy = self._held_as.footprint
        half = math.hypot(sx, sy) / 2  # it may stand turned any way about the vertical
        x0, x1, y0, y1 = held_in = self.openings[deposit.name]
        held = self.bodies[self.holding]
        others = []
        for name, body in self.bodies.items():
            o = self.items[name]
            if body != held and inside(held_in, (o.x, o.y)):
                (ax, ay, _), (bx, by, top) = p.getAABB(body, physicsClientId=self.client)
                others.append((ax, ay, bx, by, top))

        def room_at(q: Point) -> float:
            gaps = [
                max(ax - (q[0] + half), q[0] - half - bx, ay - (q[1] + half), q[1] - half - by)
                for ax, ay, bx, by, _ in others
            ]
            return round(min(gaps, default=TRAY), 3)

        middle = ((x0 + x1) / 2, (y0 + y1) / 2)

        def rank(q: Point) -> tuple:
            # filled from the back, the corners first: what is put in next (a tall box) finds the
            # middle free, and the side nearest the robot, the easiest to reach, is left for last
            return (
                -min(room_at(q), ROOM),
                -round(math.dist(q, middle), 3),
                -round(math.dist(q, self.robot), 3),
            )

        def grid(margin: float) -> list[Point]:  # its centre, where the opening is too small
            xs = np.linspace(*_within(x0, x1, margin), 5)
            ys = np.linspace(*_within(y0, y1, margin), 5)
            return [(round(float(x), 4), round(float(y), 4)) for x in xs for y in ys]

        def under(q: Point) -> float:  # the top of the highest of what it would fall onto at q
            tops = [
                top
                for ax, ay, bx, by, top in others
                if ax < q[0] + half and q[0] - half < bx and ay < q[1] + half and q[1] - half < by
            ]
            return round(max(tops, default=0.0), 2)

        safe = grid(half + 0.01)
        near_rim = grid(min(sx, sy) / 2 + RIM_GAP)
        clear = sorted(set(safe + near_rim), key=lambda q: (rank(q), q))
        return Spots(clear, sorted(safe, key=lambda q: (under(q), rank(q))), others)


class Unreached:
    """Where the arm did not reach, for many targets at one height: a base pose farther from its
    target than one that failed is not tried. The base turns in place for the arm, so the reach
    at a height is a matter of distance; only failures beyond ``beyond`` (a deposit's middle,
    which its approach pose is made to reach) count, as a target too close can fail too. It
    saves most of the solver's work on a deposit's far side: a put onto the drawer's 0.94 m top
    that tried 50 spots took 251 solves, 19 s."""

    def __init__(self, beyond: float) -> None:
        self.beyond, self.nearest = beyond, math.inf

    def rules_out(self, far: float) -> bool:
        return far >= self.nearest - 1e-3

    def add(self, far: float) -> None:
        if far > self.beyond:
            self.nearest = min(self.nearest, far)


def _within(lo: float, hi: float, margin: float) -> tuple[float, float]:
    """The range [lo, hi] narrowed by ``margin`` at each end; its middle where it is too short."""
    if hi - lo < 2 * margin:
        return (lo + hi) / 2, (lo + hi) / 2
    return lo + margin, hi - margin
