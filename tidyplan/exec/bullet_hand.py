"""The HSR's arm and hand in the pybullet world: grasping, putting into a deposit's tray, putting
down on the floor. A mixin of ``BulletWorld`` (``tidyplan.exec.bullet``), kept apart because
manipulation is where the robot's reach decides what can be done: the top grasp, the side grasp
of a tall object, the whole-body reach (the base backs off or slides in a little), and where in
a tray an object goes.
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as p

from sim.motion import TOUCH, base_contacts, blocked, contacts
from sim.robot import CARRY, GRIPPER_OPEN, HAND_DOWN, RAISED, REACHED, STOW, TURNS, hand_level
from sim.room import BIN_WALL, TRAY, holder, inside, opening
from tidyplan.exec.bullet_look import RECOGNISE_S
from tidyplan.exec.symbolic import TAKE_TOLERANCE
from tidyplan.exec.world import Outcome

Point = tuple[float, float]

SETTLE_S = 1.0  # s of physics after a release
ABOVE = 0.05  # m: the hand comes down onto an object from this far above it
ROOM = 0.03  # m between an object put into a tray and what the tray holds already
# m the base may slide along the line to where the hand must go (backing off first): the whole-body
# reach of the HSR, which moves its base where the arm alone cannot keep the hand upright
SHIFTS = (0.0, -0.1, -0.2, 0.05, 0.1)
QUARTER_TURNS = (0.0, math.pi / 2, -math.pi / 2, math.pi)  # rad about the vertical
SIDE_REACH = (0.55, 0.62, 0.75)  # m from the base's centre to a tall object's centre, for a side grasp
CLEAR = 0.05  # m between the floor and the bottom of a carried object
TALL = 0.3  # m: an object taller is taken from the side (the top grasp could not put it down upright
# on a 0.4 m table: the hand pointing down reaches 0.80 m at most, measured with sim.robot.HSR.reach)


SUNK = 0.05  # m: how far into a surface's top the held object may dip and still be lifted clear
# m between a bin's rim and the hand lowering an object into it: the fingers and the wrist stay
# above the sides, which the kinematic arm would otherwise pass through
ABOVE_RIM = 0.05


class Hand:
    """Manipulation for ``BulletWorld``: ``grasp``, ``place``, ``put_down``. Uses the world's
    ``hsr``, ``client``, ``scene``, ``bodies``, ``items``, ``scenario``, ``robot``, ``holding``,
    its seeded ``rng`` and ``rates``, and its ``_place_base``, ``_ignored``, ``_settle``,
    ``_sync``, ``_spend`` and ``_fail``."""

    def grasp(self, target: Point) -> Outcome:
        """Turn to the object at ``target``, bring the hand onto it (inverse kinematics; the base
        backs off or slides in a little where the arm alone cannot), close the fingers (or the
        suction pad, for objects wider than the hand opens), attach, lift into the carrying
        posture. A tall object is taken from the side, so that it can be put down upright
        where the top grasp could not lift it high enough. ``grasp_fail`` at 1 - the take rate:
        the object slips while lifted and drops back."""
        if self.holding is not None:
            return self._fail("hand_full", 1.0)
        near = [o for o in self._placed() if math.dist((o.x, o.y), target) <= TAKE_TOLERANCE]
        if not near:
            return self._fail("not_found", RECOGNISE_S)
        item = min(near, key=lambda o: (math.dist((o.x, o.y), target), o.name))
        body = self.bodies[item.name]
        (_, _, z0), (_, _, top) = p.getAABB(body, physicsClientId=self.client)
        seconds = self.hsr.turn_to(item.x, item.y)
        start = self.robot
        grasps = self._grasps(item, z0, top)
        for grip, before, orientation, turns in grasps:
            at, err, shift = self._whole_body_reach(grip, orientation, (item.x, item.y), turns=turns)
            if err <= REACHED:
                above, err_above = self.hsr.reach(before, orientation, strict=True, turns=(0.0,))
                above = above if err_above <= REACHED else at
                break
        else:  # no grasp keeps the hand upright: the top grasp in any orientation, from here
            shift = 0.0
            grip, before, _, _ = grasps[-1]
            self._place_base(start)
            above, err_above = self.hsr.reach(before)
            at, err = self.hsr.reach(grip)
            if max(err, err_above) > REACHED:
                seconds += self.hsr.set_joints(STOW)
                return self._fail("out_of_reach", seconds)
        seconds += self._shifted(shift) + self.hsr.set_joints(above) + self.hsr.set_joints(at)
        seconds += self.hsr.set_gripper(min(GRIPPER_OPEN, item.sx / 2))
        self._attach(item.name)
        centre = p.getBasePositionAndOrientation(body, physicsClientId=self.client)[0]
        # to put it down as it stood: the hand's orientation, its centre's and the hand's heights
        # above its bottom
        hand_at, hand_orn = self.hsr.hand()
        self._held_as = (hand_orn, centre[2] - z0, hand_at[2] - z0)
        if self.rng.random() >= self.rates.take:
            seconds += self.hsr.set_joints(above)
            self._release()
            seconds += self.hsr.set_gripper(GRIPPER_OPEN) + self.hsr.set_joints(RAISED)  # the hand away first
            self._settle()
            seconds += SETTLE_S + self.hsr.set_joints(STOW)
            self._place_base(start)
            self._sync(item.name)
            return self._fail("grasp_fail", seconds)
        seconds += self.hsr.set_joints(above) + self._carry()
        self._place_base(start)
        item.state = "held"
        return self._spend(seconds)

    def grasp_distances(self, height: float) -> tuple[float, float, float]:
        """A tall object is taken from the side, which the arm reaches farther out: the hand
        level 0.55 to 0.7 m from the base's centre (measured with ``HSR.reach``, 0.1 to 0.65 m
        up; docs/world.md), so the object's centre about 0.1 m farther."""
        return SIDE_REACH if height > TALL else super().grasp_distances(height)

    def _grasps(self, item, z0: float, top: float) -> list[tuple[tuple, tuple, tuple, tuple]]:
        """(grip, pre-grip, hand orientation, turns about the vertical allowed) to try, best
        first: for a tall object the side grasp (the hand level, the pad on the face towards
        the robot, half way up, from 5 cm before it), then the top grasp (the hand pointing
        down, turned any way, 3 cm below the top, from 5 cm above)."""
        grasps = []
        if item.sz > TALL:
            d = np.subtract((item.x, item.y), self.robot)
            d = d / (np.linalg.norm(d) or 1.0)
            face = np.subtract((item.x, item.y), d * (max(item.sx, item.sy) / 2 - 0.01))
            grip = (float(face[0]), float(face[1]), z0 + item.sz / 2)
            before = (grip[0] - 0.05 * d[0], grip[1] - 0.05 * d[1], grip[2])
            grasps.append((grip, before, hand_level(math.atan2(d[1], d[0])), (0.0,)))
        grip = (item.x, item.y, top - min(0.03, item.sz / 2))
        grasps.append((grip, (grip[0], grip[1], grip[2] + ABOVE), HAND_DOWN, TURNS))
        return grasps

    def _whole_body_reach(
        self, target, orientation, towards: Point, unreached: _Unreached | None = None, **how
    ) -> tuple[dict, float, float]:
        """Joints that bring the hand (``how``: turns, carried, as ``HSR.reach`` takes them) to
        ``target`` upright, from the base where it stands or slid along the line to ``towards``
        by one of SHIFTS (backing off first) where that touches nothing: (joints, error, shift).
        The base is left at the shift that reached; at the start when none did.

        ``unreached`` (kept by a caller trying many targets at one height) rules out base poses
        farther from the target than one from which the arm did not reach."""
        start = np.asarray(self.robot)
        d = np.subtract(towards, start)
        d = d / (np.linalg.norm(d) or 1.0)
        before = base_contacts(self.hsr, self._ignored())
        for shift in SHIFTS:
            base = start + d * shift
            far = math.dist(base, target[:2])
            if unreached is not None and unreached.rules_out(far):
                continue
            self._place_base(tuple(base))
            if shift and blocked(base_contacts(self.hsr, self._ignored()), before):
                continue
            pose, err = self.hsr.reach(target, orientation, strict=True, **how)
            if err <= REACHED:
                return pose, err, shift
            if unreached is not None:
                unreached.add(far)
        self._place_base(tuple(start))
        return {}, math.inf, 0.0

    def _shifted(self, shift: float) -> float:
        """Seconds to slide the base ``shift`` m and back, carefully (half speed)."""
        return 2 * abs(shift) / (self.scenario.robot.speed / 2)

    def place(self, deposit: str, approach: Point) -> Outcome:
        """Put the held object into ``deposit`` (its tray, or the bin it is) from its approach
        pose: turn to it, reach above it, open, let it settle. ``place_fail`` at 1 - the deliver
        rate: the hand does not open and the object stays in it."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if math.dist(self.robot, approach) > 0.1:
            return self._fail("not_at_deposit", 1.0)
        d = next(d for d in self.scenario.deposits if d.name == deposit)
        seconds = self.hsr.turn_to(d.x, d.y)
        self._carry_along()
        spots, fall_onto = self._free_spots(d)
        out = self._release_at(spots, self._let_go_z(d), seconds, fault_rate=self.rates.deliver, fall_onto=fall_onto)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        if inside(opening(self.scenario, d), (item.x, item.y)):
            item.state, item.deposit = "tidied", deposit
            return out
        # it bounced off the tray or out of the bin: it lies where physics left it, for perception
        return Outcome(False, "place_missed", out.seconds, 0.0, (item.x, item.y))

    def _let_go_z(self, deposit) -> float:
        """The surface the held object is let go 1.5 cm above, in ``deposit``: a tray's top; in a
        bin, as low as the hand can take it with the hand ABOVE_RIM over the rim. A tall box let go
        above a 0.33 m bin's rim falls 0.35 m and may tip across the bin; lowered until the hand
        nears the rim, it falls 0.15 m and stands in the corner it was put in."""
        tray_top = deposit.z + 0.01
        if holder(self.scenario, deposit) is None:
            return tray_top
        hand_height = self._held_as[2]  # above the object's bottom
        return min(tray_top, max(BIN_WALL, deposit.z + ABOVE_RIM - hand_height - 0.015))

    def put_down(self, spot: Point) -> Outcome:
        """Put the held object on the floor at ``spot`` (next to the robot); ``place_fail`` at
        1 - the drop rate, or when an object already lies there."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if any(math.dist(spot, (o.x, o.y)) < 0.2 for o in self._placed()):
            return self._fail("place_fail", 8.0)
        seconds = self.hsr.turn_to(*spot)
        self._carry_along()
        out = self._release_at([spot], 0.0, seconds, fault_rate=self.rates.drop)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        return Outcome(True, None, out.seconds, 0.0, (item.x, item.y))

    def _release_at(
        self, spots: list[Point], surface_z: float, seconds: float, fault_rate: float, fall_onto=None
    ) -> Outcome:
        """Put the held object down at the first of ``spots`` where the arm can let it go (see
        ``_pose_to_let_go``), open the hand, raise it out of the way and let physics settle it."""
        name = self.holding
        item = self.items[name]
        start = self.robot
        found = self._pose_to_let_go(spots, surface_z, fall_onto)
        if found is None:
            self._place_base(start)
            return self._fail("out_of_reach", seconds + 1.0)
        pose, shift = found
        seconds += self._shifted(shift) + self.hsr.set_joints(pose)
        self._carry_along()
        if self.rng.random() >= fault_rate:
            seconds += 2.0 + self._carry()  # tried to open, and back
            self._place_base(start)
            return self._fail("place_fail", seconds)
        self._release()
        seconds += self.hsr.set_gripper(GRIPPER_OPEN) + self.hsr.set_joints(RAISED)  # the hand away first
        self._settle()
        seconds += SETTLE_S + self.hsr.set_joints(STOW)
        self._place_base(start)
        self._sync(name)
        item.state = "placed"
        self._last_released = name
        return self._spend(seconds)

    def _pose_to_let_go(
        self, spots: list[Point], surface_z: float, fall_onto: list[Point] | None = None
    ) -> tuple[dict, float] | None:
        """(arm pose, base shift) that put the held object at one of ``spots``, the base left at
        the shift; None where none will do. In this order:

        1. upright, held as it stood at the grasp (the base backing off or sliding in a little
           where the arm alone cannot), at the first of ``spots`` where it touches nothing;
           then at the first of ``fall_onto`` (at most 4; default ``spots``) held just above
           what it would be inside of (``_clear``), to fall onto it. Tried only where the arm
           holds it upright over the middle of ``spots`` at all (not on the drawer's 0.94 m top);
        2. in any orientation (a small object may tilt, the rim holds it), from where the base
           stands: at the first of ``fall_onto`` where it touches nothing, else at the first one
           held above what it would be inside of.

        Every spot is tried touching nothing before any is tried on top of what the deposit
        holds: on top of a tall box, an object topples off, out of a tray or a bin."""
        # the hand as it was at the grasp (turned about the vertical by a quarter turn or more: four
        # tries, where the IK may turn it a little more), the object's centre on the spot
        fall_onto = spots if fall_onto is None else fall_onto
        hand_orn, centre_height, _ = self._held_as
        carried = self._grip_offset[0]  # the object's centre in the hand's frame
        held = {"turns": self._square_turns(), "carried": carried}
        upright = {"strict": True, **held}
        start = self.robot

        def centre_at(at: Point) -> tuple[float, float, float]:
            return at[0], at[1], surface_z + 0.015 + centre_height  # the object's bottom 1.5 cm above

        middle = tuple(np.mean(spots, axis=0))
        if (
            len(spots) == 1
            or self._whole_body_reach(centre_at(middle), hand_orn, middle, **held)[1] <= REACHED
        ):
            reached, unreached = {}, _Unreached(beyond=math.dist(start, middle))
            for at in spots:
                pose, err, shift = self._whole_body_reach(centre_at(at), hand_orn, at, unreached, **held)
                if err > REACHED:
                    continue
                if self._lift_to_clear(pose) == 0.0:
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
            if err <= REACHED and self._lift_to_clear(pose) == 0.0:
                return pose, 0.0
        pose, err = self.hsr.reach(centre_at(fall_onto[0]), hand_orn, **tilted)
        pose = self._clear(pose, centre_at(fall_onto[0]), hand_orn, tilted) if err <= REACHED else None
        return None if pose is None else (pose, 0.0)

    def _square_turns(self) -> tuple[float, ...]:
        """Turns of the hand about the vertical to try, best first: the quarter turns that put the
        held object's sides along the room's axes, a tray's and a bin's too (a box turned 45
        degrees takes 0.27 m of a 0.38 m tray, square 0.19 m). The solver keeps the hand upright,
        not its turn exactly: each pose is checked for contact as it comes out."""
        _, orn = p.getBasePositionAndOrientation(self.bodies[self.holding], physicsClientId=self.client)
        m = p.getMatrixFromQuaternion(orn)
        yaw = math.atan2(m[3], m[0])
        off = (yaw + math.pi / 4) % (math.pi / 2) - math.pi / 4  # its turn from square, in [-45, 45) deg
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

    def _lift_to_clear(self, pose: dict) -> float | None:
        """How far the held object, with the arm at ``pose``, must go up to be inside nothing:
        0.0 where it is clear, None where a wall or a piece of furniture is in the way beside it
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
        return max((top + 0.015 - bottom for top in tops.values()), default=0.0)

    def _free_spots(self, deposit) -> tuple[list[Point], list[Point]]:
        """Where in the deposit the held object may go if it touches nothing there, best first,
        and where it may be let fall onto what the deposit holds. Spots of two 5 x 5 grids of
        the opening (a tray's, a bin's): one that keeps the circle around the object (the hand
        may turn it) inside the rim, one for its half-width, nearer the rim, where its square
        footprint fits though its circle does not. Those with 3 cm of room from what the deposit
        holds already come first, the farthest from the middle first (a corner before a side,
        the farther from the robot first: the deposit is filled from the back, and what comes
        next, a tall box say, finds room), then the others, the roomiest first. Only the first
        grid's spots are for letting it fall: by the rim, it would fall over it. The robot sees
        the tray from its approach pose."""
        item = self.items[self.holding]
        half = math.hypot(item.sx, item.sy) / 2  # it may stand turned any way about the vertical
        x0, x1, y0, y1 = held_in = opening(self.scenario, deposit)
        held = self.bodies[self.holding]
        others = []
        for name, body in self.bodies.items():
            o = self.items[name]
            if body != held and inside(held_in, (o.x, o.y)):
                (ax, ay, _), (bx, by, _) = p.getAABB(body, physicsClientId=self.client)
                others.append((ax, ay, bx, by))

        def room_at(q: Point) -> float:
            gaps = [
                max(ax - (q[0] + half), q[0] - half - bx, ay - (q[1] + half), q[1] - half - by)
                for ax, ay, bx, by in others
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

        safe = grid(half + 0.01)
        near_rim = grid(min(item.sx, item.sy) / 2 + 0.005)
        return sorted(set(safe + near_rim), key=lambda q: (rank(q), q)), sorted(safe, key=rank)

    def _attach(self, name: str) -> None:
        body = self.bodies[name]
        hand_pos, hand_orn = self.hsr.hand()
        obj_pos, obj_orn = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
        inv_pos, inv_orn = p.invertTransform(hand_pos, hand_orn)
        self._grip_offset = p.multiplyTransforms(inv_pos, inv_orn, obj_pos, obj_orn)
        self._grip = p.createConstraint(
            self.hsr.body,
            self.hsr.grasp_link,
            body,
            -1,
            p.JOINT_FIXED,
            (0, 0, 0),
            self._grip_offset[0],
            (0, 0, 0),
            self._grip_offset[1],
            physicsClientId=self.client,
        )
        self.holding = name

    def _release(self) -> None:
        if self._grip is not None:
            p.removeConstraint(self._grip, physicsClientId=self.client)
        self._grip, self.holding = None, None

    def _carry(self) -> float:
        """The carrying posture, the arm lifted as far as a long object needs to clear the floor."""
        seconds = self.hsr.set_joints(CARRY)
        self._carry_along()
        if self.holding is not None:
            bottom = p.getAABB(self.bodies[self.holding], physicsClientId=self.client)[0][2]
            if bottom < CLEAR:
                seconds = self.hsr.set_joints(
                    {**CARRY, "arm_lift_joint": CARRY["arm_lift_joint"] + CLEAR - bottom}
                )
                self._carry_along()
        return seconds

    def _carry_along(self) -> None:
        """A kinematic motion does not step physics: the held object is put where the hand has it."""
        if self.holding is None:
            return
        hand_pos, hand_orn = self.hsr.hand()
        pos, orn = p.multiplyTransforms(hand_pos, hand_orn, *self._grip_offset)
        p.resetBasePositionAndOrientation(self.bodies[self.holding], pos, orn, physicsClientId=self.client)
        item = self.items[self.holding]
        item.x, item.y = pos[0], pos[1]


class _Unreached:
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
