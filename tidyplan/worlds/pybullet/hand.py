"""The HSR's arm and hand in the pybullet world: grasping, putting into a deposit's tray, putting
down on the floor. A mixin of ``BulletWorld`` (``tidyplan.worlds.pybullet.world``), kept apart because
manipulation is where the robot's reach decides what can be done: the top grasp, the side grasp
of a tall object, the whole-body reach (the base backs off or slides in a little). Where in a
deposit an object goes is ``tidyplan.worlds.pybullet.put``.
"""

from __future__ import annotations

import math

import numpy as np
import pybullet as p

from sim.motion import base_contacts, blocked
from sim.robot import CARRY, GRIPPER_OPEN, HAND_DOWN, RAISED, REACHED, STOW, TURNS, hand_level
from sim.room import holder, inside
from sim.scenario.model import ORIENTATION
from tidyplan.worlds.base import TAKE_TOLERANCE, Outcome
from tidyplan.worlds.pybullet.look import DRIVING_HEAD, RECOGNISE_S
from tidyplan.worlds.pybullet.put import PutIn, Spots, Unreached, fits, held_as, stood_up

Point = tuple[float, float]

SETTLE_S = 1.0  # s of physics after a release
PILED = 0.03  # m: an object whose bottom is this far above a tray's surface lies on something
ABOVE = 0.05  # m: the hand comes down onto an object from this far above it
# m the base may slide along the line to where the hand must go (backing off first): the whole-body
# reach of the HSR, which moves its base where the arm alone cannot keep the hand upright
SHIFTS = (0.0, -0.1, -0.2, 0.05, 0.1)
SIDE_REACH = (0.55, 0.62, 0.75)  # m from the base's centre to a tall object's centre, for a side grasp
CLEAR = 0.05  # m between the floor and the bottom of a carried object
TALL = 0.3  # m: an object taller is taken from the side (the top grasp could not put it down upright
# on a 0.4 m table: the hand pointing down reaches 0.80 m at most, measured with sim.robot.HSR.reach)


class Hand(PutIn):
    """Manipulation for ``BulletWorld``: ``grasp``, ``place``, ``put_down``. Uses the world's
    ``hsr``, ``client``, ``scene``, ``bodies``, ``items``, ``scenario``, ``openings``, ``robot``,
    ``holding``, its seeded ``rng`` and ``rates``, and its ``_place_base``, ``_ignored``,
    ``_settle``, ``_sync``, ``_spend`` and ``_fail``."""

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
                seconds += self._arm(STOW)
                return self._fail("out_of_reach", seconds)
        seconds += self._shifted(shift) + self._arm(above) + self.hsr.set_joints(at)
        seconds += self.hsr.set_gripper(min(GRIPPER_OPEN, item.sx / 2))
        self._attach(item.name)
        # to put it down as it stands, or stood on its end where it lies too long for a deposit
        hand = self.hsr.hand()
        pose = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
        size = next((i.sx, i.sy, i.sz) for i in self.scenario.items if i.name == item.name)
        self._held_as, self._stood_up_as = held_as(*hand, *pose, size), stood_up(*hand, *pose, size)
        axis = None if item.orientation is None else item.orientation.axis
        self._stood_down_as = None if axis is None else stood_up(*hand, *pose, size, down=axis)
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
        self, target, orientation, towards: Point, unreached: Unreached | None = None, **how
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
        held_in = self.openings[deposit]
        if d.category == ORIENTATION and self._stood_down_as is not None:
            # an orientation item goes in standing, its down end first: the hand turned so
            self._held_as = self._stood_down_as
        elif not fits(self._held_as.footprint, held_in):
            # a tall box that fell over, too long to lie in the deposit (a 0.45 m crate across a
            # 0.35 m bin, a lid that what comes next bounces off): stood on its end in the hand
            stood = self._stood_up_as
            if stood is not None and fits(stood.footprint, held_in):
                self._held_as = stood
        out = self._release_at(self._free_spots(d), self._let_go_z(d), seconds, fault_rate=self.rates.deliver)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        if inside(held_in, (item.x, item.y)) and not self._off_tray(item.name, d):
            item.state, item.deposit = "tidied", deposit
            self._judge_stance(item.name)
            return out
        # it bounced off the tray or out of the bin: it lies where physics left it, for perception
        return Outcome(False, "place_missed", out.seconds, 0.0, (item.x, item.y))

    def _off_tray(self, name: str, deposit) -> str | None:
        """The rulebook's tray rule: an object on a tray that touches the table, or lies piled on
        another object, is not deposited. Why it is not (None where it is, or no tray)."""
        if deposit.drawer or deposit.container or holder(self.scenario, deposit) is not None:
            return None  # a drawer, a container, a bin: any position inside counts
        body = self.bodies[name]
        bottom = p.getAABB(body, physicsClientId=self.client)[0][2]
        for piece in self.scene.furniture.values():
            if p.getContactPoints(body, piece, physicsClientId=self.client):
                return "touches the table"
        for other, b in self.bodies.items():
            on_it = bottom > deposit.z + PILED
            if other != name and on_it and p.getContactPoints(body, b, physicsClientId=self.client):
                return f"piled on {other}"
        return None

    def put_down(self, spot: Point) -> Outcome:
        """Put the held object on the floor at ``spot`` (next to the robot); ``place_fail`` at
        1 - the drop rate, or when an object already lies there."""
        if self.holding is None:
            return self._fail("hand_empty", 1.0)
        if any(math.dist(spot, (o.x, o.y)) < 0.2 for o in self._placed()):
            return self._fail("place_fail", 8.0)
        seconds = self.hsr.turn_to(*spot)
        self._carry_along()
        out = self._release_at(Spots([spot], [spot]), 0.0, seconds, fault_rate=self.rates.drop)
        if not out.ok:
            return out
        item = self.items[self._last_released]
        return Outcome(True, None, out.seconds, 0.0, (item.x, item.y))

    def _release_at(self, spots: Spots, surface_z: float, seconds: float, fault_rate: float) -> Outcome:
        """Put the held object down at the first of ``spots`` where the arm can let it go (see
        ``_pose_to_let_go``), open the hand, raise it out of the way and let physics settle it."""
        name = self.holding
        item = self.items[name]
        start = self.robot
        found = self._pose_to_let_go(spots, surface_z)
        if found is None:
            self._place_base(start)
            return self._fail("out_of_reach", seconds + 1.0)
        pose, shift = found
        seconds += self._shifted(shift) + self._arm(pose)
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

    def _arm(self, joints: dict[str, float]) -> float:
        """The arm's first motion of a grasp, a put or a pull: ``joints``, and the head back in its
        driving posture and the torso where the arm wants it, all at once (a close look before
        left the head on its place and the torso up); the seconds the slowest joint takes."""
        if "arm_lift_joint" in joints:
            self._lift_after_look = None
        return self.hsr.set_joints({**DRIVING_HEAD, **joints})

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
